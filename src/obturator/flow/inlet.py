"""Isentropic area ratio A/A* and the Kantrowitz-Donaldson start/unstart limits of a
capture-to-throat contraction A_c/A_t (thesis Eqs. 2 and 4).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .._docs import fill_doc
from ..errors import InputError
from ._arrays import (
    AREA_RATIO_MAX,
    as_output,
    bracketed_root,
    broadcast,
    check_branch,
    check_gamma,
    check_mach,
    checked_array,
    elementwise,
    first_bad,
    ratio_doc,
)
from .shock import normal_shock_mach

__all__ = [
    "area_ratio",
    "mach_from_area_ratio",
    "swallow_area_ratio",
    "regurgitate_area_ratio",
    "swallow_area_ratio_limit",
    "start_mach",
    "unstart_mach",
]

_FLIGHT = ratio_doc("mach : array_like\n    Flight Mach number M_1 >= 1.")


def _area_ratio_raw(m: Any, g: Any) -> Any:
    expo = (g + 1.0) / (2.0 * (g - 1.0))
    return (2.0 / (g + 1.0) * (1.0 + 0.5 * (g - 1.0) * m * m)) ** expo / m


def area_ratio(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Isentropic area ratio A/A* at Mach ``mach``.

    A/A* = (1/M) [2/(gamma+1) (1 + (gamma-1)/2 M^2)]^((gamma+1)/(2(gamma-1)))

    the right-hand side of thesis Eqs. 2 and 4.

    Parameters
    ----------
    mach : array_like
        Mach number M > 0.
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        A/A* >= 1 (1 at M = 1).
    """
    return as_output(_area_ratio_raw(check_mach(mach), check_gamma(gamma)))


def _mach_from_area_ratio_scalar(ratio: float, g: float, branch: str) -> float:
    if ratio == 1.0:
        return 1.0

    def resid(m: float) -> float:
        try:
            return _area_ratio_raw(m, g) - ratio
        except OverflowError:  # gamma near 1: A/A* grows like exp(M^2); past any ratio
            return math.inf

    if branch == "subsonic":
        # A/A* > (1/M) (2/(gamma+1))^k for every M, so this M already overshoots.
        lo = 0.5 * (2.0 / (g + 1.0)) ** ((g + 1.0) / (2.0 * (g - 1.0))) / ratio
        return bracketed_root(resid, lo, 1.0, 1e-15)
    hi = 2.0
    while resid(hi) < 0.0:
        hi *= 2.0
    return bracketed_root(resid, 1.0, hi, 1e-15)


def mach_from_area_ratio(
    ratio: ArrayLike, gamma: ArrayLike = 1.4, branch: str = "supersonic"
) -> Any:
    """Inverse of :func:`area_ratio` on one branch (scipy ``brentq``).

    Parameters
    ----------
    ratio : array_like
        Area ratio A/A* >= 1.
    gamma : array_like, optional
        Ratio of specific heats, > 1.
    branch : {"supersonic", "subsonic"}
        Which of the two Mach numbers with that area ratio.

    Returns
    -------
    float or numpy.ndarray
        Mach number (>= 1 supersonic, <= 1 subsonic; 1 for ratio 1).
    """
    r = checked_array("area_ratio", ratio, 1.0, AREA_RATIO_MAX)
    g = check_gamma(gamma)
    b = check_branch(branch)
    r, g = broadcast(area_ratio=r, gamma=g)
    return elementwise(lambda x, y: _mach_from_area_ratio_scalar(x, y, b), r, g)


