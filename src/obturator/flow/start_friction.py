"""The Kantrowitz-Donaldson start with wall friction and a discharge coefficient.

Eq. 2 (:func:`.inlet.swallow_area_ratio`) assumes the subsonic flow behind the
normal shock at the lip reaches the throat without loss and that the whole
geometric throat passes sonic flow. In the projectile the throat (the ball's
passage) lies a bore length L_p behind the lip (Table 1: L_p / 2 r_p = 8.07), so the
post-shock flow at M_2 (Eq. 3) first crosses a constant-area tube with wall friction.
Fanno flow (adiabatic, constant area; Shapiro 1953, ch. 6) accelerates it to M_3 at the
ball with

    f_D L/D = f_D L*/D (M_2) - f_D L*/D (M_3)            (:func:`.fanno.fanno_fld`)

and the throat must then pass the bore's mass flow at sonic speed from M_3
isentropically, through an effective area C_d A_t:

    A_c / A_t <= C_d A/A*(M_3)                          (:func:`start_area_ratio`)

(A_c is the bore, the capture area of the constant-area tube). With f_D = 0 and
C_d = 1 this is Eq. 2. When f_D L/D >= f_D L*/D (M_2) the tube chokes before the ball
and no throat starts it, the aligned ball included (:func:`friction_start_mach`: about
M 1.36 for f_D L/D = 0.12). Friction and C_d < 1 both lower the allowed contraction:
the start comes later in the closing motion, or never.

Friction factor (:func:`start_friction_range`): Darcy f_D at the Reynolds number of the
post-shock flow (:func:`post_shock_reynolds`: rho_1 V_1 D / mu(T_2), since rho_2 V_2 =
rho_1 V_1). The range spans the fully developed smooth pipe (Blasius 1913,
f_D = 0.316 Re^-1/4, and Colebrook 1939 with zero roughness, the lower of the two) and
the developing boundary layer from the lip, which the short tube (L/D ~8) never
outgrows: Schlichting's turbulent flat plate averaged over the tube length,
f_D = 4 C_f, C_f = 0.074 Re_L^-1/5 (Schlichting, Boundary-Layer Theory, ch. XXI),
and Colebrook with the given wall roughness, the higher of the two.

Discharge coefficient (:data:`DISCHARGE_COEFFICIENT_RANGE`): the lens between two sharp
mouth edges is an orifice. A sharp-edged orifice passing choked air has C_d rising
from the incompressible 0.61 to about 0.84 at high pressure ratios (Perry 1949, Trans.
ASME 71, 757-764; Jobson 1955, Proc. IMechE 169, 767-776); a rounded or aligned throat
has C_d -> 1 (ISO 9300 critical-flow nozzles: 0.98-0.995). The lens near theta_start
is most of the bore, blocked at one side by a step of c sin(theta): between the
two, 0.84-1.
"""

from __future__ import annotations

import math

from ..errors import check_range
from .atmosphere import standard_atmosphere, sutherland_viscosity
from .fanno import colebrook_friction_factor, fanno_fld, fanno_mach
from .inlet import area_ratio
from .shock import normal_shock_mach, normal_shock_temperature_ratio

__all__ = [
    "DISCHARGE_COEFFICIENT_RANGE",
    "blasius_friction_factor",
    "flat_plate_friction_factor",
    "post_shock_reynolds",
    "start_friction_range",
    "start_area_ratio",
    "friction_start_mach",
]

_RE_TURBULENT = 2300.0

#: Range of the discharge coefficient C_d of the lens orifice [-]: a sharp-edged orifice
#: passing choked flow (0.84, Perry 1949; Jobson 1955) to an aligned, rounded throat (1).
DISCHARGE_COEFFICIENT_RANGE: tuple[float, float] = (0.84, 1.0)


def blasius_friction_factor(reynolds: float) -> float:
    """Blasius's smooth-pipe Darcy friction factor 0.3164 Re^-1/4 [-] (Blasius 1913).

    Parameters
    ----------
    reynolds : float
        Reynolds number based on diameter, >= 2300.

    Returns
    -------
    float
        f_D.
    """
    re = check_range("reynolds", reynolds, 2300.0)
    return 0.3164 * re**-0.25


def flat_plate_friction_factor(reynolds: float, l_over_d: float) -> float:
    """Darcy factor 4 C_f of a turbulent boundary layer grown from the lip [-].

    Schlichting's mean skin friction of a turbulent flat plate of length L,
    C_f = 0.074 Re_L^-1/5 with Re_L = Re L/D (Boundary-Layer Theory, ch. XXI): the wall
    shear of a tube too short (L/D ~8) for its boundary layer to fill it, higher than
    the fully developed value.

    Parameters
    ----------
    reynolds : float
        Reynolds number based on diameter, >= 2300.
    l_over_d : float
        Tube length over diameter, > 0.

    Returns
    -------
    float
        f_D = 4 C_f.
    """
    re = check_range("reynolds", reynolds, 2300.0)
    ld = check_range("l_over_d", l_over_d, 0.0, lo_open=True)
    return 4.0 * 0.074 * (re * ld) ** -0.2


