"""Argument helpers shared by the sub-commands: numbers, kinds, solver options, study settings.

Numbers are parsed here rather than by argparse so that a bad value gives the
same one-line ``obturator: error: <field>: ...`` message (exit 2) as an
out-of-range one.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Mapping
from typing import Any

from ..errors import InputError, check_range
from ..io import CASE_FIELDS, study_settings
from ..params import PARAMS, SWEEP_PARAMS, Range
from ..solve import SolverOptions, tolerances_for_opening_time
from ._kinds import Axis, Count, Quantity

__all__ = [
    "flag",
    "parse_number",
    "parse_integer",
    "solver_options",
    "study_config",
    "study_options",
    "study_t_max",
    "fmt_seconds",
    "quantity_of",
    "axis_of",
    "SEED",
    "MAX_WORKERS",
]

_POSITIVE = Range(0.0, math.inf, True, True)
#: Bounds of the flags of parameters that have no finite range in obturator.params:
#: physical sizes of an obturator, with room to spare, so that the arithmetic stays
#: finite (found by the generated fuzz suite: --ball-radius 1e308 overflowed).
_FLAG_RANGES: dict[str, Range] = {
    "ball_radius": Range(0.0, 1.0, True, False),
    "bore_radius": Range(0.0, 1.0, True, False),
    "density": Range(0.0, 1e5, True, False),  # osmium: 22,590 kg/m^3
    "viscosity": Range(0.0, 1e3, True, False),
    "weight": Range(0.0, 1e6, True, False),
    "p1": Range(0.0, 1e9, True, False),
    "patch_radius": Range(0.0, 1.0),
    "rtol": Range(0.0, 1.0, True, True),
    "atol": Range(0.0, 1.0, True, True),
    "friction_width": Range(0.0, 1.0, True, True),
}
#: A valid, cheap value of each parameter flag (for the generated tests).
_EXAMPLES: dict[str, str] = {
    "spin_rate": "300 rad/s",
    "mu_s": "0.55",
    "theta0_deg": "87.25 deg",
    "density": "7669.6 kg/m^3",
    "hole_radius": "4.72 mm",
    "gap": "0.0508 mm",
    "mach": "3",
    "altitude_m": "1 km",
    "t_max": "0.005 s",
    "rtol": "1e-6",
    "atol": "1e-8",
    "friction_width": "1e-6",
    "patch_radius": "0.1 mm",
    "theta_dot0": "0.5 rad/s",
    "release_phase": "1 rad",
    "speed_ratio": "0.5",
    "slip_speed": "0.1 m/s",
}
#: Largest number of local worker processes: beyond a few hundred each process's
#: compiled code (~100 MB) and the pool's start-up dominate any machine we know.
MAX_WORKERS = 1024
#: A random seed: numpy takes any non-negative integer; 63 bits keep it an int64.
SEED = Count(0, 2**63 - 1, example="0")


def quantity_of(name: str) -> Quantity:
    """The kind of the flag of parameter `name`: its unit and range (positive if none)."""
    par = PARAMS[name]
    rng = _FLAG_RANGES.get(name) or par.range or _POSITIVE
    return Quantity(par.pint_unit, rng, _EXAMPLES.get(name, "1"))


def axis_of(name: str) -> Axis:
    """The kind of a sweep axis of parameter `name` (every value in its range)."""
    q = quantity_of(name)
    return Axis(q.unit, q.range, q.example)


def flag(name: str) -> str:
    """The command-line flag of a field name (``spin_rate`` -> ``--spin-rate``)."""
    return "--" + name.replace("_", "-")


def parse_number(field: str, text: str | None, *, finite: bool = True) -> float:
    """A float from flag text; non-finite values are refused unless ``finite=False``."""
    try:
        x = float(text)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(field, f"expected a number, got {text!r}") from None
    if finite and not math.isfinite(x):
        raise InputError(field, f"expected a finite number, got {text!r}")
    return x


def parse_integer(field: str, text: str | None, lo: int | None = None) -> int | None:
    """A whole number from flag text (None passes through), at least `lo` if given."""
    if text is None:
        return None
    try:
        n = int(text)
    except ValueError:
        raise InputError(field, f"expected a whole number, got {text!r}") from None
    if lo is not None and n < lo:
        raise InputError(field, f"{n} is outside the allowed range >= {lo}")
    return n


def solver_options(settings: Mapping[str, Any]) -> SolverOptions:
    """Solver options from merged settings (defaults for anything not given).

    A relative tolerance without an absolute one sets atol = rtol / 100.
    """
    return SolverOptions.from_settings(settings)


#: Case settings of a study that are neither swept nor set by a flag: its base case
#: (``base`` of :class:`obturator.sweeps.SweepSpec`).
_BASE_KEYS = tuple(
    k
    for k in CASE_FIELDS
    if k not in SWEEP_PARAMS and k not in ("case", "torque_model", "spin_mode", "t_max")
)


def study_config(args: argparse.Namespace, command: str) -> dict[str, Any]:
    """Config settings merged under the flags: case, models, t_max and fixed values.

    Every key that describes a case is taken (:data:`obturator.io.CASE_FIELDS`): the
    file that ``simulate`` runs is a study's base case. Fills the unset flags of `args`
    from ``--config`` (``speed_law`` too), puts the case settings that are not
    parameters (ball radius, viscosity, rig weight, contact and flight settings) in
    ``args.base`` and returns the fixed parameter values it gives.
    """
    conf = study_settings(args.config, command, CASE_FIELDS)
    args.base = {k: conf[k] for k in _BASE_KEYS if k in conf and k != "speed_law"}
    if getattr(args, "speed_law", None) is None:
        args.speed_law = conf.get("speed_law", "constant")
    args.case = args.case or conf.get("case", "spin-rig")
    args.torque_model = args.torque_model or conf.get("torque_model", "thesis")
    args.spin_mode = args.spin_mode or conf.get("spin_mode", "constant")
    if args.t_max is None and "t_max" in conf:
        args.t_max = repr(conf["t_max"])
    for key, value in conf.get("solver", {}).items():
        if getattr(args, key, None) is None:
            setattr(args, key, value if isinstance(value, str) else repr(value))
    return {k: float(v) for k, v in conf.items() if k in SWEEP_PARAMS}


def warn_far_from_data(spec: Any, lowest_spin: float | None = None) -> None:
    """Warn on stderr, as ``simulate`` does, when a study's lowest spin (`lowest_spin`
    [rad/s], else its spin axis's smallest value or its fixed spin) is far from the
    validated range (:func:`obturator.model.validity.outside_validated_range`). No cost
    estimate: near stick a point's cost grows with its simulated time, so a probe of one
    point says little of the others."""
    import sys

    from ..model.validity import outside_validated_range

    axis = spec.axes.get("spin_rate")
    if lowest_spin is None and axis is not None:
        lowest_spin = float(min(axis))
    case = spec.build_case({} if lowest_spin is None else {"spin_rate": lowest_spin})
    note = outside_validated_range(case)
    if note:
        print(
            f"obturator: warning: {note}; points there can take minutes each and end at the "
            "step limit (status failed)",
            file=sys.stderr,
        )


def warn_outside_data(ds: Any) -> None:
    """The study dataset's note on points outside the Appendix B runs (its attribute
    ``outside_validated_data``, :func:`obturator.sweeps.points.validity_note`) as one
    warning line on stderr, where there is one."""
    import sys

    if ds.attrs.get("outside_validated_data"):
        print(f"obturator: warning: {ds.attrs['outside_validated_data']}", file=sys.stderr)


def study_options(args: argparse.Namespace) -> SolverOptions:
    """The solver options of the study flags (after :func:`study_config`).

    Refuses ``--friction-width``/``--friction-family`` where the method gives them
    nothing to act on: ``moreau-jean`` (no width, nor its convergence check), and
    ``set-valued`` without the convergence check (whose regularised reruns are the only
    runs that use them).
    """
    method = getattr(args, "method", None)
    check = getattr(args, "convergence_check", False)
    for key, flag in (
        ("friction_width", "--friction-width"),
        ("friction_family", "--friction-family"),
    ):
        if getattr(args, key, None) is None:
            continue
        if method == "moreau-jean":
            raise InputError(
                flag, "sets the regularised law, which --method moreau-jean does not use"
            )
        if method == "set-valued" and not check:
            raise InputError(
                flag,
                "acts with --method set-valued only through the convergence check's "
                "regularised reruns, which are off here",
            )
    s: dict[str, Any] = {}
    for key in ("rtol", "atol", "method", "friction_width", "friction_family", "formulation"):
        value = getattr(args, key, None)
        if value is not None:
            numeric = key in ("rtol", "atol", "friction_width")
            s[key] = parse_number(key, value) if numeric else value
    if getattr(args, "tcr_rtol", None) is not None:
        given = [k for k in ("rtol", "atol") if k in s]
        if given:
            raise InputError("tcr_rtol", f"sets the tolerances: give it or {given[0]}, not both")
        tcr_rtol = parse_number("tcr_rtol", args.tcr_rtol)
        s["rtol"] = tolerances_for_opening_time(tcr_rtol, s.get("method", "auto"))
    return solver_options(s)


def study_t_max(args: argparse.Namespace) -> float | None:
    """``--t-max`` [s], or None for the case factory's default."""
    if args.t_max is None:
        return None
    return check_range("t_max", parse_number("t_max", args.t_max), 0.0, lo_open=True, unit="s")


def fmt_seconds(x: float, infinite: str = "-") -> str:
    """Seconds; NaN and -inf as "-", +inf as `infinite`."""
    if math.isfinite(x):
        return f"{x:.6g}"
    return infinite if x > 0 else "-"
