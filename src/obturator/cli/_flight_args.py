"""Flags of the flight commands (trajectory, envelope, probability, sensitivity,
optimize): design, projectile, launch, solver and execution, with their kinds,
and the flight model, runner and resume store they describe.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from ..errors import InputError, check_range
from ..io import SOLVER_KEYS, load_config
from ..params import Range
from ..units import parse_quantity
from ._args import axis_of, flag, quantity_of, solver_options
from ._flags import (
    ATOL,
    CONFIG,
    JSON,
    RTOL,
    T_MAX,
    TORQUE_MODEL,
    Flag,
    add_flags,
    alias,
    convergence_flags,
    execution_flags,
    option,
    quantity_option,
)
from ._flags import (
    FIGURE as FIGURE_OPTION,
)
from ._kinds import Axis, NameOrFile, OutputFile, Quantity

__all__ = [
    "add_model_arguments",
    "add_execution_arguments",
    "model_from_args",
    "quantity",
    "LAUNCH_MACH",
    "TEMPERATURE_OFFSET",
    "MACH_AXIS",
    "REQUIREMENT",
    "FIGURE",
    "MIN_SEGMENT",
    "MACH_GRID",
    "ALTITUDE_GRID",
    "REQUIREMENT_FLAG",
    "FIGURE_FLAG",
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
#: Case keys of a flight config (the file ``simulate`` runs) that the trajectory model
#: takes: the case's name, the Coulomb contacts and the launch point (a grid command's
#: grid when its flag is not given).
_CASE_CONFIG = ("case", "n_contacts", "patch_radius", *_POINT_CONFIG)
#: Case keys the trajectory model cannot honour, each with the reason it is refused.
_REFUSED = {
    "spin_mode": "the trajectory sets the spin (rifling twist, roll damping)",
    "p1": "the trajectory takes the pressure from the altitude (1976 standard atmosphere): "
    "give [flight] altitude",
    **{
        k: "applies to the spin rig only"
        for k in ("weight", "theta_dot0", "release_phase", "speed_law", "speed_ratio", "slip_speed")
    },
}
#: Launch-point grids of the grid commands when neither the flag nor the config's
#: [flight] section gives one: command -> (Mach, altitude [m]); None: required.
_GRID_DEFAULTS = {
    "envelope": (None, None),
    "probability": ("3", "0"),
    "optimize": ("1.5,2.75,4", "0,10000"),
}
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

#: Grids of launch points (envelope, probability, optimize).
MACH_GRID = option(
    "--mach",
    dest="grid_mach",
    metavar="SPEC",
    type=MACH_AXIS,
    help="muzzle Mach numbers: START:STOP:COUNT or a list a,b,c",
)
ALTITUDE_GRID = option(
    "--altitude-m",
    dest="grid_altitude",
    metavar="SPEC",
    type=axis_of("altitude_m"),
    help="launch altitudes [m]: START:STOP:COUNT or a list a,b,c",
)
REQUIREMENT_FLAG = option(
    "--requirement", metavar="S", default="0.1", type=REQUIREMENT, help="t_cr requirement [s]"
)
FIGURE_FLAG = FIGURE_OPTION.but(type=FIGURE)


def quantity(field: str, value: Any, unit: str) -> float:
    """A CLI value (number or quantity string) in `unit`."""
    return parse_quantity(field, value, unit)


def _design_flags() -> tuple[Flag, ...]:
    """The design flags: unit and range from obturator.params."""
    flags = [
        option(flag(dest), dest=dest, metavar="X", type=quantity_of(dest), help=text)
        for dest, text in _DESIGN_FLAGS.items()
    ]
    return (*flags, TORQUE_MODEL.but(choices=("thesis", "coulomb")))


_LAUNCH_POINT = (
    option("--mach", metavar="X", type=LAUNCH_MACH, help="muzzle Mach number (default 3)"),
    option(
        "--altitude-m",
        metavar="X",
        type=quantity_of("altitude_m"),
        help="launch altitude [m] (default 0)",
    ),
    option(
        "--temperature-offset-k",
        metavar="X",
        type=TEMPERATURE_OFFSET,
        help="off-standard temperature [K] (default 0)",
    ),
)
_DRAG = option(
    "--drag",
    dest="drag",
    metavar="NAME|FILE.csv",
    type=NameOrFile(_DRAG_CURVES, "tubular-open"),
    help="drag curve: tubular-closed (default), tubular-open, or a CSV with columns mach,cd",
)
_LAUNCH = (
    quantity_option(
        "--elevation-deg", "deg", Range(-90.0, 90.0), "0 deg", "elevation angle [deg] (default 0)"
    ),
    option(
        "--spin-rate",
        metavar="X",
        type=quantity_of("spin_rate"),
        help="muzzle spin [rad/s]; default: rifling twist, 2 pi V_0 / twist "
        "(12042 rad/s at Table 1's Mach 3, sea level)",
    ),
    # found by the fuzz suite: 1e308 m divided by zero; 1 mm to 100 m per turn spans every rifling
    quantity_option(
        "--twist", "m", Range(1e-3, 100.0), "0.5 m", "rifling twist [m per turn] (default 0.5327)"
    ),
    _DRAG,
    alias(_DRAG, "--cd-table"),
    quantity_option(
        "--roll-damping", "", Range(-10.0, 10.0), "-0.012", "roll-damping coefficient C_lp (-0.012)"
    ),
    # 1 g to 1 t (fuzz: 1e-300 kg stalled the trajectory integration)
    quantity_option(
        "--projectile-mass", "kg", Range(1e-3, 1e3), "0.141 kg", "projectile mass [kg] (0.141)"
    ),
)
_SOLVER = (
    option(
        "--load",
        choices=("coupled", "constant"),
        default=None,
        help="trajectory-coupled load (default) or the thesis's constant muzzle load "
        "(the envelope always computes both)",
    ),
    RTOL,
    ATOL,
    quantity_option(
        "--segment",
        "s",
        Range(MIN_SEGMENT, 0.1),
        "2 ms",
        f"segment of the coupled load [s] (2e-3; {MIN_SEGMENT:g} to 0.1)",
        metavar="S",
    ),
    T_MAX.but(help="give up after this time [s] (default 1)"),
    *convergence_flags(
        True,
        "the refined reruns; without them t_cr carries no convergence status",
    ),
)


def add_model_arguments(p: argparse.ArgumentParser, *, launch_point: bool) -> None:
    """Design, projectile, launch and solver flags shared by the envelope commands."""
    add_flags(p.add_argument_group("design (Table 1 defaults)"), *_design_flags())
    add_flags(p.add_argument_group("flight"), *(_LAUNCH_POINT if launch_point else ()), *_LAUNCH)
    add_flags(p.add_argument_group("solver"), *_SOLVER)
    add_flags(p, CONFIG)


def add_execution_arguments(p: argparse.ArgumentParser) -> None:
    """Workers, Dask scheduler, resume and output flags."""
    add_flags(p.add_argument_group("execution"), *execution_flags())
    add_flags(p, JSON)


def _settings(args: argparse.Namespace) -> dict[str, Any]:
    """Config settings (the fields this command uses) under the flags' values."""
    s: dict[str, Any] = {}
    if getattr(args, "config", None):
        s = load_config(args.config, args.command, (*_FLIGHT_CONFIG, *_CASE_CONFIG, *_REFUSED))
        for key, why in _REFUSED.items():
            if key in s:
                raise InputError(key, f"{why} (obturator {args.command})")
        if s.pop("case", "flight") != "flight":
            raise InputError("case", f"obturator {args.command} runs the flight case")
        if "launch_spin_rate" in s:
            s["spin_rate"] = s.pop("launch_spin_rate")
    if hasattr(args, "grid_mach"):  # a grid command: the file's launch point is its grid
        mach, altitude = _GRID_DEFAULTS.get(args.command, (None, None))
        point = {k: s.pop(k) for k in _POINT_CONFIG if k in s}
        if args.grid_mach is None:
            args.grid_mach = repr(point["mach"]) if "mach" in point else mach
        if args.grid_altitude is None:
            args.grid_altitude = repr(point["altitude_m"]) if "altitude_m" in point else altitude
        for name, value in (("--mach", args.grid_mach), ("--altitude-m", args.grid_altitude)):
            if value is None:
                raise InputError(name, "give the grid (or [flight] in --config)")
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

    if getattr(args, "twist", None) is not None and getattr(args, "spin_rate", None) is not None:
        raise InputError(
            "--twist", "sets the muzzle spin by the twist law, which --spin-rate replaces: give one"
        )
    s = _settings(args)
    dkw: dict[str, Any] = {
        k: s[k] for k in (*_DESIGN_FLAGS, "n_contacts", "patch_radius") if k in s
    }
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
        check_convergence=args.convergence_check,
        **mkw,
    )