def post_shock_reynolds(
    mach: float, bore_diameter: float, altitude_m: float = 0.0, gamma: float = 1.4
) -> float:
    """Reynolds number of the flow behind the normal shock at the lip [-].

    Re_2 = rho_2 V_2 D / mu(T_2) = rho_1 V_1 D / mu(T_2): the mass flux is continuous
    across the shock (Eq. 1), the viscosity is Sutherland's at the post-shock static
    temperature T_2 = T_1 (T_2/T_1)(M_1) (1976 standard atmosphere at `altitude_m`).

    Parameters
    ----------
    mach : float
        Flight Mach number M_1, > 1.
    bore_diameter : float
        D = 2 r_p [m], > 0.
    altitude_m : float
        Altitude [m], in [0, 86 000].
    gamma : float
        Ratio of specific heats, > 1.

    Returns
    -------
    float
        Re_2 based on D.
    """
    m = check_range("mach", mach, 1.0, 10.0, lo_open=True)
    d = check_range("bore_diameter", bore_diameter, 0.0, lo_open=True, unit="m")
    atm = standard_atmosphere(altitude_m)
    t2 = float(atm.temperature) * float(normal_shock_temperature_ratio(m, gamma))
    mass_flux = float(atm.density) * m * float(atm.speed_of_sound)
    return mass_flux * d / float(sutherland_viscosity(t2))


def start_friction_range(
    reynolds: float, l_over_d: float, relative_roughness: float = 0.0
) -> tuple[float, float]:
    """Range of the Darcy friction factor of the post-shock flow in the tube [-].

    Low: the lower of Blasius and smooth Colebrook (fully developed smooth pipe). High:
    the higher of Schlichting's flat plate over the tube length
    (:func:`flat_plate_friction_factor`) and Colebrook at `relative_roughness`. Below
    Re 2300 (laminar): Hagen-Poiseuille's 64/Re and the laminar plate's 4 x 1.328
    Re_L^-1/2.

    Parameters
    ----------
    reynolds : float
        Post-shock Reynolds number (:func:`post_shock_reynolds`), > 0.
    l_over_d : float
        Tube length over diameter, > 0.
    relative_roughness : float
        eps/D of the bore wall, in [0, 0.05]; 0 (smooth) by default.

    Returns
    -------
    (float, float)
        f_D low and high.
    """
    re = check_range("reynolds", reynolds, 0.0, lo_open=True)
    ld = check_range("l_over_d", l_over_d, 0.0, lo_open=True)
    if re < _RE_TURBULENT:  # laminar: Hagen-Poiseuille, and Blasius's laminar plate
        return 64.0 / re, max(64.0 / re, 4.0 * 1.328 * (re * ld) ** -0.5)
    smooth = float(colebrook_friction_factor(reynolds, 0.0))
    low = min(blasius_friction_factor(reynolds), smooth)
    rough = (
        smooth  # the same root: not searched twice
        if relative_roughness == 0.0
        else float(colebrook_friction_factor(reynolds, relative_roughness))
    )
    return low, max(flat_plate_friction_factor(reynolds, l_over_d), rough, smooth)


def start_area_ratio(
    mach: float, fld: float = 0.0, discharge_coefficient: float = 1.0, gamma: float = 1.4
) -> float:
    """Largest A_c/A_t that swallows the bow shock with friction and a discharge coefficient.

    C_d A/A*(M_3), M_3 the subsonic Fanno Mach at the throat after f_D L/D from M_2
    (see the module text); Eq. 2 for `fld` = 0 and `discharge_coefficient` = 1.

    Parameters
    ----------
    mach : float
        Flight Mach number M_1, > 1.
    fld : float
        f_D L/D of the tube between lip and throat, >= 0.
    discharge_coefficient : float
        C_d of the throat, in (0, 1].
    gamma : float
        Ratio of specific heats, > 1.

    Returns
    -------
    float
        A_c/A_t; 0 where the tube chokes before the throat (f_D L/D >= f_D L*/D (M_2)):
        no throat starts it.
    """
    m = check_range("mach", mach, 1.0, 10.0, lo_open=True)
    f = check_range("fld", fld, 0.0)
    cd = check_range("discharge_coefficient", discharge_coefficient, 0.0, 1.0, lo_open=True)
    m2 = float(normal_shock_mach(m, gamma))
    left = float(fanno_fld(m2, gamma)) - f
    if left <= 0.0:
        return 0.0
    m3 = float(fanno_mach(left, gamma, "subsonic"))
    return cd * float(area_ratio(m3, gamma))


def friction_start_mach(fld: float, gamma: float = 1.4) -> float:
    """Lowest flight Mach at which a tube with f_D L/D = `fld` can start at all [-].

    The aligned throat (A_t = A_c, C_d = 1) starts while the post-shock flow reaches it
    unchoked: f_D L*/D (M_2) > f_D L/D, i.e. M_2 below the subsonic Fanno Mach of
    `fld`, read back to M_1 through the normal shock (Eq. 3 is its own inverse).

    Parameters
    ----------
    fld : float
        f_D L/D, >= 0 (0 gives M_1 = 1).
    gamma : float
        Ratio of specific heats, > 1.

    Returns
    -------
    float
        M_1 >= 1.
    """
    f = check_range("fld", fld, 0.0)
    if f == 0.0:
        return 1.0
    m2 = float(fanno_mach(f, gamma, "subsonic"))
    g = gamma
    return math.sqrt((2.0 / (g - 1.0) + m2 * m2) / (2.0 * g / (g - 1.0) * m2 * m2 - 1.0))
