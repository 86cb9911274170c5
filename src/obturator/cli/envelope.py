"""``obturator trajectory`` and ``obturator envelope``: the obturator along the flight.

Usage::

    obturator trajectory [--mach X] [--altitude-m X] [--elevation-deg X]
        [design / projectile / solver options] [--figure FILE.png] [--out FILE.nc] [--json]

    obturator envelope --mach SPEC --altitude-m SPEC [--temperature-offset-k SPEC]
        [--requirement S] [--area-ratio X] [design / projectile / solver options]
        [--config FILE.toml] [--workers N] [--scheduler ADDRESS] [--out FILE.nc]
        [--restart] [--figure FILE.png] [--no-progress] [--json]

SPEC is ``START:STOP:COUNT`` or a list ``a,b,c`` (as for ``sweep``). Values are
SI or quantities with units (``"1 km"``, ``"115000 rpm"``). Every t_cr is
computed with the thesis's constant muzzle load and with the
trajectory-coupled load, each with its convergence status (status 2 when a
refined rerun moves it by more than 1e-3). The envelope resumes after an
interruption from ``FILE.nc.partial.jsonl``.

Config file (``--config``): the sections of :mod:`obturator.io` that apply
(``mu_s``, ``theta0``, ``torque_model``, ``t_max``, ``[ball]``, ``[gap]``,
``[flight] bore_radius``, ``[solver]``) plus::

    [projectile]
    mass = "0.141 kg"
    roll_damping = -0.012
    drag = "tubular-closed"        # or "tubular-open" or a CSV file (mach,cd)

    [launch]
    elevation = "0 deg"
    spin_rate = "12042 rad/s"      # fixes the muzzle spin (default: twist law)
    twist = "0.5327 m"
    segment = "2 ms"
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import replace
from typing import Any

from ..errors import check_range
from ..io import SOLVER_KEYS, load_config
from ..params import PARAMS, Range
from ..units import parse_quantity
from . import _json
from ._args import add_execution_flags, axis_of, quantity_of, solver_options
from ._kinds import Axis, InputFile, NameOrFile, OutputFile, Quantity

__all__ = [
    "register",
    "add_model_arguments",
    "add_execution_arguments",
    "model_from_args",
    "runner_from_args",
    "quantity",
    "MACH_AXIS",
    "REQUIREMENT",
    "FIGURE",
    "MIN_SEGMENT",
]

#: Config fields of the flight-trajectory commands (obturator.io.CONFIG_SCHEMA):
#: the design, the projectile, the launch and the solver; a launch point (mach,
#: altitude) only where the command has one (trajectory, sensitivity).
_FLIGHT_CONFIG = (
    "mu_s",
    "theta0_deg",
    "torque_model",
    "t_max",
    "ball_radius",
    "hole_radius",
    "density",
    "gap",
    "viscosity",
    "bore_radius",
    "spin_rate",
    "projectile_mass",
    "roll_damping",
    "drag",
    "elevation_deg",
    "launch_spin_rate",
    "twist",
    "segment",
    *SOLVER_KEYS,
)
_POINT_CONFIG = ("mach", "altitude_m")
#: Built-in drag curves (obturator.envelope.drag.DRAG_MODELS; not imported here:
#: start-up time).
_DRAG_CURVES = ("tubular-closed", "tubular-open")

# design flags: dest -> help (unit and range from obturator.params)
_DESIGN_FLAGS = {
    "mu_s": "sliding friction coefficient mu_s (Table 1: 0.35)",
    "theta0_deg": "initial nutation theta_0 [deg] (87.25)",
    "gap": "ball-socket gap h [m] (5.08e-5)",
    "hole_radius": "ball hole radius r_s [m] (4.72e-3)",
    "ball_radius": "ball radius R_s [m] (7.899e-3)",
    "density": "ball density [kg/m^3] (7669.6)",
    "bore_radius": "bore radius r_p [m] (4.72e-3)",
    "viscosity": "gap fluid viscosity [Pa s] (1.917e-5)",
}
_POSITIVE = Range(0.0, math.inf, True, True)
#: Launch Mach: supersonic (the bow shock of Eq. 1) up to 10 (the drag curves' end).
LAUNCH_MACH = Quantity("", Range(1.0, 10.0, True, False), "3")
#: Off-standard temperature [K]: +-100 K covers every climate the 1976 atmosphere models.
TEMPERATURE_OFFSET = Quantity("K", Range(-100.0, 100.0), "0 K")
#: Shortest coupled-load segment [s]: t_max / segment segments are integrated and
#: recorded, so 10 us keeps the default 1 s flight at 1e5 segments (the load changes
#: on the trajectory's time scale, milliseconds, far above it).
MIN_SEGMENT = 1e-5


#: A grid of launch Mach numbers (supersonic, up to 10).
MACH_AXIS = Axis("", LAUNCH_MACH.range, "3")
#: A t_cr requirement [s].
REQUIREMENT = Quantity("s", _POSITIVE, "0.1 s")
#: A figure file (formats matplotlib writes).
FIGURE = OutputFile(figure=True, example="figure.png")


def quantity(field: str, value: Any, unit: str) -> float:
    """A CLI value (number or quantity string) in `unit`."""
    return parse_quantity(field, value, unit)


def add_model_arguments(p: argparse.ArgumentParser, *, launch_point: bool) -> None:
    """Design, projectile, launch and solver flags shared by the envelope commands."""
    g = p.add_argument_group("design (Table 1 defaults)")
    for dest, text in _DESIGN_FLAGS.items():
        g.add_argument(
            "--" + dest.replace("_", "-"),
            dest=dest,
            metavar="X",
            type=_design_kind(dest),
            help=text,
        )
    g.add_argument("--torque-model", choices=("thesis", "coulomb"), default=None)
    f = p.add_argument_group("flight")
    if launch_point:
        f.add_argument(
            "--mach", metavar="X", type=LAUNCH_MACH, help="muzzle Mach number (default 3)"
        )
        f.add_argument(
            "--altitude-m",
            metavar="X",
            type=quantity_of("altitude_m"),
            help="launch altitude [m] (default 0)",
        )
        f.add_argument(
            "--temperature-offset-k",
            metavar="X",
            type=TEMPERATURE_OFFSET,
            help="off-standard temperature [K] (default 0)",
        )
    f.add_argument(
        "--elevation-deg",
        metavar="X",
        type=Quantity("deg", Range(-90.0, 90.0), "0 deg"),
        help="elevation angle [deg] (default 0)",
    )
    f.add_argument(
        "--spin-rate",
        metavar="X",
        type=quantity_of("spin_rate"),
        help="muzzle spin [rad/s]; default: rifling twist, 2 pi V_0 / twist "
        "(12042 rad/s at Table 1's Mach 3, sea level)",
    )
    f.add_argument(
        "--twist",
        metavar="X",
        type=Quantity("m", _POSITIVE, "0.5 m"),
        help="rifling twist [m per turn] (default 0.5327)",
    )
    f.add_argument(
        "--drag",
        "--cd-table",
        dest="drag",
        metavar="NAME|FILE.csv",
        type=NameOrFile(_DRAG_CURVES, "tubular-open"),
        help="drag curve: tubular-closed (default), tubular-open, or a CSV with columns mach,cd",
    )
    f.add_argument(
        "--roll-damping",
        metavar="X",
        type=Quantity("", Range(-10.0, 10.0), "-0.012"),
        help="roll-damping coefficient C_lp (-0.012)",
    )
    f.add_argument(
        "--projectile-mass",
        metavar="X",
        type=Quantity("kg", _POSITIVE, "0.141 kg"),
        help="projectile mass [kg] (0.141)",
    )
    s = p.add_argument_group("solver")
    s.add_argument(
        "--load",
        choices=("coupled", "constant"),
        default=None,
        help="trajectory-coupled load (default) or the thesis's constant muzzle load "
        "(the envelope always computes both)",
    )
    s.add_argument(
        "--rtol", metavar="X", type=quantity_of("rtol"), help="relative tolerance (default 1e-8)"
    )
    s.add_argument(
        "--atol", metavar="X", type=quantity_of("atol"), help="absolute tolerance (default 1e-10)"
    )
    s.add_argument(
        "--segment",
        metavar="S",
        type=Quantity("s", Range(MIN_SEGMENT, 0.1), "2 ms"),
        help=f"segment of the coupled load [s] (2e-3; {MIN_SEGMENT:g} to 0.1)",
    )
    s.add_argument(
        "--t-max",
        metavar="S",
        type=quantity_of("t_max"),
        help="give up after this time [s] (default 1)",
    )
    s.add_argument(
        "--no-convergence-check",
        action="store_true",
        help="skip the refined reruns (t_cr then carries no convergence status)",
    )
    p.add_argument(
        "--config", metavar="FILE.toml", type=InputFile(), help="TOML settings (flags override)"
    )


def add_execution_arguments(p: argparse.ArgumentParser) -> None:
    """Workers, Dask scheduler, resume and output flags."""
    add_execution_flags(p.add_argument_group("execution"))  # type: ignore[arg-type]
    p.add_argument("--json", action="store_true", help="print one JSON object")


def _design_kind(dest: str) -> Quantity:
    return quantity_of(dest) if dest in PARAMS else Quantity("Pa*s", _POSITIVE, "1.917e-5")


def _settings(args: argparse.Namespace) -> dict[str, Any]:
    """Config settings (the fields this command uses) under the flags' values."""
    used = _FLIGHT_CONFIG + (_POINT_CONFIG if hasattr(args, "altitude_m") else ())
    if getattr(args, "mach_point", None) is not None or hasattr(args, "mach_point"):
        used += _POINT_CONFIG
    s: dict[str, Any] = {}
    if getattr(args, "config", None):
        s = load_config(args.config, args.command, used)
        if "launch_spin_rate" in s:
            s["spin_rate"] = s.pop("launch_spin_rate")
    flags = (
        *_DESIGN_FLAGS,
        "elevation_deg",
        "spin_rate",
        "twist",
        "roll_damping",
        "projectile_mass",
        "rtol",
        "atol",
        "segment",
        "t_max",
        "mach",
        "altitude_m",
        "temperature_offset_k",
        "drag",
        "torque_model",
    )
    for dest in flags:  # values checked and converted by their kinds
        if getattr(args, dest, None) is not None:
            s[dest] = getattr(args, dest)
    return s


