"""Compressible flow of the tubular projectile's bore (thesis chapter I.B.4).

Perfect gas with constant specific heats, one-dimensional flow:

* normal shock (thesis Eqs. 1 and 3) and the pressure force that the bow shock
  puts on the closed obturator, F_p = pi r_p^2 (P_2 - P_1) (Eq. 43);
* isentropic area ratio A/A* and the Kantrowitz-Donaldson start/unstart
  limits of a capture-to-throat contraction A_c/A_t (Eqs. 2 and 4);
* Fanno flow (adiabatic, constant area, wall friction) for the choking of the
  open bore, with Darcy friction factors from Colebrook or Haaland.

The closed forms are written out by hand from the textbook relations (NACA
Report 1135; Shapiro 1953). pygasflow would provide them, but it pulls in
bokeh and panel for plotting, far too heavy a dependency for a few formulas.

Conventions: ``gamma`` is c_p/c_v; friction factors are Darcy factors,
f_D = 4 f_Fanning, which is what the thesis's f L/D = 0.102 means (Fanning
would give M ~ 1.17). All functions broadcast over their array arguments
(numpy rules): scalars in give floats out. Out-of-domain input raises
:class:`~obturator.errors.InputError` naming the field and the allowed range;
nothing is clamped.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from .atmosphere import MAX_ALTITUDE, as_output, checked_array, standard_atmosphere
from ..errors import InputError, check_range

__all__ = [
    "THESIS_REYNOLDS",
    "THESIS_REYNOLDS_MACH",
    "ChokingStep",
    "NormalShock",
    "area_ratio",
    "choking_history",
    "choking_mach",
    "choking_mach_freestream",
    "colebrook_friction_factor",
    "fanno_fld",
    "fanno_fld_limit",
    "fanno_mach",
    "flight_pressure_force",
    "freestream_reynolds",
    "friction_factor",
    "haaland_friction_factor",
    "mach_from_area_ratio",
    "normal_shock",
    "normal_shock_density_ratio",
    "normal_shock_mach",
    "normal_shock_pressure_ratio",
    "normal_shock_stagnation_pressure_ratio",
    "normal_shock_temperature_ratio",
    "pressure_force",
    "regurgitate_area_ratio",
    "start_mach",
    "swallow_area_ratio",
    "swallow_area_ratio_limit",
    "unstart_mach",
]

#: Midpoint of the thesis's bore Reynolds-number range 4e5..6e5 (chapter I.B.4.c).
THESIS_REYNOLDS = 5.0e5
#: Flight Mach number at which :data:`THESIS_REYNOLDS` is taken to hold; see
#: :func:`choking_history` for why 2.5.
THESIS_REYNOLDS_MACH = 2.5

#: Lowest Reynolds number accepted by the turbulent friction correlations.
_RE_TURBULENT = 2300.0
#: Largest relative roughness eps/D on the Moody chart.
_MAX_ROUGHNESS = 0.05
_BRANCHES = ("subsonic", "supersonic")
_CORRELATIONS = ("colebrook", "haaland")


# ---------------------------------------------------------------------------
# input handling


#: Largest Mach number accepted [-]. The perfect-gas relations are physically
#: meaningless long before (real-gas effects above M ~ 6); at 1e6 every ratio is
#: at its M -> infinity limit to ~1e-12, and far above it M^2 overflows.
MACH_MAX = 1e6
#: Largest area ratio A/A* accepted [-] (a projectile's
#: capture-to-throat ratio is of order 1-10). Far above it the inversion overflows.
AREA_RATIO_MAX = 1e100


def _mach(value: ArrayLike, *, supersonic: bool = False, field: str = "mach") -> NDArray:
    if supersonic:
        return checked_array(field, value, 1.0, MACH_MAX)
    return checked_array(field, value, 0.0, MACH_MAX, lo_open=True)


def _gamma(value: ArrayLike) -> NDArray:
    return checked_array("gamma", value, 1.0, lo_open=True)


def _broadcast(**named: NDArray) -> list[NDArray]:
    try:
        return list(np.broadcast_arrays(*named.values()))
    except ValueError:
        shapes = ", ".join(f"{k}{np.shape(v)}" for k, v in named.items())
        raise InputError(next(iter(named)), f"shapes do not broadcast: {shapes}") from None


def _first_bad(bad: NDArray) -> tuple[tuple[int, ...], str]:
    """Index of the first True in ``bad`` and a message prefix naming it for arrays."""
    index = tuple(int(k) for k in np.argwhere(bad)[0])
    prefix = f"element [{', '.join(map(str, index))}]: " if bad.ndim else ""
    return index, prefix


def _branch(branch: str) -> str:
    if branch not in _BRANCHES:
        raise InputError("branch", f"{branch!r} is not one of {', '.join(_BRANCHES)}")
    return branch


# ---------------------------------------------------------------------------
# normal shock (thesis Eqs. 1 and 3)


def normal_shock_mach(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Mach number M_2 behind a normal shock (thesis Eq. 3).

    M_2^2 = (2/(gamma-1) + M_1^2) / (2 gamma/(gamma-1) M_1^2 - 1)

    Parameters
    ----------
    mach : array_like
        Upstream Mach number M_1 >= 1.
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        Downstream Mach number M_2 <= 1.
    """
    m, g = _mach(mach, supersonic=True), _gamma(gamma)
    m2 = (2.0 / (g - 1.0) + m * m) / (2.0 * g / (g - 1.0) * m * m - 1.0)
    return as_output(np.sqrt(m2))


