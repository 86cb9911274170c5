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
trajectory-coupled load, each with its convergence status (status 4, UNCONVERGED, when a
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
import time
from dataclasses import replace
from typing import Any

from ..params import Range
from . import _json
from ._flags import JSON, OUT_NETCDF, add_command, add_flags, option, quantity_option
from ._flight_args import (
    ALTITUDE_GRID,
    FIGURE,
    FIGURE_FLAG,
    LAUNCH_MACH,
    MACH_AXIS,
    MACH_GRID,
    MIN_SEGMENT,
    REQUIREMENT,
    REQUIREMENT_FLAG,
    TEMPERATURE_OFFSET,
    add_execution_arguments,
    add_model_arguments,
    model_from_args,
    quantity,
)
from ._kinds import Axis
from ._runner import study_runner, write_dataset

__all__ = [
    "register",
    "add_model_arguments",
    "add_execution_arguments",
    "model_from_args",
    "quantity",
    "MACH_AXIS",
    "REQUIREMENT",
    "FIGURE",
    "MIN_SEGMENT",
    "LAUNCH_MACH",
]


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
    from ..envelope.start import trajectory_start

    model = model_from_args(args)
    launch = model.launch
    flight = cached_flight(model.projectile, replace(launch, spin_rate=None), model.t_max)
    spin0 = launch.muzzle_spin
    t0 = time.perf_counter()
    run = {"segment": model.segment, "t_max": model.t_max, "spin_rate": spin0}
    res = coupled_opening(model.design, flight, model.options, record=bool(args.figure), **run)
    conv = None
    if model.check_convergence and res.opened:
        conv = coupled_convergence(model.design, flight, model.options, t_cr=res.t_cr, **run)
    t_const, conv_const = constant_opening(
        model.design, launch, model.options, t_max=model.t_max, check=model.check_convergence
    )
    start = trajectory_start(model, flight, spin0)
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
        **start,
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
    _print_start(start)
    return 0


def _print_start(start: dict[str, Any]) -> None:
    def f(x: float | None) -> str:
        return "-" if x is None else f"{x:.5g}"

    conv = start["convergence_start_coupled"]
    cv = "-" if conv is None else ("converged" if conv["converged"] else "NOT converged")
    print(
        f"t_start constant   : {f(start['t_start_constant_s'])} s "
        f"(theta_start = {f(start['theta_start_muzzle_deg'])} deg at the muzzle Mach; "
        f"spill load bracket {f(start['t_start_constant_high_load_s'])}.."
        f"{f(start['t_start_constant_low_load_s'])} s)"
    )
    print(
        f"t_start coupled    : {f(start['t_start_coupled_s'])} s "
        f"({start['status_start_coupled'].replace('opened', 'started')}, {cv}; theta_start = "
        f"{f(start['theta_start_at_start_deg'])} deg at M = {f(start['mach_at_start'])})"
    )
    print(
        f"inlet at the muzzle: {start['inlet_at_muzzle']} "
        f"(Fanno choking Mach {start['choke_mach']:.4g})"
    )
    print(f"t_start bracket    : {start_bracket_text(start)}")


def start_bracket_text(start: dict[str, Any]) -> str:
    """The early and late bounds of theta_start and t_start (constant load), one line."""

    def f(x: float | None) -> str:
        return "-" if x is None else f"{x:.5g}"

    lens = (
        f"lens with f_D L/D {start['friction_fld_late']:.3g}, "
        f"C_d {start['discharge_coefficient_late']:.3g}"
    )
    if start["theta_start_late_deg"] is None:
        why = start["late_at_muzzle"].removeprefix("never starts: ")
        late = f"late never starts ({why}; {lens})"
    else:
        late = (
            f"late {f(start['t_start_constant_late_s'])} s (theta_start "
            f"{f(start['theta_start_late_deg'])} deg, {lens})"
        )
    return (
        f"early {f(start['t_start_constant_early_s'])} s (theta_start "
        f"{f(start['theta_start_early_deg'])} deg, flow turned through the hole) .. {late}"
    )


# --------------------------------------------------------------------------- envelope


def _run_envelope(args: argparse.Namespace) -> int:
    from ..envelope.envelope import EnvelopeSpec, envelope_summary, run_envelope
    from ..sweeps import parse_axis

    model = model_from_args(args, load="both")
    temps = (
        parse_axis(args.grid_temperature, "--temperature-offset-k", "K")
        if args.grid_temperature
        else [0.0]
    )
    spec = EnvelopeSpec(
        parse_axis(args.grid_mach, "--mach", ""),
        parse_axis(args.grid_altitude, "--altitude-m", "m"),
        temps,
        model=model,
        requirement=quantity("--requirement", args.requirement, "s"),
        area_ratio=quantity("--area-ratio", args.area_ratio, ""),
    )
    runner = study_runner(args, spec.identity())
    t0 = time.perf_counter()
    try:
        ds = run_envelope(spec, runner)
    finally:
        runner.close()
    elapsed = time.perf_counter() - t0
    write_dataset(args, runner, ds)
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
        + (
            f"; delay t_start - t_cr (coupled) {_fmt(s['delay_coupled_min_s'] or math.nan)} to "
            f"{_fmt(s['delay_coupled_max_s'] or math.nan)} s, unstartable "
            f"{s['unstartable_points']}, choked at start {s['choked_at_start_points']}"
            if "unstartable_points" in s
            else ""
        )
        + (f"; wrote {', '.join(wrote)}" if wrote else "")
    )
    if "never_starts_late_points" in s:
        print(
            f"late bound of t_start (wall friction, lowest C_d): never starts at "
            f"{s['never_starts_late_points']} of {s['points']} points; latest coupled "
            f"{_fmt(s['t_start_late_coupled_max_s'] or math.nan)} s"
        )
    return 0