def model_from_args(args: argparse.Namespace, load: str = "coupled") -> Any:
    """The :class:`~obturator.envelope.model.FlightModel` described by the flags."""
    from ..envelope.coupled import ObturatorDesign
    from ..envelope.drag import drag_model
    from ..envelope.model import FlightModel
    from ..envelope.trajectory import Launch, Projectile

    s = _settings(args)
    dkw: dict[str, Any] = {k: s[k] for k in _DESIGN_FLAGS if k in s}
    if "torque_model" in s:
        dkw["torque_model"] = s["torque_model"]
    design = ObturatorDesign(**dkw)
    pkw: dict[str, Any] = {}
    if "projectile_mass" in s:
        pkw["mass"] = s["projectile_mass"]
    if "roll_damping" in s:
        pkw["roll_damping"] = s["roll_damping"]
    pkw["drag"] = drag_model(s.get("drag", "tubular-closed"), bore_radius=design.bore_radius)
    projectile = Projectile(**pkw)
    lkw = {
        k: s[k]
        for k in (
            "mach",
            "altitude_m",
            "temperature_offset_k",
            "elevation_deg",
            "spin_rate",
            "twist",
        )
        if k in s
    }
    launch = Launch(**lkw)
    options = solver_options(s)
    mkw: dict[str, Any] = {}
    if "segment" in s:  # the config's too: t_max / segment segments are allocated
        mkw["segment"] = check_range("segment", s["segment"], MIN_SEGMENT, 0.1, unit="s")
    if "t_max" in s:
        mkw["t_max"] = s["t_max"]
    return FlightModel(
        design,
        launch,
        projectile,
        load=getattr(args, "load", None) or load,
        options=options,
        check_convergence=not args.no_convergence_check,
        **mkw,
    )


