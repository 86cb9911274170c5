"""U.S. Standard Atmosphere 1976, 0 to 86 km geometric altitude.

Free-stream conditions for the flight case: the static pressure P_1 ahead of
the bow shock (thesis Eq. 1; Table 1 uses P_1 = 0.099 MPa), and the density,
speed of sound and viscosity that set the bore Reynolds number of the Fanno
choking estimate (thesis chapter I.B.4.c).

The model is the lower atmosphere of the 1976 standard (NOAA/NASA/USAF,
NOAA-S/T 76-1562): seven layers of linear molecular-scale temperature T_M in
geopotential altitude H, hydrostatic pressure, perfect-gas density with the
sea-level mean molar mass M_0. Geometric altitude z is converted with

    H = r_0 z / (r_0 + z),    r_0 = 6 356 766 m.

Between 80 and 86 km the standard's kinetic temperature T differs from T_M by
the molar-mass ratio M/M_0 (its Table 8, interpolated linearly in z); T is
used for the viscosity, T_M for density and speed of sound, as in the standard.
Viscosity is Sutherland's law with the standard's beta = 1.458e-6 kg/(m s K^0.5)
and S = 110.4 K.

Every function is vectorised over altitude (numpy broadcasting): scalars in
give floats out, arrays in give arrays out. Altitudes outside [0, 86 000] m
raise :class:`~obturator.errors.InputError` naming the first offending value.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._docs import field_docs
from ..errors import InputError
from ._arrays import as_output, checked_array

__all__ = [
    "EARTH_RADIUS",
    "GAMMA_AIR",
    "MAX_ALTITUDE",
    "R_AIR",
    "STANDARD_GRAVITY",
    "Atmosphere",
    "geometric_altitude",
    "geopotential_altitude",
    "mach_from_velocity",
    "standard_atmosphere",
    "sutherland_viscosity",
]

#: Effective Earth radius r_0 of the 1976 standard [m].
EARTH_RADIUS = 6_356_766.0
#: Standard gravity g_0 [m/s^2].
STANDARD_GRAVITY = 9.80665
#: Universal gas constant R* as defined by the 1976 standard [J/(mol K)].
R_STAR = 8.31432
#: Sea-level mean molar mass of air M_0 [kg/mol].
MOLAR_MASS_AIR = 0.0289644
#: Specific gas constant of air R*/M_0 [J/(kg K)].
R_AIR = R_STAR / MOLAR_MASS_AIR
#: Ratio of specific heats of air used by the standard for the speed of sound.
GAMMA_AIR = 1.4
#: Sutherland constants of the 1976 standard: beta [kg/(m s K^0.5)], S [K].
SUTHERLAND_BETA = 1.458e-6
SUTHERLAND_S = 110.4
#: Upper limit of this model, geometric altitude [m].
MAX_ALTITUDE = 86_000.0

# Layer bases in geopotential altitude H_b [m'] and molecular-scale temperature
# gradients L_b [K/m'] (1976 standard, Table 4). The last base is the top.
_H_BASE = np.array([0.0, 11_000.0, 20_000.0, 32_000.0, 47_000.0, 51_000.0, 71_000.0])
_LAPSE = np.array([-0.0065, 0.0, 0.001, 0.0028, 0.0, -0.0028, -0.002])
_T_SEA = 288.15
_P_SEA = 101_325.0
# g_0 M_0 / R*, the hydrostatic constant [K/m'].
_HYDRO = STANDARD_GRAVITY * MOLAR_MASS_AIR / R_STAR

# Molar-mass ratio M/M_0 against geometric altitude, 80-86 km (standard, Table 8).
_MM_Z = np.arange(80_000.0, 86_001.0, 500.0)
_MM_RATIO = np.array(
    [
        1.000000,
        0.999996,
        0.999989,
        0.999971,
        0.999941,
        0.999909,
        0.999870,
        0.999829,
        0.999786,
        0.999741,
        0.999694,
        0.999641,
        0.999579,
    ]
)


def _layer_pressure(dh: Any, t_base: Any, p_base: Any, lapse: Any) -> Any:
    """Hydrostatic pressure a height ``dh`` [m'] above a layer base."""
    if lapse == 0.0:
        return p_base * np.exp(-_HYDRO * dh / t_base)
    return p_base * (t_base / (t_base + lapse * dh)) ** (_HYDRO / lapse)


def _base_states() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """March T_M and P up the layer bases (the standard's T_b and P_b)."""
    temps = [_T_SEA]
    pres = [_P_SEA]
    for i in range(len(_H_BASE) - 1):
        dh = _H_BASE[i + 1] - _H_BASE[i]
        temps.append(temps[i] + _LAPSE[i] * dh)
        pres.append(float(_layer_pressure(dh, temps[i], pres[i], _LAPSE[i])))
    return np.array(temps), np.array(pres)


_T_BASE, _P_BASE = _base_states()


def geopotential_altitude(altitude_m: ArrayLike) -> Any:
    """Geopotential altitude H = r_0 z / (r_0 + z) [m'] of geometric altitude z [m].

    Parameters
    ----------
    altitude_m : array_like
        Geometric altitude z [m], within [0, 86 000] m.

    Returns
    -------
    float or numpy.ndarray
        Geopotential altitude H [m'].
    """
    z = checked_array("altitude_m", altitude_m, 0.0, MAX_ALTITUDE, unit="m")
    return as_output(EARTH_RADIUS * z / (EARTH_RADIUS + z))


def geometric_altitude(geopotential_m: ArrayLike) -> Any:
    """Geometric altitude z = r_0 H / (r_0 - H) [m] of geopotential altitude H [m'].

    Parameters
    ----------
    geopotential_m : array_like
        Geopotential altitude H [m'], within [0, 84 852] m' (z = 0..86 km).

    Returns
    -------
    float or numpy.ndarray
        Geometric altitude z [m].
    """
    h_top = EARTH_RADIUS * MAX_ALTITUDE / (EARTH_RADIUS + MAX_ALTITUDE)
    h = checked_array("geopotential_m", geopotential_m, 0.0, h_top, unit="m'")
    return as_output(EARTH_RADIUS * h / (EARTH_RADIUS - h))


def sutherland_viscosity(temperature: ArrayLike) -> Any:
    """Dynamic viscosity of air by Sutherland's law [Pa s].

    mu = beta T^(3/2) / (T + S), beta = 1.458e-6 kg/(m s K^0.5), S = 110.4 K
    (1976 standard, Eq. 51).

    Parameters
    ----------
    temperature : array_like
        Kinetic temperature T [K], > 0.

    Returns
    -------
    float or numpy.ndarray
        Dynamic viscosity mu [Pa s].
    """
    t = checked_array("temperature", temperature, 0.0, lo_open=True, unit="K")
    return as_output(SUTHERLAND_BETA * t**1.5 / (t + SUTHERLAND_S))


@field_docs
@dataclass(frozen=True)
class Atmosphere:
    """State of the 1976 standard atmosphere at one or more altitudes.

    Attributes are floats for a scalar altitude, arrays otherwise.
    """

    #: Geometric altitude z [m].
    altitude_m: Any
    #: Geopotential altitude H [m'].
    geopotential_m: Any
    #: Kinetic temperature T [K].
    temperature: Any
    #: Static pressure P [Pa].
    pressure: Any
    #: Density rho [kg/m^3].
    density: Any
    #: Speed of sound a [m/s].
    speed_of_sound: Any
    #: Dynamic viscosity mu [Pa s].
    dynamic_viscosity: Any

    @property
    def kinematic_viscosity(self) -> Any:
        """Kinematic viscosity nu = mu / rho [m^2/s]."""
        return as_output(np.asarray(self.dynamic_viscosity) / np.asarray(self.density))


def standard_atmosphere(altitude_m: ArrayLike) -> Atmosphere:
    """U.S. Standard Atmosphere 1976 at geometric altitude ``altitude_m``.

    Parameters
    ----------
    altitude_m : array_like
        Geometric altitude z [m], within [0, 86 000] m.

    Returns
    -------
    Atmosphere
        Temperature [K], pressure [Pa], density [kg/m^3], speed of sound
        [m/s] and Sutherland viscosity [Pa s].

    Raises
    ------
    InputError
        If any altitude lies outside [0, 86 000] m (no extrapolation).

    Examples
    --------
    Geometric 20 km is geopotential 19.937 km, below the 20 km' layer base
    (5474.9 Pa):

    >>> round(standard_atmosphere(20_000.0).pressure, 1)
    5529.3
    """
    if isinstance(altitude_m, float | int) and not isinstance(altitude_m, bool):
        # one altitude: memoised (the flight studies ask for the same few altitudes at
        # every segment of every trajectory), keyed on its exact bits
        return _one_altitude(float(altitude_m).hex())
    return _atmosphere(altitude_m)


@functools.lru_cache(maxsize=1024)
def _one_altitude(altitude_hex: str) -> Atmosphere:
    """:func:`_atmosphere` at the altitude whose :meth:`float.hex` is `altitude_hex`
    (immutable: a frozen record of floats)."""
    return _atmosphere(float.fromhex(altitude_hex))


def _atmosphere(altitude_m: ArrayLike) -> Atmosphere:
    """:func:`standard_atmosphere`, computed."""
    z = checked_array("altitude_m", altitude_m, 0.0, MAX_ALTITUDE, unit="m")
    h = EARTH_RADIUS * z / (EARTH_RADIUS + z)
    # Layer index: the last base at or below H (the top of layer 6 is 84 852 m').
    i = np.clip(np.searchsorted(_H_BASE, h, side="right") - 1, 0, len(_H_BASE) - 1)
    dh = h - _H_BASE[i]
    lapse = _LAPSE[i]
    t_base = _T_BASE[i]
    t_mol = t_base + lapse * dh
    with np.errstate(divide="ignore", invalid="ignore"):
        # Both branches are evaluated element-wise; where() keeps the right one.
        p_grad = _P_BASE[i] * (t_base / t_mol) ** (_HYDRO / np.where(lapse == 0.0, 1.0, lapse))
    p_iso = _P_BASE[i] * np.exp(-_HYDRO * dh / t_base)
    pressure = np.where(lapse == 0.0, p_iso, p_grad)
    density = pressure / (R_AIR * t_mol)
    speed = np.sqrt(GAMMA_AIR * R_AIR * t_mol)
    # Kinetic temperature differs from T_M only above 80 km (molar-mass drop).
    t_kin = t_mol * np.interp(z, _MM_Z, _MM_RATIO, left=1.0, right=_MM_RATIO[-1])
    mu = SUTHERLAND_BETA * t_kin**1.5 / (t_kin + SUTHERLAND_S)
    return Atmosphere(
        altitude_m=as_output(z),
        geopotential_m=as_output(h),
        temperature=as_output(t_kin),
        pressure=as_output(pressure),
        density=as_output(density),
        speed_of_sound=as_output(speed),
        dynamic_viscosity=as_output(mu),
    )


def mach_from_velocity(v: ArrayLike, altitude_m: ArrayLike) -> Any:
    """Flight Mach number M = v / a(z) in the 1976 standard atmosphere.

    Parameters
    ----------
    v : array_like
        Flight speed [m/s], >= 0.
    altitude_m : array_like
        Geometric altitude z [m], within [0, 86 000] m; broadcast against `v`.

    Returns
    -------
    float or numpy.ndarray
        Mach number [-].
    """
    speed = checked_array("v", v, 0.0, unit="m/s")
    a = np.asarray(standard_atmosphere(altitude_m).speed_of_sound)
    try:
        return as_output(speed / a)
    except ValueError:
        raise InputError("v", "cannot broadcast v against altitude_m") from None
