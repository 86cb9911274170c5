"""``obturator gasdyn``: compressible-flow checks of the bore (thesis chapter I.B.4).

Sub-commands::

    obturator gasdyn normal-shock --mach M [--gamma G] [--json]
    obturator gasdyn start (--area-ratio X | --mach M) [--gamma G] [--json]
    obturator gasdyn choke (--fld X | --l-over-d X (--reynolds X [--iterations N]
                           | --bore-diameter-m D [--altitude-m H])) [--json]
    obturator gasdyn atmosphere --altitude-m H [--json]

Numbers are parsed by :mod:`._args` rather than by argparse so that a bad value
gives the same one-line ``obturator: error:`` message (exit 2) as an
out-of-range one.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from .. import flow as gd
from ..errors import InputError
from ..flow import standard_atmosphere
from ..params import Range
from . import _json
from ._args import parse_integer, parse_number, quantity_of
from ._kinds import Count, Quantity

#: Ratio of specific heats: 1 < gamma <= 5/3 for ideal gases (5/3: monatomic).
GAMMA = Quantity("", Range(1.0, 5.0 / 3.0, True, False), "1.4")
SUPERSONIC = Quantity("", Range(1.0, math.inf, False, True), "2")
POSITIVE = Quantity("", Range(0.0, math.inf, True, True), "2")
NON_NEGATIVE = Quantity("", Range(0.0, math.inf, False, True), "0.5")

__all__ = ["register"]

Row = tuple[str, Any, str]


def _number(field: str, text: str | None) -> float:
    return parse_number(field, text, finite=False)  # the gas-dynamics checks name the range


def _integer(field: str, text: str) -> int:
    return int(parse_integer(field, text))  # type: ignore[arg-type]


def _fmt(value: Any) -> str:
    if isinstance(value, str):
        return value
    if isinstance(value, int):
        return str(value)
    return f"{value:.6g}"


def _print_table(rows: list[Row]) -> None:
    """Print ``rows`` as three aligned columns: quantity, value, unit."""
    cells = [(label, _fmt(value), unit) for label, value, unit in rows]
    w_label = max(len(c[0]) for c in cells)
    w_value = max(len(c[1]) for c in cells)
    for label, value, unit in cells:
        print(f"{label:<{w_label}}  {value:>{w_value}}  {unit}".rstrip())


def _emit(args: argparse.Namespace, data: dict[str, Any], rows: list[Row]) -> int:
    if args.json:
        print(_json.dumps(data))
    else:
        _print_table(rows)
    return 0


def _emit_fields(args: argparse.Namespace, fields: list[tuple[str, str, Any, str]]) -> int:
    """Print (key, label, value, unit) fields: as JSON keys, or as the table's rows."""
    data = {key: value for key, _, value, _ in fields}
    return _emit(args, data, [(label, value, unit) for _, label, value, unit in fields])


def _cmd_normal_shock(args: argparse.Namespace) -> int:
    s = gd.normal_shock(_number("mach", args.mach), _number("gamma", args.gamma))
    return _emit_fields(
        args,
        [
            ("mach", "upstream Mach M1", s.mach, "-"),
            ("gamma", "gamma", s.gamma, "-"),
            ("mach2", "downstream Mach M2 (Eq. 3)", s.mach2, "-"),
            ("pressure_ratio", "pressure ratio p2/p1 (Eq. 1)", s.pressure_ratio, "-"),
            ("density_ratio", "density ratio rho2/rho1", s.density_ratio, "-"),
            ("temperature_ratio", "temperature ratio T2/T1", s.temperature_ratio, "-"),
            (
                "stagnation_pressure_ratio",
                "stagnation pressure ratio p02/p01",
                s.stagnation_pressure_ratio,
                "-",
            ),
        ],
    )