def normal_shock_pressure_ratio(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Static-pressure ratio P_2/P_1 across a normal shock (thesis Eq. 1).

    Eq. 1, (1 + gamma M_1^2)/(1 + gamma M_2^2) with M_2 from Eq. 3, reduces to
    1 + 2 gamma/(gamma+1) (M_1^2 - 1), evaluated here.

    Parameters
    ----------
    mach : array_like
        Upstream Mach number M_1 >= 1.
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        P_2/P_1 >= 1.
    """
    m, g = _mach(mach, supersonic=True), _gamma(gamma)
    return as_output(1.0 + 2.0 * g / (g + 1.0) * (m * m - 1.0))


def normal_shock_density_ratio(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Density ratio rho_2/rho_1 = u_1/u_2 across a normal shock.

    rho_2/rho_1 = (gamma+1) M_1^2 / ((gamma-1) M_1^2 + 2)

    Parameters
    ----------
    mach : array_like
        Upstream Mach number M_1 >= 1.
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        rho_2/rho_1, between 1 and (gamma+1)/(gamma-1).
    """
    m, g = _mach(mach, supersonic=True), _gamma(gamma)
    return as_output((g + 1.0) * m * m / ((g - 1.0) * m * m + 2.0))


def normal_shock_temperature_ratio(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Static-temperature ratio T_2/T_1 = (P_2/P_1)/(rho_2/rho_1) across a normal shock.

    Parameters
    ----------
    mach : array_like
        Upstream Mach number M_1 >= 1.
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        T_2/T_1 >= 1.
    """
    return as_output(
        np.asarray(normal_shock_pressure_ratio(mach, gamma))
        / np.asarray(normal_shock_density_ratio(mach, gamma))
    )


def normal_shock_stagnation_pressure_ratio(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Stagnation-pressure ratio p_02/p_01 across a normal shock.

    p_02/p_01 = (rho_2/rho_1)^(gamma/(gamma-1)) (P_2/P_1)^(-1/(gamma-1)),
    from the isentropic relation on each side with T_0 conserved.

    Parameters
    ----------
    mach : array_like
        Upstream Mach number M_1 >= 1.
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        p_02/p_01 <= 1 (the entropy rise across the shock).
    """
    g = _gamma(gamma)
    rho = np.asarray(normal_shock_density_ratio(mach, gamma))
    p = np.asarray(normal_shock_pressure_ratio(mach, gamma))
    # Logs keep the powers finite at large M_1 and gamma close to 1.
    return as_output(np.exp((g * np.log(rho) - np.log(p)) / (g - 1.0)))


@dataclass(frozen=True)
class NormalShock:
    """All normal-shock ratios for upstream Mach ``mach`` (floats or arrays).

    Attributes
    ----------
    mach, gamma : float or numpy.ndarray
        Upstream Mach number M_1 and ratio of specific heats.
    mach2 : float or numpy.ndarray
        Downstream Mach number M_2 (Eq. 3).
    pressure_ratio, density_ratio, temperature_ratio : float or numpy.ndarray
        P_2/P_1 (Eq. 1), rho_2/rho_1, T_2/T_1.
    stagnation_pressure_ratio : float or numpy.ndarray
        p_02/p_01.
    """

    mach: Any
    gamma: Any
    mach2: Any
    pressure_ratio: Any
    density_ratio: Any
    temperature_ratio: Any
    stagnation_pressure_ratio: Any


def normal_shock(mach: ArrayLike, gamma: ArrayLike = 1.4) -> NormalShock:
    """Normal-shock state behind upstream Mach ``mach`` (thesis Eqs. 1 and 3).

    Parameters
    ----------
    mach : array_like
        Upstream Mach number M_1 >= 1.
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    NormalShock
    """
    m, g = _broadcast(mach=_mach(mach, supersonic=True), gamma=_gamma(gamma))
    return NormalShock(
        mach=as_output(m),
        gamma=as_output(g),
        mach2=normal_shock_mach(m, g),
        pressure_ratio=normal_shock_pressure_ratio(m, g),
        density_ratio=normal_shock_density_ratio(m, g),
        temperature_ratio=normal_shock_temperature_ratio(m, g),
        stagnation_pressure_ratio=normal_shock_stagnation_pressure_ratio(m, g),
    )


def pressure_force(
    mach: ArrayLike, p1: ArrayLike, bore_radius: ArrayLike, gamma: ArrayLike = 1.4
) -> Any:
    """Bow-shock pressure force on the closed obturator (thesis Eq. 43).

    F_p = pi r_p^2 (P_2 - P_1), with P_2/P_1 from Eq. 1. The thesis writes
    Delta P = P_1 - P_2 (Eq. 44) but uses its magnitude; the force pushes the
    ball aft into its socket, and is returned positive.

    Parameters
    ----------
    mach : array_like
        Flight Mach number M_1 >= 1.
    p1 : array_like
        Free-stream static pressure P_1 [Pa], > 0.
    bore_radius : array_like
        Radius r_p of the hole through the projectile [m], > 0.
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        F_p [N]. Table 1 (M_1 = 3, P_1 = 0.099 MPa, r_p = 4.72 mm) gives 64.6 N.
    """
    p = checked_array("p1", p1, 0.0, lo_open=True, unit="Pa")
    r = checked_array("bore_radius", bore_radius, 0.0, lo_open=True, unit="m")
    ratio = np.asarray(normal_shock_pressure_ratio(mach, gamma))
    _broadcast(mach=ratio, p1=p, bore_radius=r)
    return as_output(math.pi * r * r * p * (ratio - 1.0))


def flight_pressure_force(
    mach: ArrayLike,
    *,
    altitude_m: ArrayLike | None = None,
    p1: ArrayLike | None = None,
    bore_radius: ArrayLike,
    gamma: ArrayLike = 1.4,
) -> Any:
    """Pressure force F_p [N] in flight, P_1 given directly or by altitude.

    Parameters
    ----------
    mach : array_like
        Flight Mach number M_1 >= 1.
    altitude_m : array_like, optional
        Geometric altitude [m] in [0, 86 000]; P_1 is the 1976 standard
        atmosphere's pressure there. Exactly one of `altitude_m`, `p1`.
    p1 : array_like, optional
        Free-stream static pressure [Pa], > 0.
    bore_radius : array_like
        Bore radius r_p [m], > 0.
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        F_p = pi r_p^2 (P_2 - P_1) [N] (thesis Eq. 43).
    """
    if (altitude_m is None) == (p1 is None):
        raise InputError("altitude_m", "give exactly one of altitude_m [m] and p1 [Pa]")
    if altitude_m is not None:
        p1 = standard_atmosphere(altitude_m).pressure
    return pressure_force(mach, p1, bore_radius, gamma)


# ---------------------------------------------------------------------------
# isentropic area ratio and Kantrowitz-Donaldson (thesis Eqs. 2 and 4)


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
    return as_output(_area_ratio_raw(_mach(mach), _gamma(gamma)))


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
        return brentq(resid, lo, 1.0, xtol=1e-15, rtol=4 * np.finfo(float).eps)
    hi = 2.0
    while resid(hi) < 0.0:
        hi *= 2.0
    return brentq(resid, 1.0, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps)


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
    g = _gamma(gamma)
    b = _branch(branch)
    r, g = _broadcast(area_ratio=r, gamma=g)
    solve = np.vectorize(lambda x, y: _mach_from_area_ratio_scalar(x, y, b), otypes=[float])
    return as_output(solve(r, g))


def swallow_area_ratio(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Largest A_c/A_t that swallows the bow shock at flight Mach M_1 (thesis Eq. 2).

    Kantrowitz-Donaldson: with the normal shock at the capture plane the
    throat must pass the post-shock flow at M = 1, so A_c/A_t = A/A*(M_2)
    with M_2 from Eq. 3 (equivalently A/A*(M_1) p_02/p_01).

    Parameters
    ----------
    mach : array_like
        Flight Mach number M_1 >= 1.
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        A_c/A_t; rises from 1 at M_1 = 1 towards :func:`swallow_area_ratio_limit`.
    """
    return area_ratio(normal_shock_mach(mach, gamma), gamma)


def regurgitate_area_ratio(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """A_c/A_t at which a started inlet regurgitates its shock (unstarts) at M_1 (Eq. 4).

    Isentropic contraction limit A_c/A_t = A/A*(M_1): below the Mach number
    where this equals the geometric ratio the throat can no longer pass the
    captured flow shock-free.

    Parameters
    ----------
    mach : array_like
        Flight Mach number M_1 >= 1.
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        A_c/A_t >= 1.
    """
    return area_ratio(_mach(mach, supersonic=True), gamma)


def swallow_area_ratio_limit(gamma: ArrayLike = 1.4) -> Any:
    """Limit of Eq. 2 as M_1 -> infinity: A/A* at M_2 = sqrt((gamma-1)/(2 gamma)).

    About 1.6661 for gamma = 1.4; a contraction at or above it never self-starts.

    Parameters
    ----------
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        Supremum of :func:`swallow_area_ratio` over M_1.
    """
    g = _gamma(gamma)
    return as_output(_area_ratio_raw(np.sqrt((g - 1.0) / (2.0 * g)), g))


def start_mach(ratio: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Flight Mach number above which A_c/A_t self-starts (inverse of thesis Eq. 2).

    M_2 is the subsonic root of A/A*(M_2) = A_c/A_t; M_1 then follows from
    Eq. 3 read backwards (the normal-shock relation is its own inverse).
    A_c/A_t = 1, the constant-area bore, starts at any supersonic Mach (M_1 = 1).

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
    g = _gamma(gamma)
    r, g = _broadcast(area_ratio=r, gamma=g)
    limit = _area_ratio_raw(np.sqrt((g - 1.0) / (2.0 * g)), g)
    bad = r >= limit
    if np.any(bad):
        i, where = _first_bad(bad)
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


# ---------------------------------------------------------------------------
# Fanno flow and friction factor (thesis chapter I.B.4.c)


def _fanno_raw(m: Any, g: Any) -> Any:
    msq = m * m
    return (1.0 - msq) / (g * msq) + (g + 1.0) / (2.0 * g) * np.log(
        (g + 1.0) * msq / (2.0 + (g - 1.0) * msq)
    )


def fanno_fld(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Fanno choking length f_D L*/D of a constant-area duct entered at Mach ``mach``.

    f_D L*/D = (1 - M^2)/(gamma M^2)
               + (gamma+1)/(2 gamma) ln[(gamma+1) M^2 / (2 + (gamma-1) M^2)]

    with the Darcy factor f_D = 4 f_Fanning (tables list it as 4 f L*/D).
    A duct longer than L* chokes.

    Parameters
    ----------
    mach : array_like
        Entry Mach number M > 0.
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        f_D L*/D >= 0 (0 at M = 1).
    """
    return as_output(_fanno_raw(_mach(mach), _gamma(gamma)))


def fanno_fld_limit(gamma: ArrayLike = 1.4) -> Any:
    """Supremum of f_D L*/D on the supersonic branch (M -> infinity).

    (gamma+1)/(2 gamma) ln((gamma+1)/(gamma-1)) - 1/gamma, 0.8215 for gamma = 1.4.

    Parameters
    ----------
    gamma : array_like, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    float or numpy.ndarray
        Limit of f_D L*/D.
    """
    g = _gamma(gamma)
    return as_output((g + 1.0) / (2.0 * g) * np.log((g + 1.0) / (g - 1.0)) - 1.0 / g)


def _fanno_mach_scalar(fld: float, g: float, branch: str) -> float:
    if fld == 0.0:
        return 1.0

    def resid(m: float) -> float:
        return float(_fanno_raw(m, g)) - fld

    if branch == "subsonic":
        lo = 0.5
        while resid(lo) < 0.0:
            lo *= 0.5
        return brentq(resid, lo, 1.0, xtol=1e-15, rtol=4 * np.finfo(float).eps)
    hi = 2.0
    while resid(hi) < 0.0:
        hi *= 2.0
        if hi > 1e12:  # pragma: no cover - excluded by the range check
            raise InputError("fld", f"{fld:g} is too close to the supersonic limit")
    return brentq(resid, 1.0, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps)


def fanno_mach(fld: ArrayLike, gamma: ArrayLike = 1.4, branch: str = "supersonic") -> Any:
    """Entry Mach number whose Fanno choking length is f_D L*/D = ``fld``.

    For a duct of given f_D L/D this is the entry Mach at which it just chokes:
    on the supersonic branch, the flight Mach below which the bore chokes.

    Parameters
    ----------
    fld : array_like
        f_D L/D >= 0 (Darcy factor). On the supersonic branch it must be below
        :func:`fanno_fld_limit` (0.8215 for gamma = 1.4): a longer duct chokes
        at every supersonic entry Mach.
    gamma : array_like, optional
        Ratio of specific heats, > 1.
    branch : {"supersonic", "subsonic"}
        Which root.

    Returns
    -------
    float or numpy.ndarray
        Entry Mach number (1 for fld = 0).

    Examples
    --------
    The thesis's f L/D = 0.102 (chapter I.B.4.c):

    >>> round(fanno_mach(0.102), 3)
    1.406
    """
    b = _branch(branch)
    x = checked_array("fld", fld, 0.0)
    g = _gamma(gamma)
    x, g = _broadcast(fld=x, gamma=g)
    if b == "supersonic":
        limit = (g + 1.0) / (2.0 * g) * np.log((g + 1.0) / (g - 1.0)) - 1.0 / g
        bad = x >= limit
        if np.any(bad):
            i, where = _first_bad(bad)
            raise InputError(
                "fld",
                f"{where}{x[i]:g} exceeds the supersonic Fanno limit: the duct chokes at every "
                f"supersonic entry Mach; allowed range [0, {limit[i]:.6g}) for "
                f"gamma = {g[i]:g}",
            )
    solve = np.vectorize(lambda a, c: _fanno_mach_scalar(a, c, b), otypes=[float])
    return as_output(solve(x, g))


def _check_reynolds(reynolds: ArrayLike) -> NDArray:
    # The correlations are for turbulent pipe flow; below transition they are wrong.
    return checked_array("reynolds", reynolds, _RE_TURBULENT)


def _check_roughness(relative_roughness: ArrayLike) -> NDArray:
    return checked_array("relative_roughness", relative_roughness, 0.0, _MAX_ROUGHNESS)


def _colebrook_scalar(re: float, eps: float) -> float:
    # Colebrook in s = 1/sqrt(f): s + 2 log10(eps/3.7 + 2.51 s/Re) = 0, increasing
    # in s; s in [1, 1000] spans f from 1e-6 to 1, wider than the Moody chart.
    def resid(s: float) -> float:
        return s + 2.0 * math.log10(eps / 3.7 + 2.51 * s / re)

    s = brentq(resid, 1.0, 1000.0, xtol=1e-14, rtol=4 * np.finfo(float).eps)
    return 1.0 / (s * s)


def colebrook_friction_factor(reynolds: ArrayLike, relative_roughness: ArrayLike = 0.0) -> Any:
    """Darcy friction factor from the Colebrook-White equation (solved with ``brentq``).

    1/sqrt(f) = -2 log10(eps/(3.7 D) + 2.51/(Re sqrt(f)))

    Parameters
    ----------
    reynolds : array_like
        Reynolds number based on diameter, >= 2300 (turbulent correlation).
    relative_roughness : array_like, optional
        eps/D in [0, 0.05]; 0 is a hydraulically smooth pipe.

    Returns
    -------
    float or numpy.ndarray
        Darcy friction factor f_D.
    """
    re, eps = _broadcast(
        reynolds=_check_reynolds(reynolds), relative_roughness=_check_roughness(relative_roughness)
    )
    return as_output(np.vectorize(_colebrook_scalar, otypes=[float])(re, eps))


def haaland_friction_factor(reynolds: ArrayLike, relative_roughness: ArrayLike = 0.0) -> Any:
    """Darcy friction factor from Haaland's explicit formula (within ~2 % of Colebrook).

    1/sqrt(f) = -1.8 log10[(eps/(3.7 D))^1.11 + 6.9/Re]

    Parameters
    ----------
    reynolds : array_like
        Reynolds number based on diameter, >= 2300.
    relative_roughness : array_like, optional
        eps/D in [0, 0.05].

    Returns
    -------
    float or numpy.ndarray
        Darcy friction factor f_D.
    """
    re, eps = _broadcast(
        reynolds=_check_reynolds(reynolds), relative_roughness=_check_roughness(relative_roughness)
    )
    s = -1.8 * np.log10((eps / 3.7) ** 1.11 + 6.9 / re)
    return as_output(1.0 / (s * s))


def friction_factor(
    reynolds: ArrayLike, relative_roughness: ArrayLike = 0.0, correlation: str = "colebrook"
) -> Any:
    """Darcy friction factor of turbulent pipe flow by the named correlation.

    Parameters
    ----------
    reynolds : array_like
        Reynolds number based on diameter, >= 2300.
    relative_roughness : array_like, optional
        eps/D in [0, 0.05]; 0 (smooth) by default.
    correlation : {"colebrook", "haaland"}
        Which correlation.

    Returns
    -------
    float or numpy.ndarray
        Darcy friction factor f_D.
    """
    return _friction(reynolds, relative_roughness, correlation)


def _friction(reynolds: ArrayLike, relative_roughness: ArrayLike, correlation: str) -> Any:
    # Module-level alias: choking_history has a parameter named friction_factor.
    if correlation == "colebrook":
        return colebrook_friction_factor(reynolds, relative_roughness)
    if correlation == "haaland":
        return haaland_friction_factor(reynolds, relative_roughness)
    raise InputError("correlation", f"{correlation!r} is not one of {', '.join(_CORRELATIONS)}")


@dataclass(frozen=True)
class ChokingStep:
    """One pass of the thesis's friction-factor iteration.

    Attributes
    ----------
    iteration : int
        0 for the first estimate.
    reynolds : float
        Bore Reynolds number used for the friction factor.
    friction_factor : float
        Darcy friction factor f_D.
    fld : float
        f_D L/D.
    mach : float
        Choking (entry = flight) Mach number from the Fanno relation.
    """

    iteration: int
    reynolds: float
    friction_factor: float
    fld: float
    mach: float


def _choke_from_f(f: float, l_over_d: float, gamma: float) -> float:
    fld = f * l_over_d
    limit = float(fanno_fld_limit(gamma))
    if fld >= limit:
        raise InputError(
            "l_over_d",
            f"f L/D = {fld:.4g} (f = {f:.4g}, L/D = {l_over_d:g}) reaches the supersonic "
            f"Fanno limit {limit:.4g}: the bore chokes at every supersonic Mach; "
            f"allowed range (0, {limit / f:.4g})",
        )
    return float(fanno_mach(fld, gamma))


def choking_history(
    l_over_d: float,
    reynolds: float | None = None,
    *,
    reynolds_mach: float = THESIS_REYNOLDS_MACH,
    friction_factor: float | None = None,
    iterations: int = 1,
    relative_roughness: float = 0.0,
    correlation: str = "colebrook",
    gamma: float = 1.4,
) -> tuple[ChokingStep, ...]:
    """The thesis's choking-Mach iteration for the open bore, step by step.

    Step 0: f_D from the Reynolds number, f_D L/D, choking Mach from the
    supersonic Fanno branch (:func:`fanno_mach`). Each further step revises
    the Reynolds number to the choking Mach just found and repeats.

    How Re is revised: Re = rho V D / mu with rho and mu the free-stream static
    values, which do not change while the projectile decelerates at a given
    altitude, and V = M a. The flow enters the constant-area bore without a
    shock (the sharp lip makes only weak waves), so the bore Re at the choking
    condition is the free-stream one at the choking Mach:

        Re(M) = reynolds * M / reynolds_mach.

    The thesis does not say at which Mach its 4e5..6e5 holds. Its end points
    are in the ratio 3:2, which is what Re proportional to M gives over flight
    Mach 2..3 (Re/M = 2e5; sea level with D = 9.44 mm gives 2.2e5), so the
    midpoint 5e5 is taken at ``reynolds_mach`` = 2.5. This gives 1.42 then
    1.45 for L/D = 8.07 (the thesis: 1.41 then 1.44).

    Parameters
    ----------
    l_over_d : float
        Bore length over diameter, > 0 (Table 1: 76.2 / 9.44 = 8.07).
    reynolds : float, optional
        Bore Reynolds number at Mach `reynolds_mach`, >= 2300; default
        :data:`THESIS_REYNOLDS` (5e5).
    reynolds_mach : float, optional
        Flight Mach at which `reynolds` holds, > 0; default 2.5.
    friction_factor : float, optional
        Use this Darcy f in step 0 instead of the correlation (the thesis read
        0.01275 off a chart); later steps use the correlation.
    iterations : int, optional
        Number of revisions after step 0, in [0, 1000].
    relative_roughness : float, optional
        eps/D in [0, 0.05]; smooth by default.
    correlation : {"colebrook", "haaland"}
        Friction correlation.
    gamma : float, optional
        Ratio of specific heats, > 1.

    Returns
    -------
    tuple of ChokingStep
        ``iterations + 1`` steps; the last one's ``mach`` is the answer.
    """
    ld = check_range("l_over_d", l_over_d, 0.0, lo_open=True)
    re0 = check_range("reynolds", THESIS_REYNOLDS if reynolds is None else reynolds, _RE_TURBULENT)
    m_ref = check_range("reynolds_mach", reynolds_mach, 0.0, lo_open=True)
    n = int(check_range("iterations", iterations, 0, 1000))
    if n != iterations:
        raise InputError("iterations", f"expected a whole number in [0, 1000], got {iterations!r}")
    g = float(_gamma(gamma))
    eps = float(_check_roughness(relative_roughness))
    if correlation not in _CORRELATIONS:
        raise InputError("correlation", f"{correlation!r} is not one of {', '.join(_CORRELATIONS)}")

    if friction_factor is None:
        f = float(_friction(re0, eps, correlation))
    else:
        f = check_range("friction_factor", friction_factor, 0.0, 1.0, lo_open=True)
    mach = _choke_from_f(f, ld, g)
    steps = [ChokingStep(0, re0, f, f * ld, mach)]
    for k in range(1, n + 1):
        re = re0 * mach / m_ref
        f = float(_friction(re, eps, correlation))
        mach = _choke_from_f(f, ld, g)
        steps.append(ChokingStep(k, re, f, f * ld, mach))
    return tuple(steps)


def choking_mach(
    l_over_d: float,
    reynolds: float | None = None,
    *,
    reynolds_mach: float = THESIS_REYNOLDS_MACH,
    friction_factor: float | None = None,
    iterations: int = 1,
    relative_roughness: float = 0.0,
    correlation: str = "colebrook",
    gamma: float = 1.4,
) -> float:
    """Flight Mach below which the open bore chokes (thesis chapter I.B.4.c).

    The last step of :func:`choking_history`, which documents the iteration
    and the parameters. ``iterations=0`` is the thesis's first estimate
    (M ~ 1.41), ``iterations=1`` its revised one (M = 1.44).

    Returns
    -------
    float
        Choking Mach number.
    """
    return choking_history(
        l_over_d,
        reynolds,
        reynolds_mach=reynolds_mach,
        friction_factor=friction_factor,
        iterations=iterations,
        relative_roughness=relative_roughness,
        correlation=correlation,
        gamma=gamma,
    )[-1].mach


def freestream_reynolds(
    mach: ArrayLike, bore_diameter: ArrayLike, altitude_m: ArrayLike = 0.0
) -> Any:
    """Bore Reynolds number Re = rho (M a) D / mu from the 1976 standard atmosphere.

    Parameters
    ----------
    mach : array_like
        Flight Mach number, > 0.
    bore_diameter : array_like
        Bore diameter D = 2 r_p [m], > 0.
    altitude_m : array_like, optional
        Geometric altitude [m] in [0, 86 000]; sea level by default.

    Returns
    -------
    float or numpy.ndarray
        Reynolds number based on D.
    """
    m = _mach(mach)
    d = checked_array("bore_diameter", bore_diameter, 0.0, lo_open=True, unit="m")
    atm = standard_atmosphere(altitude_m)
    rho, a, mu = (np.asarray(x) for x in (atm.density, atm.speed_of_sound, atm.dynamic_viscosity))
    _broadcast(mach=m, bore_diameter=d, altitude_m=rho)
    return as_output(rho * m * a * d / mu)


def choking_mach_freestream(
    l_over_d: float,
    bore_diameter: float,
    *,
    altitude_m: float = 0.0,
    relative_roughness: float = 0.0,
    correlation: str = "colebrook",
    gamma: float = 1.4,
    tol: float = 1e-12,
    max_iterations: int = 200,
) -> float:
    """Choking Mach with the bore Re iterated to convergence from free-stream conditions.

    Fixed point of M -> fanno_mach(f_D(Re(M)) L/D) with Re(M) from
    :func:`freestream_reynolds` (velocity M a, density and Sutherland
    viscosity of the 1976 standard atmosphere at `altitude_m`). f_D falls
    slowly with Re, so the map is a strong contraction; it starts at M = 2.5.

    Parameters
    ----------
    l_over_d : float
        Bore length over diameter, > 0.
    bore_diameter : float
        Bore diameter D [m], > 0 (Table 1: 2 r_p = 9.44 mm).
    altitude_m : float, optional
        Geometric altitude [m] in [0, 86 000].
    relative_roughness : float, optional
        eps/D in [0, 0.05].
    correlation : {"colebrook", "haaland"}
        Friction correlation.
    gamma : float, optional
        Ratio of specific heats, > 1 (for the Fanno relation).
    tol : float, optional
        Convergence tolerance on M, > 0.
    max_iterations : int, optional
        Iteration cap, >= 1.

    Returns
    -------
    float
        Converged choking Mach number.

    Raises
    ------
    InputError
        On bad input, if Re drops below the turbulent range (very high
        altitude or tiny bore), or if the iteration does not converge.
    """
    ld = check_range("l_over_d", l_over_d, 0.0, lo_open=True)
    d = check_range("bore_diameter", bore_diameter, 0.0, lo_open=True, unit="m")
    h = float(checked_array("altitude_m", altitude_m, 0.0, MAX_ALTITUDE, unit="m"))
    eps = float(_check_roughness(relative_roughness))
    g = float(_gamma(gamma))
    check_range("tol", tol, 0.0, lo_open=True)
    cap = int(check_range("max_iterations", max_iterations, 1))
    if correlation not in _CORRELATIONS:
        raise InputError("correlation", f"{correlation!r} is not one of {', '.join(_CORRELATIONS)}")
    mach = THESIS_REYNOLDS_MACH
    for _ in range(cap):
        re = float(freestream_reynolds(mach, d, h))
        if re < _RE_TURBULENT:
            raise InputError(
                "bore_diameter",
                f"bore Reynolds number {re:.4g} at M = {mach:.4g} is below the turbulent "
                f"range of the friction correlations (>= {_RE_TURBULENT:g})",
            )
        new = _choke_from_f(float(_friction(re, eps, correlation)), ld, g)
        if abs(new - mach) <= tol:
            return new
        mach = new
    raise InputError("max_iterations", f"no convergence to {tol:g} in {cap} iterations")