def runner_from_args(args: argparse.Namespace, store: Any = None) -> Any:
    """The :class:`~obturator.envelope.executor.Runner` described by the flags."""
    from ..envelope.executor import Runner

    return Runner(
        workers=args.workers,  # whole numbers >= 1 (their kinds)
        scheduler=args.scheduler,
        store=store,
        progress=not args.no_progress and sys.stderr.isatty(),
        chunk_size=args.chunk_size,
    )


def open_store(args: argparse.Namespace, identity: dict[str, Any]) -> Any:
    """The resume store next to ``--out`` (None without ``--out``)."""
    from ..envelope.executor import ResultStore, store_path

    if not getattr(args, "out", None):
        return None
    return ResultStore(store_path(args.out), identity, args.restart)


def _fmt(x: float) -> str:
    return f"{x:.5g}" if math.isfinite(x) else "-"


# --------------------------------------------------------------------------- trajectory


def _run_trajectory(args: argparse.Namespace) -> int:
    from ..envelope.coupled import (
        STATUS_FLAGS,
        cached_flight,
        constant_opening,
        coupled_convergence,
        coupled_opening,
    )

    model = model_from_args(args)
    launch = model.launch
    flight = cached_flight(model.projectile, replace(launch, spin_rate=None), model.t_max)
    spin0 = launch.muzzle_spin
    t0 = time.perf_counter()
    res = coupled_opening(
        model.design,
        flight,
        model.options,
        segment=model.segment,
        t_max=model.t_max,
        spin_rate=spin0,
        record=bool(args.figure),
    )
    conv = None
    if model.check_convergence and res.opened:
        conv = coupled_convergence(
            model.design,
            flight,
            model.options,
            segment=model.segment,
            t_max=model.t_max,
            spin_rate=spin0,
            t_cr=res.t_cr,
        )
    t_const, conv_const = constant_opening(
        model.design, launch, model.options, t_max=model.t_max, check=model.check_convergence
    )
    elapsed = time.perf_counter() - t0
    out = {
        "mach": launch.mach,
        "altitude_m": launch.altitude_m,
        "muzzle_velocity_m_s": launch.velocity,
        "muzzle_spin_rad_s": spin0,
        "t_cr_coupled_s": res.t_cr if res.opened else None,
        "status_coupled": STATUS_FLAGS[res.status],
        "convergence_coupled": None if conv is None else conv.to_dict(),
        "t_cr_constant_s": t_const if math.isfinite(t_const) else None,
        "convergence_constant": conv_const,
        "relative_difference": (res.t_cr / t_const - 1.0)
        if res.opened and math.isfinite(t_const)
        else None,
        "mach_at_opening": res.mach_end,
        "force_at_opening_N": res.force_end,
        "spin_at_opening_rad_s": res.spin_end,
        "segments": res.n_segments,
        "segment_s": res.segment,
        "elapsed_s": elapsed,
    }
    if args.out:
        ds = flight.to_xarray()
        ds.attrs.update(
            {k: ("" if v is None else v) for k, v in out.items() if not isinstance(v, dict)}
        )
        from ..sweeps import write_netcdf

        write_netcdf(ds, args.out)
    if args.figure and res.history is not None:
        from ..envelope.figures import plot_coupled

        plot_coupled(res.history, t_const, args.figure)
    if args.json:
        print(_json.dumps(out))
        return 0
    conv_txt = "-" if conv is None else ("converged" if conv.converged else "NOT converged")
    cc = (
        "-" if conv_const is None else ("converged" if conv_const["converged"] else "NOT converged")
    )
    print(
        f"M0 = {launch.mach:g}, altitude {launch.altitude_m:g} m: V0 = {launch.velocity:.1f} m/s, "
        f"omega_p0 = {spin0:.0f} rad/s"
    )
    print(f"t_cr constant load : {_fmt(t_const)} s ({cc})")
    print(
        f"t_cr coupled       : {_fmt(res.t_cr)} s ({STATUS_FLAGS[res.status]}, {conv_txt}; "
        f"{res.n_segments} segments of {res.segment:g} s)"
    )
    if out["relative_difference"] is not None:
        print(
            f"difference {100 * out['relative_difference']:+.2f} %; at opening M = "
            f"{res.mach_end:.4f}, F_p = {res.force_end:.4g} N, omega_p = {res.spin_end:.1f} rad/s"
        )
    return 0


