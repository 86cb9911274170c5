"""Torque models acting on the ball (thesis chapter II.B).

Each model is a small frozen dataclass in plain SI units. They are combined in
a :class:`TorqueModel` (one viscous part plus one sliding-friction part, thesis
Eqs. 62-64) which packs itself into a flat float array consumed by the compiled
right-hand side in :mod:`obturator.core.dynamics`. Nothing here integrates.

Sign convention: every torque opposes the relative angular velocity
omega_r = omega_ball - omega_p Z (thesis Eqs. 35-36, 69), so the power
omega_r . G is never positive.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..core.layout import (
    FRIC_COULOMB,
    FRIC_NONE,
    FRIC_THESIS_FLIGHT,
    FRIC_THESIS_RIG,
    SPEED_CODES,
    VISC_LINEAR,
    VISC_NONE,
)
from ..errors import InputError, check_range
from ..reference import TABLE1
from ..vocab import SPEED_LAWS, SpeedLawName, check_choice

__all__ = [
    "AIR_DYNAMIC_VISCOSITY",
    "AIR_DENSITY",
    "CouetteViscous",
    "NakabayashiViscous",
    "ThesisRigFriction",
    "ThesisFlightFriction",
    "CoulombContactFriction",
    "MATERIALS",
    "hertz_patch_radius",
    "TorqueModel",
    "SlipSpeedLaw",
    "ViscousTorque",
    "FrictionTorque",
]

#: Table 1 gap-fluid viscosity mu_f [Pa s].
AIR_DYNAMIC_VISCOSITY = TABLE1["viscosity"]
#: Air density at sea level [kg/m^3] (for the Reynolds number, Eq. 40).
AIR_DENSITY = 1.225
#: Smallest gap accepted [m]: below ~0.1 um (the mean free path of air is 68 nm)
#: the continuum Couette/Nakabayashi models of the gap flow do not apply.
MIN_GAP = 1e-7


def _check_film(ball_radius: float, gap: float, viscosity: float) -> None:
    """The inputs of every viscous-film model: R_s, gap h [m] (below R_s), mu_f [Pa s]."""
    check_range("ball_radius", ball_radius, 0.0, math.inf, lo_open=True, unit="m")
    check_range("gap", gap, MIN_GAP, ball_radius, hi_open=True, unit="m")
    check_range("viscosity", viscosity, 0.0, unit="Pa s")


@dataclass(frozen=True)
class CouetteViscous:
    """Viscous torque of plane Couette flow in the gap, thesis Eqs. (32)-(34).

    Q = -S omega_r with S = (8/3) pi R_s^4 mu_f / h.

    Parameters
    ----------
    ball_radius : float
        R_s [m].
    gap : float
        Radial clearance h between ball and socket [m].
    viscosity : float
        Dynamic viscosity of the gap fluid mu_f [Pa s].
    scale : float
        Multiplier on S (the thesis's Fig. 10 runs S x 1, 10, 100, 1000) [-].
    """

    ball_radius: float
    gap: float
    viscosity: float = AIR_DYNAMIC_VISCOSITY
    scale: float = 1.0

    def __post_init__(self) -> None:
        _check_film(self.ball_radius, self.gap, self.viscosity)
        check_range("scale", self.scale, 0.0)

    @property
    def coefficient(self) -> float:
        """Shear constant S [N m s], thesis Eq. (34) (times `scale`)."""
        return self.scale * 8.0 / 3.0 * math.pi * self.ball_radius**4 * self.viscosity / self.gap

    def pack(self) -> tuple[float, float, float, float]:
        """(code, S, K_turb, omega_transition) for the compiled kernel."""
        return (VISC_LINEAR, self.coefficient, 0.0, math.inf)


@dataclass(frozen=True)
class NakabayashiViscous:
    """Spherical-Couette viscous torque after Nakabayashi, thesis Eqs. (37)-(42).

    Laminar branch (Eq. 42): M_v = (8/3) pi ((1 + eps)/eps) mu_f R_s^3 omega_r,
    eps = h / R_s; Table 1 gives S = 12.38e-9 N m s. Turbulent branch (Eq. 39),
    used when Re = R_s^2 omega_r / nu exceeds Re_t = 70 eps^-1.6 (Eq. 41):
    M_v = C_m rho_f R_s^5 omega_r^2 with
    C_m = (0.053/eps) (1 + 7 eps/4)/(1 - 3 eps/2) Re^-1/4.
    Eq. (37) is garbled in the print ("omega_r^5"); the omega_r^2 scaling is the
    one for which the laminar C_m reduces to Eq. (42), so the laminar C_m here is
    (8 pi/3)((1+eps)/eps) Re^-1. As printed, the two branches do not join at
    Re_t (the turbulent moment is larger); the thesis never reaches Re_t.

    Parameters
    ----------
    ball_radius : float
        R_s [m].
    gap : float
        h [m].
    viscosity : float
        mu_f [Pa s].
    fluid_density : float
        rho_f of the gap fluid [kg/m^3] (enters only the turbulent branch).
    turbulent : bool
        Whether to switch to Eq. (39) above Re_t.
    scale : float
        Multiplier on the moment [-].
    """

    ball_radius: float
    gap: float
    viscosity: float = AIR_DYNAMIC_VISCOSITY
    fluid_density: float = AIR_DENSITY
    turbulent: bool = True
    scale: float = 1.0

    def __post_init__(self) -> None:
        _check_film(self.ball_radius, self.gap, self.viscosity)
        check_range("fluid_density", self.fluid_density, 0.0, math.inf, lo_open=True, unit="kg/m^3")
        check_range("scale", self.scale, 0.0)

    @property
    def gap_ratio(self) -> float:
        """eps = h / R_s [-]."""
        return self.gap / self.ball_radius

    @property
    def coefficient(self) -> float:
        """Laminar shear constant S [N m s], Eq. (42)."""
        e = self.gap_ratio
        return (
            self.scale * 8.0 / 3.0 * math.pi * (1.0 + e) / e * self.viscosity * self.ball_radius**3
        )

    @property
    def transition_reynolds(self) -> float:
        """Re_t = 70 eps^-1.6 [-], Eq. (41)."""
        return 70.0 * self.gap_ratio**-1.6

    @property
    def transition_rate(self) -> float:
        """|omega_r| at which Re = Re_t [rad/s]."""
        nu = self.viscosity / self.fluid_density
        return self.transition_reynolds * nu / self.ball_radius**2 if nu > 0 else math.inf

    @property
    def turbulent_coefficient(self) -> float:
        """K in M_v = K |omega_r|^1.75 on the turbulent branch [N m s^1.75], Eq. (39)."""
        e = self.gap_ratio
        nu = self.viscosity / self.fluid_density
        g = (1.0 + 1.75 * e) / (1.0 - 1.5 * e)
        return self.scale * 0.053 / e * g * self.fluid_density * self.ball_radius**4.5 * nu**0.25

    def pack(self) -> tuple[float, float, float, float]:
        """(code, S, K_turb, omega_transition) for the compiled kernel."""
        w_t = self.transition_rate if self.turbulent else math.inf
        return (VISC_LINEAR, self.coefficient, self.turbulent_coefficient, w_t)


ViscousTorque = CouetteViscous | NakabayashiViscous


#: Largest sliding friction coefficient accepted [-]: dry engineering pairs stay
#: below ~1.5 (the thesis uses 0.35-0.55); beyond it the stick phases only get
#: stiffer and slower to integrate, with no physical case to cover.
MAX_MU = 2.0
#: Largest normal load accepted [N]: ten times the flight load behind a Mach 10
#: normal shock at sea level (~1 kN).
MAX_LOAD = 1e4
#: Largest rig normal load accepted [N]: over 100 times the ball's weight.
MAX_RIG_WEIGHT = 10.0


def _check_mu(mu_s: float) -> float:
    return check_range("mu_s", mu_s, 0.0, MAX_MU)


def _check_contact(
    mu_s: float, load_field: str, load: float, max_load: float, radius: float
) -> None:
    """The inputs of every sliding-friction model: mu_s, the normal load [N], R_s [m]."""
    _check_mu(mu_s)
    check_range(load_field, load, 0.0, max_load, unit="N")
    check_range("ball_radius", radius, 0.0, math.inf, lo_open=True, unit="m")


@dataclass(frozen=True)
class ThesisRigFriction:
    """Sliding friction on the spin rig, thesis Eqs. (56)-(61).

    One contact at the bottom of the socket, P_G = -R_s X (gravity along -X,
    fixed in the laboratory). Torque magnitude mu_s W R_s sqrt(1 - (w_X/w_r)^2),
    direction -omega_r/|omega_r| (Eq. 61), as in Appendix A with C(1) = 1.

    Parameters
    ----------
    mu_s : float
        Sliding friction coefficient [-], >= 0.
    weight : float
        Normal load W [N] (the ball's weight on the rig).
    ball_radius : float
        R_s [m].
    """

    mu_s: float
    weight: float
    ball_radius: float

    def __post_init__(self) -> None:
        _check_contact(self.mu_s, "weight", self.weight, MAX_RIG_WEIGHT, self.ball_radius)

    @property
    def moment_scale(self) -> float:
        """mu_s W R_s [N m]."""
        return self.mu_s * self.weight * self.ball_radius

    @property
    def arm_vanishes(self) -> bool:
        """True: the arm sqrt(1 - u_X^2) is zero along X (no torque about the contact
        normal), so it has a sharp minimum whenever omega_r swings past X."""
        return True

    def pack(self) -> tuple[float, float, float, float, float, float]:
        """(code, moment scale, R_s, beta, n_contacts, pivot arm (unused))."""
        return (FRIC_THESIS_RIG, self.moment_scale, self.ball_radius, math.pi / 2.0, 1.0, 0.0)


@dataclass(frozen=True)
class ThesisFlightFriction:
    """Sliding friction in flight, thesis Eqs. (43)-(55) with Appendix A's arm.

    The pressure force F_p = pi r_p^2 (P_2 - P_1) (Eq. 43) presses the ball on
    the ring where the bore meets the socket, at beta from Z. Torque magnitude
    mu_s F_p cos(beta) R_s ARM with
    ARM = sqrt(1 - sin^2(beta)(w_X/w_r)^2 - cos^2(beta)(w_Z/w_r)^2)
    (Appendix A; Eq. 55's printed sqrt(2)/2 factor is not used), direction
    -omega_r/|omega_r|.

    Parameters
    ----------
    mu_s : float
        Sliding friction coefficient [-].
    pressure_force : float
        F_p [N].
    ball_radius : float
        R_s [m].
    contact_angle : float
        beta [rad], in (0, pi/2); the thesis uses beta_s = asin(r_p/R_s).
    """

    mu_s: float
    pressure_force: float
    ball_radius: float
    contact_angle: float

    def __post_init__(self) -> None:
        _check_contact(self.mu_s, "pressure_force", self.pressure_force, MAX_LOAD, self.ball_radius)
        check_range(
            "contact_angle",
            self.contact_angle,
            0.0,
            math.pi / 2,
            lo_open=True,
            hi_open=True,
            unit="rad",
        )

    @property
    def moment_scale(self) -> float:
        """mu_s F_p cos(beta) R_s [N m]."""
        return self.mu_s * self.pressure_force * math.cos(self.contact_angle) * self.ball_radius

    @property
    def arm_vanishes(self) -> bool:
        """Whether Appendix A's arm, at least min(sin beta, cos beta) over slip directions,
        comes as near zero as the rig's does when omega_r passes close to X (below
        0.2); False for Table 1's beta = 36.7 deg (0.60)."""
        return min(math.sin(self.contact_angle), math.cos(self.contact_angle)) < 0.2

    def pack(self) -> tuple[float, float, float, float, float, float]:
        """(code, moment scale, R_s, beta, n_contacts, pivot arm (unused))."""
        return (
            FRIC_THESIS_FLIGHT,
            self.moment_scale,
            self.ball_radius,
            self.contact_angle,
            2.0,
            0.0,
        )


@dataclass(frozen=True)
class CoulombContactFriction:
    """Physically exact Coulomb friction at point contacts.

    At each contact point P_k (fixed in the inertial frame, on the sphere of
    radius R_s) the socket surface slips past the ball with velocity
    v_k = omega_r x P_k; the friction force F_k = -mu_s N_k v_k/|v_k| acts there
    and the torque on the ball is sum_k P_k x F_k. Unlike the thesis's form,
    the torque is perpendicular to each P_k, not along omega_r; both dissipate.

    Rig (``n_contacts=1, contact_angle=pi/2``): one contact at P = -R_s X with
    N = W. Flight: a ring of ``n_contacts`` points at polar angle beta from Z,
    equally spaced in azimuth from the X-Z plane (``n_contacts=2`` are the
    thesis's P_1, P_2 of Eq. 47).

    Parameters
    ----------
    mu_s : float
        Sliding friction coefficient [-].
    normal_force : float
        Load that presses the ball into its seat [N]: W on the rig, F_p in flight.
    ball_radius : float
        R_s [m].
    contact_angle : float
        beta [rad] from +Z; pi/2 selects the rig's single bottom contact.
    n_contacts : int
        Number of contact points N (>= 1).
    normal_load : {"thesis", "radial"}
        How the load is shared: "thesis" gives each point F cos(beta)/N as the
        thesis's Eq. (45b) does; "radial" gives F/(N cos(beta)), the radial
        reaction that balances an axial load on a spherical seat.
    patch_radius : float
        Radius a of each contact's circular patch [m], >= 0. A patch resists
        pivoting (drilling) about the contact normal with up to mu N eps,
        eps = 3 pi a / 16 (Hertzian pressure), coupled to sliding in
        Contensou's way (elliptic approximation, Leine and Glocker 2003). With
        a = 0 (a point contact) nothing resists pivoting and, on the rig, t_cr
        does not converge as the regularisation width shrinks; see
        :func:`hertz_patch_radius` for a physically argued value.

    Notes
    -----
    The point-contact idealisation is the thesis's own (p. 34: "a point
    contact at the bottom of the housing is assumed"); the patch is the
    smallest physical addition that makes the exact law well posed.
    """

    mu_s: float
    normal_force: float
    ball_radius: float
    contact_angle: float = math.pi / 2
    n_contacts: int = 1
    normal_load: str = "thesis"
    patch_radius: float = 0.0

    def __post_init__(self) -> None:
        _check_contact(self.mu_s, "normal_force", self.normal_force, MAX_LOAD, self.ball_radius)
        check_range("contact_angle", self.contact_angle, 0.0, math.pi / 2, lo_open=True, unit="rad")
        if not isinstance(self.n_contacts, int) or not 1 <= self.n_contacts <= 1000:
            raise InputError(
                "n_contacts",
                f"{self.n_contacts!r} is outside the allowed range 1..1000 (an integer)",
            )
        if self.normal_load not in ("thesis", "radial"):
            raise InputError("normal_load", f"{self.normal_load!r}; allowed: 'thesis', 'radial'")
        if self.normal_load == "radial" and self.contact_angle >= math.pi / 2:
            raise InputError("normal_load", "'radial' needs contact_angle < pi/2 rad")
        check_range("patch_radius", self.patch_radius, 0.0, self.ball_radius, unit="m")

    @property
    def pivot_arm(self) -> float:
        """eps = 3 pi a / 16 [m]: pivot torque limit over mu N for a Hertzian patch."""
        return 3.0 * math.pi * self.patch_radius / 16.0

    @property
    def load_per_contact(self) -> float:
        """N_k [N]."""
        c = math.cos(self.contact_angle)
        if self.contact_angle >= math.pi / 2:  # rig: the full weight at one point
            return self.normal_force / self.n_contacts
        if self.normal_load == "thesis":
            return self.normal_force * c / self.n_contacts
        return self.normal_force / (self.n_contacts * c)

    @property
    def arm_vanishes(self) -> bool:
        """True for one contact: it holds no torque about its normal but through the
        small pivot arm of its patch, a sharp minimum as omega_r swings past the normal."""
        return self.n_contacts == 1

    def pack(self) -> tuple[float, float, float, float, float, float]:
        """(code, mu_s N_k, R_s, beta, n_contacts, pivot arm eps)."""
        return (
            FRIC_COULOMB,
            self.mu_s * self.load_per_contact,
            self.ball_radius,
            self.contact_angle,
            float(self.n_contacts),
            self.pivot_arm,
        )


#: Young's modulus and Poisson ratio of the contacting materials (handbook values).
MATERIALS: dict[str, tuple[float, float]] = {
    "steel": (200e9, 0.29),
    "lucite": (3.0e9, 0.37),  # PMMA: the thesis rig's housing (Fig. 22)
}


def hertz_patch_radius(
    load: float,
    ball_radius: float,
    gap: float,
    *,
    ball_material: str = "steel",
    seat_material: str = "steel",
) -> float:
    """Hertz contact radius a of a ball in a conforming spherical seat [m].

    a = (3 N R* / (4 E*))^(1/3) with R* = R_s (R_s + h) / h for a seat of
    radius R_s + h, and 1/E* = (1 - nu_1^2)/E_1 + (1 - nu_2^2)/E_2.

    Parameters
    ----------
    load : float
        Normal load N [N] (W on the rig, F_p split over the contacts in flight).
    ball_radius : float
        R_s [m].
    gap : float
        Radial clearance h [m] (seat radius R_s + h).
    ball_material, seat_material : {"steel", "lucite"}
        Keys of :data:`MATERIALS`. The thesis rig: steel ball in a lucite
        housing (chapter III, Fig. 22); in flight: a steel socket.

    Returns
    -------
    float
        a [m]. Table 1 rig (W = 0.07987 N, h = 50.8 um, lucite): 0.279 mm.
    """
    check_range("load", load, 0.0, unit="N")
    check_range("ball_radius", ball_radius, 0.0, math.inf, lo_open=True, unit="m")
    check_range("gap", gap, 0.0, math.inf, lo_open=True, unit="m")
    for field, name in (("ball_material", ball_material), ("seat_material", seat_material)):
        if name not in MATERIALS:
            raise InputError(field, f"{name!r}; allowed: {', '.join(MATERIALS)}")
    inv_e = sum(
        (1.0 - nu * nu) / e for e, nu in (MATERIALS[ball_material], MATERIALS[seat_material])
    )
    r_eff = ball_radius * (ball_radius + gap) / gap
    return (3.0 * load * r_eff * inv_e / 4.0) ** (1.0 / 3.0)


FrictionTorque = ThesisRigFriction | ThesisFlightFriction | CoulombContactFriction


@dataclass(frozen=True)
class SlipSpeedLaw:
    """Dependence of the sliding friction coefficient on the slip speed v.

    mu(v) = mu_s phi(v) with (see :func:`obturator.core.dynamics.friction_speed_factor`)

    * ``"constant"``: phi = 1, the thesis's law;
    * ``"weakening"`` (Stribeck type, static > kinetic): phi = r + (1 - r) exp(-(v/v_s)^2),
      mu_s at rest falling to r mu_s in fast slip;
    * ``"strengthening"`` (velocity-strengthening, typical of polymers such as the
      rig's lucite housing, thesis chapter III): phi = r + (1 - r) v/(v + v_s),
      r mu_s at rest rising to mu_s in fast slip.

    For the thesis laws v = R_s |omega_r|; for Coulomb contacts v is each
    contact's generalised slip speed.

    Parameters
    ----------
    kind : {"constant", "weakening", "strengthening"}
    ratio : float
        r in (0, 1] [-].
    speed : float
        v_s > 0 [m/s]. Rig slip speeds are 0 at stick and up to about
        R_s omega_p ~ 1.6 m/s at 200 rad/s.
    """

    kind: SpeedLawName = "constant"
    ratio: float = 1.0
    speed: float = 0.1

    def __post_init__(self) -> None:
        check_choice("speed_law", self.kind, SPEED_LAWS)
        check_range("speed_ratio", self.ratio, 0.0, 1.0, lo_open=True)
        check_range("slip_speed", self.speed, 0.0, math.inf, lo_open=True, unit="m/s")

    def pack(self) -> tuple[float, float, float]:
        """(code, r, v_s) for the compiled kernel."""
        return (float(SPEED_CODES[self.kind]), float(self.ratio), float(self.speed))


@dataclass(frozen=True)
class TorqueModel:
    """Total applied torque G = viscous + sliding friction (thesis Eqs. 62-64).

    Parameters
    ----------
    viscous : CouetteViscous or NakabayashiViscous or None
        Viscous gap torque; None for none.
    friction : ThesisRigFriction or ThesisFlightFriction or CoulombContactFriction or None
        Sliding-friction torque; None for none.
    speed_law : SlipSpeedLaw
        Slip-speed dependence of mu (default constant, as in the thesis).
    """

    viscous: ViscousTorque | None = None
    friction: FrictionTorque | None = None
    speed_law: SlipSpeedLaw = SlipSpeedLaw()

    def pack(self) -> tuple[float, ...]:
        """Flat parameter tuple: viscous (4 values) then friction (6 values)."""
        v = self.viscous.pack() if self.viscous is not None else (VISC_NONE, 0.0, 0.0, math.inf)
        f = (
            self.friction.pack()
            if self.friction is not None
            else (FRIC_NONE, 0.0, 1.0, math.pi / 2, 1.0, 0.0)
        )
        return tuple(float(x) for x in (*v, *f))

    @property
    def is_regularised(self) -> bool:
        """Whether a Coulomb-type (set-valued) term is present and needs a width."""
        return self.friction is not None and self.friction.mu_s > 0