def _cmd_start(args: argparse.Namespace) -> int:
    gamma = _number("gamma", args.gamma)
    limit = float(gd.swallow_area_ratio_limit(gamma))
    if args.area_ratio is not None:
        ratio = _number("area_ratio", args.area_ratio)
        unstart = gd.unstart_mach(ratio, gamma)
        # Above the Eq. 2 limit the inlet never self-starts; the unstart Mach of
        # an inlet started some other way is still meaningful, so report both.
        start = gd.start_mach(ratio, gamma) if ratio < limit else None
        data = {
            "area_ratio": ratio,
            "gamma": gamma,
            "start_mach": start,
            "unstart_mach": unstart,
            "swallow_area_ratio_limit": limit,
        }
        rows: list[Row] = [
            ("area ratio A_c/A_t", ratio, "-"),
            ("gamma", gamma, "-"),
            (
                "start Mach (Eq. 2)",
                start if start is not None else "never (ratio >= Eq. 2 limit)",
                "-" if start is not None else "",
            ),
            ("unstart Mach (Eq. 4)", unstart, "-"),
            ("Eq. 2 limit as M1 -> inf", limit, "-"),
        ]
        return _emit(args, data, rows)
    mach = _number("mach", args.mach)
    swallow = gd.swallow_area_ratio(mach, gamma)
    regurgitate = gd.regurgitate_area_ratio(mach, gamma)
    data = {
        "mach": mach,
        "gamma": gamma,
        "mach2": gd.normal_shock_mach(mach, gamma),
        "swallow_area_ratio": swallow,
        "regurgitate_area_ratio": regurgitate,
    }
    rows = [
        ("flight Mach M1", mach, "-"),
        ("gamma", gamma, "-"),
        ("post-shock Mach M2 (Eq. 3)", data["mach2"], "-"),
        ("swallow A_c/A_t (Eq. 2)", swallow, "-"),
        ("regurgitate A_c/A_t (Eq. 4)", regurgitate, "-"),
    ]
    return _emit(args, data, rows)


#: The flags of ``gasdyn choke`` that act on some of its three routes only (--fld; L/D
#: with --reynolds; L/D with --bore-diameter-m): dest -> (flag, default, the routes it
#: acts on). They default to None, so that one given on another route is refused;
#: :func:`_choke_route` fills in the defaults after that check.
_CHOKE_ONLY: dict[str, tuple[str, str | None, tuple[str, ...]]] = {
    "branch": ("--branch", "supersonic", ("--fld",)),
    "reynolds": ("--reynolds", None, ("--l-over-d",)),
    "bore_diameter_m": ("--bore-diameter-m", None, ("--l-over-d",)),
    "reynolds_mach": ("--reynolds-mach", str(gd.THESIS_REYNOLDS_MACH), ("--reynolds",)),
    "iterations": ("--iterations", "1", ("--reynolds",)),
    "altitude_m": ("--altitude-m", "0", ("--bore-diameter-m",)),
    "roughness": ("--roughness", "0", ("--reynolds", "--bore-diameter-m")),
    "correlation": ("--correlation", "colebrook", ("--reynolds", "--bore-diameter-m")),
}


def _choke_route(args: argparse.Namespace) -> None:
    """Refuse a flag given on a route of ``gasdyn choke`` it does nothing on (one line
    naming both flags), then set the unset ones to their defaults."""
    if args.fld is not None:
        routes = ("--fld",)
    elif args.bore_diameter_m is not None:
        routes = ("--l-over-d", "--bore-diameter-m")
    elif args.reynolds is not None:
        routes = ("--l-over-d", "--reynolds")
    else:
        raise InputError("reynolds", "--l-over-d needs --reynolds or --bore-diameter-m")
    for dest, (flag, default, acts_on) in _CHOKE_ONLY.items():
        if getattr(args, dest) is None:
            setattr(args, dest, default)
        elif not set(acts_on) & set(routes):
            raise InputError(
                flag, f"applies with {' or '.join(acts_on)} only, not with {routes[-1]}"
            )


