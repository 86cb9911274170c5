"""The thesis's built-in cases (Table 1, rig and flight columns; Figs. 9-10 Couette).

Factories return a :class:`~obturator.model.case.Case`; every argument is SI (angles
in degrees where the name says ``_deg``).
"""

from __future__ import annotations

import functools
import inspect
import math
from collections.abc import Callable
from typing import Any, Literal

from ..errors import InputError, check_range
from ..reference import COUETTE_P52, TABLE1
from ..vocab import CASE_NAMES, TORQUE_MODELS, SpinMode, TorqueName, check_choice
from .case import Case
from .geometry import BoredBall
from .torques import (
    CouetteViscous,
    CoulombContactFriction,
    NakabayashiViscous,
    SlipSpeedLaw,
    ThesisFlightFriction,
    ThesisRigFriction,
    TorqueModel,
    hertz_patch_radius,
)

__all__ = [
    "TABLE1",
    "table1_ball",
    "rig_case",
    "flight_case",
    "couette_case",
    "case_from_settings",
    "CASE_NAMES",
    "TORQUE_MODELS",
]


def table1_ball(
    *,
    density: float | None = None,
    hole_radius: float | None = None,
    radius: float | None = None,
) -> BoredBall:
    """The Table 1 ball (R_s = 7.899 mm, r_s = 4.72 mm, rho = 7669.6 kg/m^3), or a variant."""
    return BoredBall(
        radius=TABLE1["ball_radius"] if radius is None else radius,
        hole_radius=TABLE1["hole_radius"] if hole_radius is None else hole_radius,
        density=TABLE1["density"] if density is None else density,
    )


#: Units of the factories' quantity arguments (a pint.Quantity is converted to these).
_UNITS = {
    "spin_rate": "rad/s",
    "mu_s": "",
    "theta0_deg": "deg",
    "weight": "N",
    "gap": "m",
    "viscosity": "Pa*s",
    "patch_radius": "m",
    "t_max": "s",
    "mach": "",
    "p1": "Pa",
    "altitude_m": "m",
    "pressure_force": "N",
    "bore_radius": "m",
}


def _accepts_quantities(factory: Callable[..., Case]) -> Callable[..., Case]:
    """Let a case factory take pint.Quantity arguments (converted to SI, checked as usual)."""

    @functools.wraps(factory)
    def wrapper(*args: Any, **kwargs: Any) -> Case:
        names = list(inspect.signature(factory).parameters)
        bound = dict(zip(names, args, strict=False)) | kwargs
        for name, value in bound.items():
            if name in _UNITS and hasattr(value, "magnitude") and hasattr(value, "units"):
                from ..io import parse_quantity

                bound[name] = parse_quantity(name, value, _UNITS[name])
        return factory(**bound)

    return wrapper


def _theta0(theta0_deg: float) -> float:
    return math.radians(check_range("theta0_deg", theta0_deg, 0.0, 90.0, lo_open=True, unit="deg"))


def _check_model(torque_model: str) -> None:
    check_choice("torque_model", torque_model, TORQUE_MODELS)


@_accepts_quantities
def rig_case(
    spin_rate: float = TABLE1["rig_spin_rate"],
    mu_s: float = TABLE1["mu_s"],
    *,
    theta0_deg: float = TABLE1["theta0_deg"],
    torque_model: TorqueName = "thesis",
    spin_mode: SpinMode = "constant",
    weight: float | None = TABLE1["rig_weight"],
    ball: BoredBall | None = None,
    gap: float = TABLE1["gap"],
    viscosity: float = TABLE1["viscosity"],
    patch_radius: float | None = None,
    speed_law: SlipSpeedLaw | None = None,
    release_rate: tuple[float, float, float] = (0.0, 0.0, 0.0),
    release_phase: float = 0.0,
    t_max: float = 100.0,
) -> Case:
    """Spin-rig case (Table 1 "gravitational model", thesis Eqs. 56-61, 64).

    Parameters
    ----------
    spin_rate : float
        omega_p [rad/s].
    mu_s : float
        Sliding friction coefficient [-].
    theta0_deg : float
        theta_0 [deg].
    torque_model : {"thesis", "coulomb"}
        Eq. (61) or exact Coulomb friction at the single bottom contact.
    spin_mode : {"constant", "free", "thesis-energy"}
        The rig is driven: "constant" is the physical choice.
    weight : float or None
        Normal load W [N]; Table 1's measured 0.07987 N by default, None for
        the ball's computed weight (which is what density/hole studies vary).
    ball : BoredBall, optional
        Defaults to :func:`table1_ball`.
    gap, viscosity : float
        Gap h [m] and mu_f [Pa s] of the Nakabayashi viscous torque (Eq. 42).
    patch_radius : float or None
        Contact patch radius of the "coulomb" model [m]; None: the Hertz
        radius of the steel ball in the rig's lucite housing (chapter III,
        Fig. 22) under W, 0.279 mm for Table 1; 0: a point contact (not well
        posed: its t_cr does not converge in the width). Ignored by "thesis".
    speed_law : SlipSpeedLaw, optional
        Slip-speed dependence of mu (default: constant, the thesis's law).
    release_rate, release_phase
        Release transient (theta_dot_0, phi_dot_0, psi_dot_0 - omega_p) [rad/s]
        and psi_0 [rad]; see :class:`~obturator.solve.Case`.
    t_max : float
        Integration limit [s]. Default 100 s: near-stick runs at low spin open
        late (about 43 s at 40 rad/s, mu_s = 0.5473).
    """
    _check_model(torque_model)
    ball = ball or table1_ball()
    w = ball.weight if weight is None else weight
    if torque_model == "thesis":
        friction = ThesisRigFriction(mu_s, w, ball.radius)
    else:
        a = (
            hertz_patch_radius(w, ball.radius, gap, seat_material="lucite")
            if patch_radius is None
            else patch_radius
        )
        friction = CoulombContactFriction(mu_s, w, ball.radius, patch_radius=a)
    torque = TorqueModel(
        NakabayashiViscous(ball.radius, gap, viscosity), friction, speed_law or SlipSpeedLaw()
    )
    return Case(
        ball,
        torque,
        spin_rate,
        _theta0(theta0_deg),
        spin_mode=spin_mode,
        t_max=t_max,
        name="spin-rig",
        release_rate=tuple(float(x) for x in release_rate),
        release_phase=float(release_phase),
    )


