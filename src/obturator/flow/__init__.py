"""Compressible flow of the bore (thesis chapter I.B.4) and the standard atmosphere.

Perfect gas with constant specific heats, one-dimensional flow:

* normal shock (thesis Eqs. 1 and 3) and the pressure force that the bow shock
  puts on the closed obturator, F_p = pi r_p^2 (P_2 - P_1) (Eq. 43);
* isentropic area ratio A/A* and the Kantrowitz-Donaldson start/unstart
  limits of a capture-to-throat contraction A_c/A_t (Eqs. 2 and 4);
* Fanno flow (adiabatic, constant area, wall friction) for the choking of the
  open bore, with Darcy friction factors from Colebrook or Haaland;
* the start of the tube with the wall friction of the post-shock flow and a
  discharge coefficient of the throat (the late bound of theta_start);
* the U.S. Standard Atmosphere 1976 (free-stream pressure, viscosity).

Modules: :mod:`.shock`, :mod:`.inlet`, :mod:`.fanno`, :mod:`.start_friction`,
:mod:`.atmosphere`;
input checks of array arguments in :mod:`._arrays`.

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

from ._arrays import AREA_RATIO_MAX, MACH_MAX
from .atmosphere import (
    Atmosphere,
    geometric_altitude,
    geopotential_altitude,
    mach_from_velocity,
    standard_atmosphere,
    sutherland_viscosity,
)
from .fanno import (
    THESIS_REYNOLDS,
    THESIS_REYNOLDS_MACH,
    ChokingStep,
    choking_history,
    choking_mach,
    choking_mach_freestream,
    colebrook_friction_factor,
    fanno_fld,
    fanno_fld_limit,
    fanno_mach,
    freestream_reynolds,
    friction_factor,
    haaland_friction_factor,
)
from .inlet import (
    area_ratio,
    mach_from_area_ratio,
    regurgitate_area_ratio,
    start_mach,
    swallow_area_ratio,
    swallow_area_ratio_limit,
    unstart_mach,
)
from .shock import (
    NormalShock,
    flight_pressure_force,
    normal_shock,
    normal_shock_density_ratio,
    normal_shock_mach,
    normal_shock_pressure_ratio,
    normal_shock_stagnation_pressure_ratio,
    normal_shock_temperature_ratio,
    pressure_force,
)

__all__ = [
    "AREA_RATIO_MAX",
    "Atmosphere",
    "ChokingStep",
    "MACH_MAX",
    "NormalShock",
    "THESIS_REYNOLDS",
    "THESIS_REYNOLDS_MACH",
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
    "geometric_altitude",
    "geopotential_altitude",
    "haaland_friction_factor",
    "mach_from_area_ratio",
    "mach_from_velocity",
    "normal_shock",
    "normal_shock_density_ratio",
    "normal_shock_mach",
    "normal_shock_pressure_ratio",
    "normal_shock_stagnation_pressure_ratio",
    "normal_shock_temperature_ratio",
    "pressure_force",
    "regurgitate_area_ratio",
    "standard_atmosphere",
    "start_mach",
    "sutherland_viscosity",
    "swallow_area_ratio",
    "swallow_area_ratio_limit",
    "unstart_mach",
]
