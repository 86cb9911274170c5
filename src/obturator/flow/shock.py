"""Normal shock (thesis Eqs. 1 and 3) and the bow-shock pressure force on the closed
obturator, F_p = pi r_p^2 (P_2 - P_1) (Eq. 43).

Perfect gas with constant specific heats (NACA Report 1135).

>>> round(normal_shock_pressure_ratio(3.0), 4)
10.3333
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .._docs import field_docs, fill_doc
from ..errors import InputError
from ._arrays import (
    GAMMA_DOC,
    as_output,
    broadcast,
    check_gamma,
    check_mach,
    checked_array,
    ratio_doc,
)
from .atmosphere import standard_atmosphere

__all__ = [
    "normal_shock_mach",
    "normal_shock_pressure_ratio",
    "normal_shock_density_ratio",
    "normal_shock_temperature_ratio",
    "normal_shock_stagnation_pressure_ratio",
    "NormalShock",
    "normal_shock",
    "pressure_force",
    "flight_pressure_force",
]

_UPSTREAM_MACH = """\
mach : array_like
    Upstream Mach number M_1 >= 1."""
_UPSTREAM = ratio_doc(_UPSTREAM_MACH)


@fill_doc(params=_UPSTREAM)
def normal_shock_mach(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Mach number M_2 behind a normal shock (thesis Eq. 3).

    M_2^2 = (2/(gamma-1) + M_1^2) / (2 gamma/(gamma-1) M_1^2 - 1)

    {params}
        Downstream Mach number M_2 <= 1.
    """
    m, g = check_mach(mach, supersonic=True), check_gamma(gamma)
    m2 = (2.0 / (g - 1.0) + m * m) / (2.0 * g / (g - 1.0) * m * m - 1.0)
    return as_output(np.sqrt(m2))


@fill_doc(params=_UPSTREAM)
def normal_shock_pressure_ratio(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Static-pressure ratio P_2/P_1 across a normal shock (thesis Eq. 1).

    Eq. 1, (1 + gamma M_1^2)/(1 + gamma M_2^2) with M_2 from Eq. 3, reduces to
    1 + 2 gamma/(gamma+1) (M_1^2 - 1), evaluated here.

    {params}
        P_2/P_1 >= 1.
    """
    m, g = check_mach(mach, supersonic=True), check_gamma(gamma)
    return as_output(1.0 + 2.0 * g / (g + 1.0) * (m * m - 1.0))


@fill_doc(params=_UPSTREAM)
def normal_shock_density_ratio(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Density ratio rho_2/rho_1 = u_1/u_2 across a normal shock.

    rho_2/rho_1 = (gamma+1) M_1^2 / ((gamma-1) M_1^2 + 2)

    {params}
        rho_2/rho_1, between 1 and (gamma+1)/(gamma-1).
    """
    m, g = check_mach(mach, supersonic=True), check_gamma(gamma)
    return as_output((g + 1.0) * m * m / ((g - 1.0) * m * m + 2.0))


@fill_doc(params=_UPSTREAM)
def normal_shock_temperature_ratio(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Static-temperature ratio T_2/T_1 = (P_2/P_1)/(rho_2/rho_1) across a normal shock.

    {params}
        T_2/T_1 >= 1.
    """
    return as_output(
        np.asarray(normal_shock_pressure_ratio(mach, gamma))
        / np.asarray(normal_shock_density_ratio(mach, gamma))
    )


@fill_doc(params=_UPSTREAM)
def normal_shock_stagnation_pressure_ratio(mach: ArrayLike, gamma: ArrayLike = 1.4) -> Any:
    """Stagnation-pressure ratio p_02/p_01 across a normal shock.

    p_02/p_01 = (rho_2/rho_1)^(gamma/(gamma-1)) (P_2/P_1)^(-1/(gamma-1)),
    from the isentropic relation on each side with T_0 conserved.

    {params}
        p_02/p_01 <= 1 (the entropy rise across the shock).
    """
    g = check_gamma(gamma)
    rho = np.asarray(normal_shock_density_ratio(mach, gamma))
    p = np.asarray(normal_shock_pressure_ratio(mach, gamma))
    # Logs keep the powers finite at large M_1 and gamma close to 1.
    return as_output(np.exp((g * np.log(rho) - np.log(p)) / (g - 1.0)))


@field_docs
@dataclass(frozen=True)
class NormalShock:
    """All normal-shock ratios for upstream Mach ``mach`` (floats or arrays)."""

    #: Upstream Mach number M_1 [-].
    mach: Any
    #: Ratio of specific heats gamma [-].
    gamma: Any
    #: Downstream Mach number M_2 [-] (Eq. 3).
    mach2: Any
    #: Static pressure ratio P_2/P_1 [-] (Eq. 1).
    pressure_ratio: Any
    #: Density ratio rho_2/rho_1 [-].
    density_ratio: Any
    #: Static temperature ratio T_2/T_1 [-].
    temperature_ratio: Any
    #: Stagnation pressure ratio p_02/p_01 [-].
    stagnation_pressure_ratio: Any


@fill_doc(mach=_UPSTREAM_MACH, gamma=GAMMA_DOC)
def normal_shock(mach: ArrayLike, gamma: ArrayLike = 1.4) -> NormalShock:
    """Normal-shock state behind upstream Mach ``mach`` (thesis Eqs. 1 and 3).

    Parameters
    ----------
    {mach}
    {gamma}

    Returns
    -------
    NormalShock
    """
    m, g = broadcast(mach=check_mach(mach, supersonic=True), gamma=check_gamma(gamma))
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
    broadcast(mach=ratio, p1=p, bore_radius=r)
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
