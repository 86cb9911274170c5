"""Array inputs of the flow relations: range checks that name the offending element
(and the one root finder of their scalar inversions).

Every flow function broadcasts over its array arguments (numpy rules) and
returns a float for scalar input; out-of-domain input raises
:class:`~obturator.errors.InputError` naming the field, the element and the
allowed range. Nothing is clamped.

>>> checked_array("mach", [1.5, 3.0], 1.0).tolist()
[1.5, 3.0]
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError, check_range

__all__ = [
    "MACH_MAX",
    "AREA_RATIO_MAX",
    "GAMMA_DOC",
    "ratio_doc",
    "as_output",
    "bracketed_root",
    "broadcast",
    "check_branch",
    "check_gamma",
    "check_mach",
    "checked_array",
    "elementwise",
    "first_bad",
]

_BRANCHES = ("subsonic", "supersonic")


def checked_array(
    field: str,
    value: ArrayLike,
    lo: float = -math.inf,
    hi: float = math.inf,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    unit: str = "",
) -> NDArray[np.float64]:
    """Return ``value`` as a float array after checking every element's range.

    The array counterpart of :func:`obturator.errors.check_range`: NaN, inf and
    out-of-range elements raise :class:`InputError`, naming the first
    offending element (in C order) and its index. Nothing is clamped.

    Parameters
    ----------
    field : str
        Field name used in the message.
    value : array_like
        Number or array of numbers.
    lo, hi, lo_open, hi_open, unit
        As for :func:`obturator.errors.check_range`.

    Returns
    -------
    numpy.ndarray
        ``value`` as float64 (0-d for a scalar).

    Notes
    -----
    A Python or NumPy float is checked by :func:`~obturator.errors.check_range` instead
    of NumPy's masked reductions: the same test and the same error, without the
    array machinery, which dominated the scalar inversions that call the relations
    inside root searches (the flight-envelope study's start condition per segment).
    """
    if isinstance(value, float):
        return np.array(
            check_range(field, value, lo, hi, lo_open=lo_open, hi_open=hi_open, unit=unit)
        )
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(field, f"expected a number or array of numbers, got {value!r}") from None
    with np.errstate(invalid="ignore"):
        above = arr > lo if lo_open else arr >= lo
        below = arr < hi if hi_open else arr <= hi
        ok = np.isfinite(arr) & above & below
    if not np.all(ok):
        index = tuple(int(i) for i in np.argwhere(~ok)[0])
        bad = float(arr[index])
        try:
            check_range(field, bad, lo, hi, lo_open=lo_open, hi_open=hi_open, unit=unit)
        except InputError as exc:
            if arr.ndim == 0:
                raise
            reason = str(exc)[len(field) + 2 :]
            where = ", ".join(str(i) for i in index)
            raise InputError(field, f"element [{where}]: {reason}") from None
    return arr


def as_output(x: Any) -> Any:
    """Return a Python float for 0-d results, the array otherwise."""
    x = np.asarray(x, dtype=float)
    return float(x) if x.ndim == 0 else x


#: Largest Mach number accepted [-]. The perfect-gas relations are physically
#: meaningless long before (real-gas effects above M ~ 6); at 1e6 every ratio is
#: at its M -> infinity limit to ~1e-12, and far above it M^2 overflows.
MACH_MAX = 1e6
#: Largest area ratio A/A* accepted [-] (a projectile's
#: capture-to-throat ratio is of order 1-10). Far above it the inversion overflows.
AREA_RATIO_MAX = 1e100


#: Docstring text of the ``gamma`` argument of every flow relation
#: (:func:`obturator._docs.fill_doc`).
GAMMA_DOC = """\
gamma : array_like, optional
    Ratio of specific heats, > 1."""


def ratio_doc(*arguments: str) -> str:
    """Parameters and return type of a relation of (``*arguments``, gamma), as docstring text."""
    params = "\n".join((*arguments, GAMMA_DOC))
    return f"Parameters\n----------\n{params}\n\nReturns\n-------\nfloat or numpy.ndarray"


def check_mach(value: ArrayLike, *, supersonic: bool = False, field: str = "mach") -> NDArray:
    """Mach numbers in (0, MACH_MAX], or [1, MACH_MAX] when `supersonic`."""
    if supersonic:
        return checked_array(field, value, 1.0, MACH_MAX)
    return checked_array(field, value, 0.0, MACH_MAX, lo_open=True)


def check_gamma(value: ArrayLike) -> NDArray:
    """Ratios of specific heats gamma > 1."""
    return checked_array("gamma", value, 1.0, lo_open=True)


def broadcast(**named: NDArray) -> list[NDArray]:
    """The arrays broadcast together, or an InputError naming their shapes."""
    try:
        return list(np.broadcast_arrays(*named.values()))
    except ValueError:
        shapes = ", ".join(f"{k}{np.shape(v)}" for k, v in named.items())
        raise InputError(next(iter(named)), f"shapes do not broadcast: {shapes}") from None


def first_bad(bad: NDArray) -> tuple[tuple[int, ...], str]:
    """Index of the first True in ``bad`` and a message prefix naming it for arrays."""
    index = tuple(int(k) for k in np.argwhere(bad)[0])
    prefix = f"element [{', '.join(map(str, index))}]: " if bad.ndim else ""
    return index, prefix


def check_branch(branch: str) -> str:
    """``"subsonic"`` or ``"supersonic"``."""
    if branch not in _BRANCHES:
        raise InputError("branch", f"{branch!r} is not one of {', '.join(_BRANCHES)}")
    return branch


def elementwise(f: Callable[..., float], *arrays: NDArray) -> Any:
    """`f` of each element of the broadcast `arrays`, as :func:`as_output` gives it.

    The scalar inversions are Python functions of floats; ``np.vectorize`` would call them
    the same way, but costs more than the inversion itself on one element, so 0-d input
    calls `f` directly (the flight studies invert one Mach number per segment).
    """
    if all(a.ndim == 0 for a in arrays):
        return float(f(*(float(a) for a in arrays)))
    return as_output(np.vectorize(f, otypes=[float])(*arrays))


def bracketed_root(f: Callable[[float], float], lo: float, hi: float, xtol: float) -> float:
    """The root of `f` in [lo, hi] (a sign change) by scipy's ``brentq``, to `xtol` and
    4 ulp relative.

    scipy.optimize is imported on the first call, not with the package: its import
    would join every command's start-up, and most runs never invert a flow relation
    (scipy.integrate is deferred likewise; import costs: ``docs/benchmarks.md``).
    """
    from scipy.optimize import brentq

    return float(brentq(f, lo, hi, xtol=xtol, rtol=4 * np.finfo(float).eps))