# --------------------------------------------------------------------------- envelope


def _run_envelope(args: argparse.Namespace) -> int:
    from ..envelope.envelope import EnvelopeSpec, envelope_summary, run_envelope
    from ..sweeps import parse_axis, write_netcdf

    model = model_from_args(args, load="both")
    temps = (
        parse_axis(args.grid_temperature, "--temperature-offset-k")
        if args.grid_temperature
        else [0.0]
    )
    spec = EnvelopeSpec(
        parse_axis(args.grid_mach, "--mach"),
        parse_axis(args.grid_altitude, "--altitude-m"),
        temps,
        model=model,
        requirement=quantity("--requirement", args.requirement, "s"),
        area_ratio=quantity("--area-ratio", args.area_ratio, ""),
    )
    store = open_store(args, spec.identity())
    runner = runner_from_args(args, store)
    t0 = time.perf_counter()
    try:
        ds = run_envelope(spec, runner)
    finally:
        if store is not None:
            store.close()
    elapsed = time.perf_counter() - t0
    if args.out:
        write_netcdf(ds, args.out)
        store.remove()
    if args.figure:
        from ..envelope.figures import plot_envelope

        plot_envelope(ds, args.figure)
    summary = envelope_summary(ds)
    summary.update(
        elapsed_s=elapsed,
        computed=runner.n_computed,
        resumed=runner.n_resumed,
        backend=runner.backend,
        workers=runner.n_workers,
    )
    if args.json:
        print(_json.dumps(summary))
        return 0
    _print_envelope(ds)
    s = summary
    wrote = [p for p in (args.out, args.figure) if p]
    rd = s.get("max_relative_difference")
    at = s.get("max_relative_difference_at", {})
    print(
        f"envelope: {s['points']} points in {elapsed:.1f} s ({runner.n_computed} computed, "
        f"{runner.n_resumed} resumed); meet {s['requirement_s']:g} s: coupled "
        f"{s['coupled_meets_requirement']}, constant {s['constant_meets_requirement']}; "
        f"not converged: coupled {s['coupled_not_converged']}, constant "
        f"{s['constant_not_converged']}"
        + (
            f"; coupled/constant - 1 from {100 * s['min_relative_difference']:+.2f} % to "
            f"{100 * rd:+.2f} % (at M {at.get('mach', math.nan):g}, "
            f"{at.get('altitude_m', math.nan):g} m)"
            if rd is not None
            else ""
        )
        + f"; verdict changed at {s['verdict_changed_points']} points; choked at opening "
        f"{s['choked_at_opening_points']}, not started {s['not_started_points']}"
        + (f"; wrote {', '.join(wrote)}" if wrote else "")
    )
    return 0


