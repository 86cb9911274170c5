"""The columns of a spin-rig data file and the checks across them (one schema).

Read by :func:`obturator.calibration.data.load_spin_rig_csv` for ``calibrate``,
``validate`` and ``design-experiment``: every column is known (:data:`RUN_COLUMNS` and
the fixed ones) or refused, naming the closest known name and the allowed list; a
command refuses a known column it does not use; and each run's columns agree with each
other and with a ball that can open (:func:`check_runs`).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError

__all__ = ["RUN_COLUMNS", "SETTING_NAMES", "CASE_COLUMNS", "column_help", "check_runs"]

_TIME = "t_cr_s"
_READOUT = "readout_hz"
_SPIN = "spin_rate_rad_s"
_PRINTED = "omega_p_printed_rad_s"
_STARRED = "starred"
#: Free text per run (a note of the operator), read by no computation.
_COMMENT = "comment"
_KNOWN = (_READOUT, _SPIN, _TIME, _PRINTED, _STARRED)
#: A number as a data file may write it: ASCII digits, one optional sign, decimal point
#: and exponent. Python's float() also reads "3_00" (300), "inf", "nan" and non-ASCII
#: digits, none of which a rig's readout writes.
_STRICT_NUMBER = re.compile(r"^[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?$")
#: Optional per-run settings: name -> (SI unit, unit of a header without one, parameter
#: of obturator.params.PARAMS whose range applies). A header names the unit as
#: ``name_unit`` (``hole_radius_mm``; ``_`` between units reads as ``/``, a trailing
#: digit as a power: ``density_kg_m3``), ``name [unit]`` (``density [g/cm^3]``) or
#: ``name (unit)``; a bare ``name`` is in the documented unit.
RUN_COLUMNS: dict[str, tuple[str, str, str]] = {
    "theta0": ("deg", "deg", "theta0_deg"),
    "hole_radius": ("m", "mm", "hole_radius"),
    "density": ("kg/m^3", "kg/m^3", "density"),
    "ball_mass": ("kg", "g", "ball_mass"),
    "theta_measured": ("deg", "deg", "theta0_deg"),
    "t_measured": ("s", "s", "t_max"),
}
#: Per-run setting names (SpinRigData.settings keys) of each optional column.
SETTING_NAMES = {
    "theta0": "theta0_deg",
    "hole_radius": "hole_radius",
    "density": "density",
    "ball_mass": "ball_mass",
    "theta_measured": "theta_measured_deg",
    "t_measured": "t_measured",
}
#: The per-run setting columns of the rig's case (what calibrate and design-experiment
#: use); validate also fits the times to intermediate angles (theta_measured, t_measured).
CASE_COLUMNS = ("theta0", "hole_radius", "density", "ball_mass")
#: The per-run setting columns of the rig's case (what calibrate and design-experiment
#: use); validate also fits the times to intermediate angles (theta_measured, t_measured).
CASE_COLUMNS = ("theta0", "hole_radius", "density", "ball_mass")


def _fail(column: str, source: str, line: int, what: str) -> InputError:
    return InputError(column, f"{source}, line {line}: {what}")


def column_help(columns: Iterable[str] = tuple(RUN_COLUMNS)) -> str:
    """The columns a data file may hold, as the help and the errors list them.

    Parameters
    ----------
    columns : iterable of str
        The per-run setting columns (:data:`RUN_COLUMNS`) the reading command uses.
    """
    settings = ", ".join(f"{c} [{RUN_COLUMNS[c][1]}]" for c in columns)
    return (
        f"{_TIME}, {_READOUT} or {_SPIN}, {_STARRED}, {_PRINTED}, {_COMMENT} (free text), "
        f"and per run {settings}, each with its unit in the header as name_unit, "
        "'name [unit]' or 'name (unit)'"
    )


def _closest(cell: str) -> str:
    """The known column name nearest to `cell` (difflib's ratio, case-blind)."""
    import difflib

    names = [*_KNOWN, _COMMENT]
    names += [f"{c}_{u.replace('/', '_').replace('^', '')}" for c, (_, u, _) in RUN_COLUMNS.items()]
    key = cell.strip().lower()
    return max(names, key=lambda n: difflib.SequenceMatcher(None, key, n).ratio())


def check_header(header: list[str], source: str, line: int, columns: tuple[str, ...]) -> None:
    """Every header cell is a known column the reading command uses, else one error."""
    for cell in header:
        if cell in _KNOWN or cell == _COMMENT:
            continue
        found = column_unit(cell)
        if found is None:
            raise _fail(
                cell,
                source,
                line,
                f"unknown column {cell!r} (closest known: {_closest(cell)!r}); allowed: "
                + column_help(columns),
            )
        if found[0] not in columns:
            unused = ", ".join(c for c in RUN_COLUMNS if c not in columns)
            raise _fail(
                cell,
                source,
                line,
                f"column {cell!r} is not used by this command (it reads "
                f"{', '.join(columns) or 'no per-run settings'}; {unused}: obturator "
                "validate); remove the column",
            )


def column_unit(cell: str) -> tuple[str, str] | None:
    """(optional column, unit text) of a header cell, None if it is none of them."""
    for name in sorted(RUN_COLUMNS, key=len, reverse=True):
        if cell == name:
            return name, RUN_COLUMNS[name][1]
        rest = cell[len(name) :]
        if not cell.startswith(name) or not rest:
            continue
        if rest[0] == "_":
            # hole_radius_mm -> mm, density_kg_m3 -> kg/m^3
            return name, re.sub(r"([A-Za-z])(\d)", r"\1^\2", rest[1:].replace("_", "/"))
        bracket = rest.strip()
        if bracket[:1] + bracket[-1:] in ("[]", "()"):
            return name, bracket[1:-1].strip()
    return None


def check_runs(
    settings: dict[str, NDArray[np.float64]],
    times: NDArray[np.float64],
    rows: list[tuple[int, list[str]]],
    source: str,
) -> None:
    """Each run's columns agree with one another and with a ball that can open.

    * A run opens when theta falls from theta_0 to the opening angle
      beta_s = asin(r_s / R_s) (Eq. 6; r_s the run's hole radius, else Table 1's). A
      run with theta_0 = 90 deg starts at the equilibrium with the hole square to the
      spin axis, from which t_cr grows without bound (``params.FIT_SPECS``), and one
      with theta_0 <= beta_s is open at release: neither can have the measured t_cr.
      Every such run is named in one error.
    * An intermediate angle comes with its time, and lies strictly between beta_s and
      theta_0 (the ball nutates down from theta_0 and the run ends at beta_s).
    * Its time is below the run's t_cr: theta(t) is continuous and starts above the
      intermediate angle, which lies above beta_s, so theta passes it before it first
      reaches beta_s (intermediate value theorem); a later time is a different event or
      a wrong cell, and would pull every run of a fit.
    """
    from ..reference import TABLE1

    n = len(rows)
    nan = np.full(n, np.nan)
    angle, time = settings.get("theta_measured_deg"), settings.get("t_measured")
    theta0 = settings.get("theta0_deg", nan)
    hole = settings.get("hole_radius", nan)
    closed: list[str] = []
    for k, (ln, _) in enumerate(rows):
        t0 = theta0[k] if np.isfinite(theta0[k]) else TABLE1["theta0_deg"]
        r_s = hole[k] if np.isfinite(hole[k]) else TABLE1["hole_radius"]
        beta = math.degrees(math.asin(r_s / TABLE1["ball_radius"]))
        if t0 >= 90.0:
            closed.append(
                f"line {ln} (theta0 = {t0:g} deg: the equilibrium, hole square to the spin)"
            )
        elif t0 <= beta:
            closed.append(
                f"line {ln} (theta0 = {t0:g} deg <= opening angle {beta:.4g} deg: open at release)"
            )
        if angle is None and time is None:
            continue
        a = angle[k] if angle is not None else math.nan
        t = time[k] if time is not None else math.nan
        if np.isfinite(a) != np.isfinite(t):
            col = "t_measured" if np.isfinite(a) else "theta_measured"
            raise _fail(col, source, ln, "theta_measured and t_measured come together")
        if not np.isfinite(a):
            continue
        if not beta < a < t0:
            raise _fail(
                "theta_measured",
                source,
                ln,
                f"{a:g} deg is not between the run's opening angle beta_s = {beta:.4g} deg "
                f"and theta_0 = {t0:g} deg (the ball nutates down from theta_0 and the run "
                "ends at beta_s)",
            )
        if not t < times[k]:
            raise _fail(
                "t_measured",
                source,
                ln,
                f"{t:g} s is not below the run's t_cr_s = {times[k]:g} s (theta passes "
                f"{a:g} deg on its way from theta_0 to beta_s, so before the run opens)",
            )
    if closed:
        raise InputError(
            "theta0",
            f"{source}: {len(closed)} run(s) where the ball cannot open, yet a t_cr was "
            "measured: " + "; ".join(closed[:5]) + ("; ..." if len(closed) > 5 else ""),
        )