@_accepts_quantities
def flight_case(
    spin_rate: float = TABLE1["flight_spin_rate"],
    mu_s: float = TABLE1["mu_s"],
    *,
    theta0_deg: float = TABLE1["theta0_deg"],
    torque_model: TorqueName = "thesis",
    spin_mode: SpinMode = "constant",
    mach: float = TABLE1["mach"],
    p1: float | None = TABLE1["p1"],
    altitude_m: float | None = None,
    gamma: float = TABLE1["gamma"],
    pressure_force: float | None = None,
    n_contacts: int = 2,
    ball: BoredBall | None = None,
    bore_radius: float = TABLE1["bore_radius"],
    gap: float = TABLE1["gap"],
    viscosity: float = TABLE1["viscosity"],
    patch_radius: float | None = None,
    t_max: float = 0.5,
) -> Case:
    """Flight case (Table 1 "aerodynamic model", thesis Eqs. 43-55, 63).

    The ball is pressed on the bore ring by F_p = pi r_p^2 (P_2 - P_1) behind the
    normal bow shock (Eqs. 1, 3, 43). Give either ``p1`` [Pa] or
    ``altitude_m`` [m] (standard atmosphere), or ``pressure_force`` [N] directly.

    Parameters
    ----------
    torque_model : {"thesis", "coulomb"}
        Appendix A's two-point arm, or exact Coulomb friction at ``n_contacts``
        ring points.
    patch_radius : float or None
        Contact patch radius of the "coulomb" model [m]; None: the Hertz
        radius of the steel ball in a steel socket under each contact's load;
        0: point contacts. Ignored by "thesis".
    """
    _check_model(torque_model)
    from ..flow.gasdynamics import flight_pressure_force

    ball = ball or table1_ball()
    if pressure_force is None:
        if altitude_m is not None:
            p1 = None
        pressure_force = float(
            flight_pressure_force(
                mach, altitude_m=altitude_m, p1=p1, bore_radius=bore_radius, gamma=gamma
            )
        )
    beta = math.asin(
        check_range(
            "bore_radius", bore_radius, 0.0, ball.radius, lo_open=True, hi_open=True, unit="m"
        )
        / ball.radius
    )
    if torque_model == "thesis":
        friction = ThesisFlightFriction(mu_s, pressure_force, ball.radius, beta)
    else:
        point = CoulombContactFriction(mu_s, pressure_force, ball.radius, beta, n_contacts)
        a = (
            hertz_patch_radius(point.load_per_contact, ball.radius, gap)
            if patch_radius is None
            else patch_radius
        )
        friction = CoulombContactFriction(
            mu_s, pressure_force, ball.radius, beta, n_contacts, patch_radius=a
        )
    torque = TorqueModel(NakabayashiViscous(ball.radius, gap, viscosity), friction)
    return Case(
        ball,
        torque,
        spin_rate,
        _theta0(theta0_deg),
        spin_mode=spin_mode,
        t_max=t_max,
        name="flight",
    )


def couette_case(scale: float = 1.0, *, t_max: float = 0.1) -> Case:
    """Viscous-only flight case of Figs. 9-10 (Couette S of Eq. 34, times `scale`).

    Inputs from the thesis p. 52 (:data:`obturator.reference.COUETTE_P52`):
    R_s = 7.62 mm, r_s = 4.7625 mm, h = 0.0254 mm, rho = 7800 kg/m^3,
    mu = 1.92e-5 Pa s, omega_p = 12042.77 rad/s.
    """
    p52 = COUETTE_P52
    ball = BoredBall(p52["ball_radius"], p52["hole_radius"], p52["density"])
    torque = TorqueModel(CouetteViscous(ball.radius, p52["gap"], p52["viscosity"], scale), None)
    return Case(
        ball,
        torque,
        p52["spin_rate"],
        math.radians(TABLE1["theta0_deg"]),
        t_max=t_max,
        name=f"couette-x{scale:g}",
    )