def _print_envelope(ds: Any) -> None:
    if "temperature_offset_k" in ds.dims:
        ds = ds.isel(temperature_offset_k=0)
    alts = ds["altitude_m"].values
    head = "  Mach  " + "".join(f"{a:>20g}" for a in alts)
    print("t_cr [s] coupled (constant load); * not converged, c choked at opening")
    print(head + "   altitude [m]")
    for i, m in enumerate(ds["mach"].values):
        cells = []
        for j in range(alts.size):
            tc = float(ds["t_cr_coupled"].values[i, j])
            t0 = float(ds["t_cr_constant"].values[i, j])
            flag = (
                "*"
                if 2 in (ds["status_coupled"].values[i, j], ds["status_constant"].values[i, j])
                else " "
            )
            flag += "c" if ds["choked_at_opening"].values[i, j] else " "
            cells.append(f"{_fmt(tc):>8} ({_fmt(t0):>7}){flag}")
        print(f"{m:6.3g}  " + "".join(f"{c:>20}" for c in cells))


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``trajectory`` and ``envelope`` sub-commands."""
    t = subparsers.add_parser(
        "trajectory",
        help="t_cr along one flight: trajectory-coupled vs constant load",
        description="Fly the Table 1 projectile from the muzzle (point mass, drag, gravity, "
        "1976 atmosphere, roll damping) and integrate the obturator with the load and spin "
        "of the flight; compare with the thesis's constant load.",
    )
    add_model_arguments(t, launch_point=True)
    t.add_argument(
        "--out", metavar="FILE.nc", type=OutputFile(), help="write the trajectory as NetCDF"
    )
    t.add_argument("--figure", metavar="FILE.png", type=FIGURE, help="theta(t), F_p(t), M(t)")
    t.add_argument("--json", action="store_true", help="print one JSON object")
    t.set_defaults(func=_run_trajectory)

    e = subparsers.add_parser(
        "envelope",
        help="t_cr map over muzzle Mach x altitude (coupled and constant load)",
        description="Opening time over the firing envelope with the constant and the "
        "trajectory-coupled load; marks choked (Fanno) and unstarted (Kantrowitz) points. "
        "SPEC is START:STOP:COUNT or a,b,c.",
    )
    e.add_argument(
        "--mach",
        dest="grid_mach",
        metavar="SPEC",
        required=True,
        type=MACH_AXIS,
        help="muzzle Mach numbers",
    )
    e.add_argument(
        "--altitude-m",
        dest="grid_altitude",
        metavar="SPEC",
        required=True,
        type=axis_of("altitude_m"),
        help="launch altitudes [m] (units allowed: '0,1 km')",
    )
    e.add_argument(
        "--temperature-offset-k",
        dest="grid_temperature",
        metavar="SPEC",
        type=Axis("K", TEMPERATURE_OFFSET.range, "0 K"),
        help="temperature offsets [K]",
    )
    e.add_argument(
        "--requirement", metavar="S", default="0.1", type=REQUIREMENT, help="t_cr requirement [s]"
    )
    e.add_argument(
        "--area-ratio",
        metavar="X",
        default="1",
        type=Quantity("", Range(1.0, math.inf, False, True), "1"),
        help="inlet A_c/A_t (default 1)",
    )
    add_model_arguments(e, launch_point=False)
    add_execution_arguments(e)
    e.add_argument(
        "--out", metavar="FILE.nc", default="envelope.nc", type=OutputFile(), help="NetCDF output"
    )
    e.add_argument("--figure", metavar="FILE.png", type=FIGURE, help="contour map")
    e.set_defaults(func=_run_envelope)