def _print_grid(ds: Any, title: str, cell: Any) -> None:
    alts = ds["altitude_m"].values
    rows = [
        (f"{m:.3g}", [cell(i, j) for j in range(alts.size)])
        for i, m in enumerate(ds["mach"].values)
    ]
    # one width for every column (flags after the value), so the rows line up
    width = max([len(f"{a:g}") + 2 for a in alts] + [len(c) for _, cs in rows for c in cs])
    print(title)
    print("  Mach  " + "".join(f"  {f'{a:g}  ':>{width}}" for a in alts) + " altitude [m]")
    for m, cells in rows:
        print(f"{m:>6}  " + "".join(f"  {c:>{width}}" for c in cells).rstrip())


def _print_envelope(ds: Any) -> None:
    if "temperature_offset_k" in ds.dims:
        ds = ds.isel(temperature_offset_k=0)

    def pair(a: str, b: str, i: int, j: int) -> str:
        return f"{_fmt(float(ds[a].values[i, j]))} ({_fmt(float(ds[b].values[i, j]))})"

    def first_light(i: int, j: int) -> str:
        statuses = (ds["status_coupled"].values[i, j], ds["status_constant"].values[i, j])
        flag = "*" if 2 in statuses else " "
        flag += "c" if ds["choked_at_opening"].values[i, j] else " "
        return pair("t_cr_coupled", "t_cr_constant", i, j) + flag

    def start(i: int, j: int) -> str:
        flag = "u" if ds["unstartable"].values[i, j] else " "
        flag += "c" if ds["choked_at_start"].values[i, j] else " "
        return pair("t_start_coupled", "delay_coupled", i, j) + flag

    _print_grid(
        ds, "t_cr [s] coupled (constant load); * not converged, c choked at opening", first_light
    )
    if "t_start_coupled" in ds:
        title = "t_start [s] coupled (delay t_start - t_cr); u unstartable, c choked at start"
        _print_grid(ds, title, start)


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``trajectory`` and ``envelope`` sub-commands."""
    t = add_command(
        subparsers,
        "trajectory",
        _run_trajectory,
        "Fly the Table 1 projectile from the muzzle (point mass, drag, gravity, 1976 "
        "atmosphere, roll damping) and integrate the obturator with the load and spin of "
        "the flight; compare with the thesis's constant load.",
    )
    add_model_arguments(t, launch_point=True)
    add_flags(
        t,
        OUT_NETCDF.but(help="write the trajectory as NetCDF"),
        FIGURE_FLAG.but(help="theta(t), F_p(t), M(t)"),
        JSON,
    )
    e = add_command(
        subparsers,
        "envelope",
        _run_envelope,
        "Opening time over the firing envelope with the constant and the trajectory-coupled "
        "load; marks choked (Fanno) and unstarted (Kantrowitz) points. SPEC is "
        "START:STOP:COUNT or a,b,c.",
        MACH_GRID.but(help="muzzle Mach numbers (required, or [flight] mach in --config)"),
        ALTITUDE_GRID.but(
            help="launch altitudes [m] (units allowed: '0,1 km'; required, or [flight] "
            "altitude in --config)"
        ),
        option(
            "--temperature-offset-k",
            dest="grid_temperature",
            metavar="SPEC",
            type=Axis("K", TEMPERATURE_OFFSET.range, "0 K"),
            help="temperature offsets [K]",
        ),
        REQUIREMENT_FLAG,
        quantity_option(
            "--area-ratio",
            "",
            Range(1.0, math.inf, False, True),
            "1",
            "inlet A_c/A_t (default 1)",
            default="1",
        ),
    )
    add_model_arguments(e, launch_point=False)
    add_execution_arguments(e)
    add_flags(
        e,
        OUT_NETCDF.but(default="envelope.nc", help="NetCDF output"),
        FIGURE_FLAG.but(help="contour map"),
    )
