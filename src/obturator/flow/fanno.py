"""Fanno flow (adiabatic, constant area, wall friction) for the choking of the open
bore (thesis chapter I.B.4.c), with Darcy friction factors from Colebrook or Haaland.

Friction factors are Darcy factors, f_D = 4 f_Fanning, which is what the
thesis's f L/D = 0.102 means (Fanning would give M ~ 1.17). The thesis's bore
Reynolds number (midpoint of its 4e5..6e5) is taken to hold at Mach 2.5
(:data:`obturator.reference.THESIS_REYNOLDS`, ``THESIS_REYNOLDS_MACH``; see
:func:`choking_history` for why).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._docs import field_docs, fill_doc
from ..errors import InputError, check_range
from ..reference import THESIS_REYNOLDS, THESIS_REYNOLDS_MACH
from ._arrays import (
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
from .atmosphere import MAX_ALTITUDE, standard_atmosphere

__all__ = [
    "THESIS_REYNOLDS",
    "THESIS_REYNOLDS_MACH",
    "fanno_fld",
    "fanno_fld_limit",
    "fanno_mach",
    "colebrook_friction_factor",
    "haaland_friction_factor",
    "friction_factor",
    "ChokingStep",
    "choking_history",
    "choking_mach",
    "freestream_reynolds",
    "choking_mach_freestream",
]


#: Lowest Reynolds number accepted by the turbulent friction correlations.
_RE_TURBULENT = 2300.0
#: Largest relative roughness eps/D on the Moody chart.
_MAX_ROUGHNESS = 0.05
_BRANCHES = ("subsonic", "supersonic")
_CORRELATIONS = ("colebrook", "haaland")


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
    return as_output(_fanno_raw(check_mach(mach), check_gamma(gamma)))


@fill_doc(params=ratio_doc())
def fanno_fld_limit(gamma: ArrayLike = 1.4) -> Any:
    """Supremum of f_D L*/D on the supersonic branch (M -> infinity).

    (gamma+1)/(2 gamma) ln((gamma+1)/(gamma-1)) - 1/gamma, 0.8215 for gamma = 1.4.

    {params}
        Limit of f_D L*/D.
    """
    g = check_gamma(gamma)
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
        return bracketed_root(resid, lo, 1.0, 1e-15)
    hi = 2.0
    while resid(hi) < 0.0:
        hi *= 2.0
        if hi > 1e12:  # pragma: no cover - excluded by the range check
            raise InputError("fld", f"{fld:g} is too close to the supersonic limit")
    return bracketed_root(resid, 1.0, hi, 1e-15)


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
    b = check_branch(branch)
    x = checked_array("fld", fld, 0.0)
    g = check_gamma(gamma)
    x, g = broadcast(fld=x, gamma=g)
    if b == "supersonic":
        limit = (g + 1.0) / (2.0 * g) * np.log((g + 1.0) / (g - 1.0)) - 1.0 / g
        bad = x >= limit
        if np.any(bad):
            i, where = first_bad(bad)
            raise InputError(
                "fld",
                f"{where}{x[i]:g} exceeds the supersonic Fanno limit: the duct chokes at every "
                f"supersonic entry Mach; allowed range [0, {limit[i]:.6g}) for "
                f"gamma = {g[i]:g}",
            )
    return elementwise(lambda a, c: _fanno_mach_scalar(a, c, b), x, g)


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

    s = bracketed_root(resid, 1.0, 1000.0, 1e-14)
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
    re, eps = broadcast(
        reynolds=_check_reynolds(reynolds), relative_roughness=_check_roughness(relative_roughness)
    )
    return elementwise(_colebrook_scalar, re, eps)


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
    re, eps = broadcast(
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


@field_docs
@dataclass(frozen=True)
class ChokingStep:
    """One pass of the thesis's friction-factor iteration."""

    #: 0 for the first estimate.
    iteration: int
    #: Bore Reynolds number used for the friction factor.
    reynolds: float
    #: Darcy friction factor f_D.
    friction_factor: float
    #: f_D L/D.
    fld: float
    #: Choking (entry = flight) Mach number from the Fanno relation.
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
    g = float(check_gamma(gamma))
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
    m = check_mach(mach)
    d = checked_array("bore_diameter", bore_diameter, 0.0, lo_open=True, unit="m")
    atm = standard_atmosphere(altitude_m)
    rho, a, mu = (np.asarray(x) for x in (atm.density, atm.speed_of_sound, atm.dynamic_viscosity))
    broadcast(mach=m, bore_diameter=d, altitude_m=rho)
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
    g = float(check_gamma(gamma))
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