@fill_doc(params=_FLIGHT)
def swallow_area_ratio(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Largest A_c/A_t that swallows the bow shock at flight Mach M_1 (thesis Eq. 2).

    Kantrowitz-Donaldson: with the normal shock at the capture plane the
    throat must pass the post-shock flow at M = 1, so A_c/A_t = A/A*(M_2)
    with M_2 from Eq. 3 (equivalently A/A*(M_1) p_02/p_01).

    {params}
        A_c/A_t; rises from 1 at M_1 = 1 towards :func:`swallow_area_ratio_limit`.
    """
    return area_ratio(normal_shock_mach(mach, gamma), gamma)


@fill_doc(params=_FLIGHT)
def regurgitate_area_ratio(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """A_c/A_t at which a started inlet regurgitates its shock (unstarts) at M_1 (Eq. 4).

    Isentropic contraction limit A_c/A_t = A/A*(M_1): below the Mach number
    where this equals the geometric ratio the throat can no longer pass the
    captured flow shock-free.

    {params}
        A_c/A_t >= 1.
    """
    return area_ratio(check_mach(mach, supersonic=True), gamma)


@fill_doc(params=ratio_doc())
def swallow_area_ratio_limit(gamma: ArrayLike = 1.4) -> Any:
    """Limit of Eq. 2 as M_1 -> infinity: A/A* at M_2 = sqrt((gamma-1)/(2 gamma)).

    About 1.6661 for gamma = 1.4; a contraction at or above it never self-starts.

    {params}
        Supremum of :func:`swallow_area_ratio` over M_1.
    """
    g = check_gamma(gamma)
    return as_output(_area_ratio_raw(np.sqrt((g - 1.0) / (2.0 * g)), g))


def start_mach(ratio: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Flight Mach number above which A_c/A_t self-starts (inverse of thesis Eq. 2).

    M_2 is the subsonic root of A/A*(M_2) = A_c/A_t; M_1 then follows from
    Eq. 3 read backwards (the normal-shock relation is its own inverse).
    A_c/A_t = 1, the constant-area bore, gives M_1 = 1: in this frictionless,
    perfect-throat limit it starts at any supersonic Mach. With wall friction between
    lip and throat and a discharge coefficient it does not
    (:mod:`obturator.flow.start_friction`).

    Parameters
    ----------
    ratio : array_like
        Capture-to-throat area ratio A_c/A_t, in [1, limit) with the limit
        from :func:`swallow_area_ratio_limit` (1.6661 for gamma = 1.4).
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        Self-starting Mach number M_1 >= 1.

    Raises
    ------
    InputError
        If the ratio is at or above the limit: no flight Mach swallows the shock.
    """
    r = checked_array("area_ratio", ratio, 1.0)
    g = check_gamma(gamma)
    r, g = broadcast(area_ratio=r, gamma=g)
    limit = _area_ratio_raw(np.sqrt((g - 1.0) / (2.0 * g)), g)
    bad = r >= limit
    if np.any(bad):
        i, where = first_bad(bad)
        raise InputError(
            "area_ratio",
            f"{where}{r[i]:g} never self-starts: Eq. 2 requires A_c/A_t < {limit[i]:.6g} "
            f"(its limit as M_1 -> infinity for gamma = {g[i]:g}); allowed range "
            f"[1, {limit[i]:.6g})",
        )
    m2 = np.asarray(mach_from_area_ratio(r, g, "subsonic"))
    with np.errstate(divide="ignore"):
        m1sq = (2.0 / (g - 1.0) + m2 * m2) / (2.0 * g / (g - 1.0) * m2 * m2 - 1.0)
    return as_output(np.sqrt(m1sq))


def unstart_mach(ratio: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Flight Mach number below which a started A_c/A_t unstarts (inverse of thesis Eq. 4).

    The supersonic root of A/A*(M_1) = A_c/A_t. Between :func:`unstart_mach`
    and :func:`start_mach` the inlet's state depends on its history.

    Parameters
    ----------
    ratio : array_like
        Capture-to-throat area ratio A_c/A_t >= 1.
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        Unstart Mach number M_1 >= 1 (1 for the constant-area bore).
    """
    return mach_from_area_ratio(ratio, gamma, "supersonic")
