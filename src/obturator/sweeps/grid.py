"""Sweep axes: parsing ``START:STOP:COUNT`` or ``a,b,c`` (with units) and parameter names.

>>> parse_axis("100:700:4", "spin_rate").tolist()
[100.0, 300.0, 500.0, 700.0]
>>> parse_axis("1000:6000:2 rpm", "spin_rate", unit="rad/s").round(2).tolist()
[104.72, 628.32]
"""

from __future__ import annotations

import math
import re
from typing import Any

import numpy as np

from ..errors import InputError
from ..params import SWEEP_PARAMS

__all__ = ["MAX_POINTS", "parse_value", "parse_axis", "canonical_name", "as_axis"]

#: Largest number of grid points or samples of one study.
MAX_POINTS = 100_000_000


def parse_value(name: str, text: str, what: str, unit: str | None = None) -> float:
    """A number, or with `unit` (pint syntax) also a quantity such as "7.8 g/cm^3"."""
    t = text.strip()
    if unit is not None:
        from ..io import parse_quantity

        try:
            return parse_quantity(name, t, "" if unit == "1" else unit)
        except InputError as exc:
            raise InputError(name, f"{what}: {str(exc).split(': ', 1)[1]}") from None
    try:
        x = float(t)
    except ValueError:
        raise InputError(name, f"{what} {t!r} is not a number") from None
    if not math.isfinite(x):
        raise InputError(name, f"{what} {t!r} must be finite")
    return x


def parse_axis(text: str, name: str = "axis", unit: str | None = None) -> np.ndarray:
    """Parse the values of one sweep axis.

    Parameters
    ----------
    text : str
        ``START:STOP:COUNT`` -- COUNT evenly spaced values from START to STOP,
        both ends included (``numpy.linspace``; the last value is STOP
        exactly); START > STOP gives a decreasing axis. COUNT is a whole
        number >= 1; COUNT = 1 is accepted only with START == STOP (a single
        value is better written as a plain number). Or a comma list
        ``a,b,c`` of distinct values, kept in the given order; a plain number
        is a list of one value.
    name : str
        Parameter name used in error messages (e.g. ``"--spin-rate"``).
    unit : str, optional
        The parameter's unit. When given, every value may carry a unit of its
        own (``"7.8 g/cm^3"``, ``"1000 rpm:6000 rpm:11"``) or a range one unit
        for START and STOP after COUNT (``"1000:6000:11 rpm"``); bare numbers
        are in `unit` (as on the ``simulate`` command line).

    Returns
    -------
    numpy.ndarray
        1-D float array, in the unit of the parameter.

    Raises
    ------
    InputError
        On malformed text, non-finite values, COUNT < 1 or not a whole
        number, repeated values, or a spacing below floating-point resolution.
    """
    if not isinstance(text, str) or not text.strip():
        raise InputError(name, "empty value: expected START:STOP:COUNT or a list a,b,c")
    s = text.strip()
    if ":" in s:
        parts = s.split(":")
        if len(parts) != 3:
            raise InputError(
                name, f"malformed range {s!r}: expected START:STOP:COUNT (e.g. 200:700:20)"
            )
        count_text, _, trailing = parts[2].strip().partition(" ")
        if trailing.strip():
            if unit is None:
                raise InputError(name, f"malformed range {s!r}: units are not accepted here")
            parts = [f"{parts[0]} {trailing}", f"{parts[1]} {trailing}", count_text]
        start = parse_value(name, parts[0], "START", unit)
        stop = parse_value(name, parts[1], "STOP", unit)
        try:
            count = int(parts[2].strip())
        except ValueError:
            raise InputError(
                name, f"malformed range {s!r}: COUNT {parts[2].strip()!r} is not a whole number"
            ) from None
        if count < 1:
            raise InputError(name, f"malformed range {s!r}: COUNT must be >= 1, got {count}")
        if count > MAX_POINTS:
            raise InputError(name, f"COUNT {count} exceeds the limit of {MAX_POINTS} points")
        if count == 1:
            if start != stop:
                raise InputError(
                    name,
                    f"range {s!r} has COUNT = 1 but START != STOP; give a single value instead",
                )
            return np.array([start])
        values = np.linspace(start, stop, count)
    else:
        parts = _unit_after_list(name, s, unit)
        values = np.array([parse_value(name, p, "value", unit) for p in parts], dtype=float)
        if len(np.unique(values)) != len(values):
            raise InputError(name, f"list {s!r} repeats a value")
        return values
    steps = np.diff(values)
    if not (np.all(steps > 0) or np.all(steps < 0)):
        raise InputError(
            name, f"range {s!r}: the {count} values are not distinct in floating point"
        )
    return values


def _unit_after_list(name: str, s: str, unit: str | None) -> list[str]:
    """The values of a list, a unit after the last one applied to every value.

    ``"1000,2000 rpm"`` is 1000 rpm and 2000 rpm; values that each carry a unit
    (``"1 km,500 m"``) stand as written; a list that mixes bare numbers and units
    any other way (``"1000 rpm,2000"``) is refused: it has no single reading.
    """
    parts = [p.strip() for p in s.split(",")]
    has_unit = [bool(p) and not _is_number(p) for p in parts]
    if unit is None or not any(has_unit) or all(has_unit):
        return parts
    if has_unit[-1] and not any(has_unit[:-1]):
        m = re.match(r"^([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(\S.*)$", parts[-1])
        if m is not None:
            return [*(f"{p} {m.group(2)}" for p in parts[:-1]), parts[-1]]
    raise InputError(
        name,
        f"list {s!r} mixes values with and without a unit; write the unit once after "
        "the last value (applies to all) or after every value",
    )


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def canonical_name(text: str) -> str:
    """The parameter name of a flag or key (``--spin-rate``, ``spin-rate`` -> ``spin_rate``)."""
    key = text.strip().lstrip("-").replace("-", "_")
    if key not in SWEEP_PARAMS:
        raise InputError(
            "parameter", f"unknown parameter {text!r}; allowed: {', '.join(SWEEP_PARAMS)}"
        )
    return key


def as_axis(name: str, values: Any) -> np.ndarray:
    """Validated, read-only 1-D axis values (numbers, finite, distinct, at least one)."""
    try:
        arr = np.array(values, dtype=float).reshape(-1) if np.ndim(values) <= 1 else None
    except (TypeError, ValueError):
        raise InputError(name, f"axis values must be numbers, got {values!r}") from None
    if arr is None:
        raise InputError(name, "axis values must be a 1-D sequence")
    if arr.size == 0:
        raise InputError(name, "an axis needs at least one value")
    if not np.all(np.isfinite(arr)):
        raise InputError(name, "axis values must be finite")
    if len(np.unique(arr)) != arr.size:
        raise InputError(name, "axis values must be distinct")
    arr.setflags(write=False)
    return arr