def _cmd_choke(args: argparse.Namespace) -> int:
    if args.bore_diameter_m is not None and args.reynolds is not None:
        raise InputError("reynolds", "give either --reynolds or --bore-diameter-m, not both")
    _choke_route(args)
    gamma = _number("gamma", args.gamma)
    if args.fld is not None:
        fld = _number("fld", args.fld)
        mach = gd.fanno_mach(fld, gamma, args.branch)
        data = {"fld": fld, "gamma": gamma, "branch": args.branch, "mach": mach}
        rows: list[Row] = [
            ("f_D L/D", fld, "-"),
            ("gamma", gamma, "-"),
            (f"choking Mach ({args.branch})", mach, "-"),
        ]
        return _emit(args, data, rows)

    l_over_d = _number("l_over_d", args.l_over_d)
    roughness = _number("relative_roughness", args.roughness)
    if args.bore_diameter_m is not None:
        diameter = _number("bore_diameter_m", args.bore_diameter_m)
        altitude = _number("altitude_m", args.altitude_m)
        mach = gd.choking_mach_freestream(
            l_over_d,
            diameter,
            altitude_m=altitude,
            relative_roughness=roughness,
            correlation=args.correlation,
            gamma=gamma,
        )
        re = float(gd.freestream_reynolds(mach, diameter, altitude))
        f = float(gd.friction_factor(re, roughness, args.correlation))
        data = {
            "l_over_d": l_over_d,
            "bore_diameter_m": diameter,
            "altitude_m": altitude,
            "correlation": args.correlation,
            "relative_roughness": roughness,
            "reynolds": re,
            "friction_factor": f,
            "fld": f * l_over_d,
            "mach": mach,
        }
        rows = [
            ("L/D", l_over_d, "-"),
            ("bore diameter", diameter, "m"),
            ("altitude", altitude, "m"),
            ("Reynolds number at choking", re, "-"),
            (f"friction factor f_D ({args.correlation})", f, "-"),
            ("f_D L/D", f * l_over_d, "-"),
            ("choking Mach (converged)", mach, "-"),
        ]
        return _emit(args, data, rows)

    steps = gd.choking_history(
        l_over_d,
        _number("reynolds", args.reynolds),
        reynolds_mach=_number("reynolds_mach", args.reynolds_mach),
        iterations=_integer("iterations", args.iterations),
        relative_roughness=roughness,
        correlation=args.correlation,
        gamma=gamma,
    )
    data = {
        "l_over_d": l_over_d,
        "reynolds_mach": _number("reynolds_mach", args.reynolds_mach),
        "correlation": args.correlation,
        "relative_roughness": roughness,
        "steps": [
            {
                "iteration": s.iteration,
                "reynolds": s.reynolds,
                "friction_factor": s.friction_factor,
                "fld": s.fld,
                "mach": s.mach,
            }
            for s in steps
        ],
        "mach": steps[-1].mach,
    }
    if args.json:
        print(_json.dumps(data))
        return 0
    header = ("iteration", "Re", "f_D", "f_D L/D", "Mach")
    table = [header] + [
        (str(s.iteration), _fmt(s.reynolds), _fmt(s.friction_factor), _fmt(s.fld), _fmt(s.mach))
        for s in steps
    ]
    widths = [max(len(r[i]) for r in table) for i in range(len(header))]
    print(
        f"L/D = {l_over_d:g}, correlation = {args.correlation}, Re scales as M/{args.reynolds_mach}"
    )
    for r in table:
        print("  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)))
    return 0


def _cmd_atmosphere(args: argparse.Namespace) -> int:
    atm = standard_atmosphere(_number("altitude_m", args.altitude_m))
    return _emit_fields(
        args,
        [
            ("altitude_m", "geometric altitude", atm.altitude_m, "m"),
            ("geopotential_m", "geopotential altitude", atm.geopotential_m, "m'"),
            ("temperature_K", "temperature", atm.temperature, "K"),
            ("pressure_Pa", "pressure", atm.pressure, "Pa"),
            ("density_kg_m3", "density", atm.density, "kg/m^3"),
            ("speed_of_sound_m_s", "speed of sound", atm.speed_of_sound, "m/s"),
            ("dynamic_viscosity_Pa_s", "dynamic viscosity", atm.dynamic_viscosity, "Pa s"),
            (
                "kinematic_viscosity_m2_s",
                "kinematic viscosity",
                atm.kinematic_viscosity,
                "m^2/s",
            ),
        ],
    )


def register(subparsers: Any) -> None:
    """Add the ``gasdyn`` command and its sub-commands to ``subparsers``."""
    parser = subparsers.add_parser(
        "gasdyn",
        help="normal shock, inlet start/unstart, Fanno choking, standard atmosphere",
        description="Compressible flow of the open bore (thesis chapter I.B.4).",
    )
    sub = parser.add_subparsers(dest="gasdyn_command", metavar="TOPIC")
    sub.required = True

    def common(p: argparse.ArgumentParser, gamma: bool = True) -> None:
        if gamma:
            p.add_argument(
                "--gamma",
                default="1.4",
                type=GAMMA,
                help="ratio of specific heats (1.4; ideal gases: 1 < gamma <= 5/3)",
            )
        p.add_argument("--json", action="store_true", help="print one JSON object")

    p = sub.add_parser("normal-shock", help="normal-shock ratios (Eqs. 1, 3)")
    p.add_argument("--mach", required=True, type=SUPERSONIC, help="upstream Mach number M1 >= 1")
    common(p)
    p.set_defaults(func=_cmd_normal_shock)

    p = sub.add_parser(
        "start",
        help="Kantrowitz-Donaldson start/unstart (Eqs. 2, 4)",
        description="Area ratio A_c/A_t -> start and unstart Mach; "
        "Mach -> swallow and regurgitate area ratios.",
    )
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument(
        "--area-ratio",
        type=Quantity("", Range(1.0, math.inf, False, True), "1.2"),
        help="capture-to-throat area ratio A_c/A_t >= 1",
    )
    g.add_argument("--mach", type=SUPERSONIC, help="flight Mach number M1 >= 1")
    common(p)
    p.set_defaults(func=_cmd_start)

    p = sub.add_parser(
        "choke",
        help="Fanno choking Mach of the bore",
        description="Choking Mach from f_D L/D, or from L/D with the thesis's "
        "friction-factor iteration (--reynolds) or converged from free-stream "
        "conditions (--bore-diameter-m). f_D is the Darcy factor.",
    )
    g = p.add_mutually_exclusive_group(required=True)
    g.add_argument("--fld", type=NON_NEGATIVE, help="f_D L/D (Darcy friction factor)")
    g.add_argument("--l-over-d", type=POSITIVE, help="bore length over diameter")
    p.add_argument(
        "--branch",
        choices=("supersonic", "subsonic"),
        help="which choking Mach of f_D L/D: the supersonic (default) or the subsonic branch",
    )
    p.add_argument("--reynolds", type=POSITIVE, help="bore Reynolds number at --reynolds-mach")
    p.add_argument(
        "--reynolds-mach",
        type=POSITIVE,
        help="flight Mach at which --reynolds holds (2.5)",
    )
    p.add_argument(
        "--iterations",
        type=Count(1, 100),
        help="friction-factor revisions of --reynolds (1; the iteration converges in < 10)",
    )
    p.add_argument(
        "--bore-diameter-m",
        type=Quantity("m", Range(0.0, math.inf, True, True), "9.44 mm"),
        help="bore diameter [m]: iterate Re to convergence",
    )
    p.add_argument(
        "--altitude-m",
        type=quantity_of("altitude_m"),
        help="altitude for --bore-diameter-m [m] (0)",
    )
    p.add_argument(
        "--roughness",
        type=Quantity("", Range(0.0, 1.0, False, True), "0.001"),
        help="relative roughness eps/D of --reynolds or --bore-diameter-m (default 0: smooth)",
    )
    p.add_argument(
        "--correlation",
        choices=("colebrook", "haaland"),
        help="friction factor of --reynolds or --bore-diameter-m: Colebrook-White (default) "
        "or Haaland",
    )
    common(p)
    p.set_defaults(func=_cmd_choke)

    p = sub.add_parser("atmosphere", help="U.S. Standard Atmosphere 1976")
    p.add_argument(
        "--altitude-m",
        required=True,
        type=quantity_of("altitude_m"),
        help="geometric altitude [m] (units allowed: '11 km', '36089 ft'), 0..86000",
    )
    common(p, gamma=False)
    p.set_defaults(func=_cmd_atmosphere)
