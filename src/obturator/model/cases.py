"""The thesis's built-in cases (Table 1, rig and flight columns; Figs. 9-10 Couette).

Factories return a :class:`~obturator.model.case.Case`; every argument is SI (angles
in degrees where the name says ``_deg``).
"""

from __future__ import annotations

import functools
import inspect
import math
from collections.abc import Callable, Mapping
from typing import Any

from .._docs import fill_doc
from ..errors import InputError, check_range
from ..params import PARAMS
from ..reference import COUETTE_P52, TABLE1
from ..vocab import CASE_NAMES, SPIN_MODES, TORQUE_MODELS, SpinMode, TorqueName, check_choice
from .ageing import ContactAgeing
from .case import Case
from .geometry import BoredBall
from .torques import (
    MAX_RIG_WEIGHT,
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


def _accepts_quantities(factory: Callable[..., Case]) -> Callable[..., Case]:
    """Let a case factory take pint.Quantity arguments (converted to SI, checked as usual)."""

    names = list(inspect.signature(factory).parameters)  # once, not on every call

    @functools.wraps(factory)
    def wrapper(*args: Any, **kwargs: Any) -> Case:
        bound = dict(zip(names, args, strict=False)) | kwargs
        for name, value in bound.items():
            if name in PARAMS and hasattr(value, "magnitude") and hasattr(value, "units"):
                from ..units import parse_quantity

                bound[name] = parse_quantity(name, value, PARAMS[name].pint_unit)
        return factory(**bound)

    return wrapper


def _theta0(theta0_deg: float) -> float:
    return math.radians(check_range("theta0_deg", theta0_deg, 0.0, 90.0, lo_open=True, unit="deg"))


def _check_model(torque_model: str) -> None:
    check_choice("torque_model", torque_model, TORQUE_MODELS)


#: Docstring text of the inputs every case constructor takes first
#: (:func:`obturator._docs.fill_doc`).
CASE_INPUTS_DOC = """\
spin_rate : float
    omega_p [rad/s].
mu_s : float
    Sliding friction coefficient [-].
theta0_deg : float
    theta_0 [deg]."""


@_accepts_quantities
@fill_doc(case_inputs=CASE_INPUTS_DOC)
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
    ageing: ContactAgeing | None = None,
) -> Case:
    """Spin-rig case (Table 1 "gravitational model", thesis Eqs. 56-61, 64).

    Parameters
    ----------
    {case_inputs}
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
        and psi_0 [rad]; see :class:`~obturator.model.case.Case`.
    t_max : float
        Integration limit [s]. Default 100 s: near-stick runs at low spin open
        late (about 43 s at 40 rad/s, mu_s = 0.5473).
    ageing : ContactAgeing, optional
        Static friction of the lucite seat aged for the time the contact patch takes
        to pass (:mod:`obturator.model.ageing`): mu_s becomes the fast-slip value and
        the friction at rest mu_s + b ln(1 + t_d/tau); not with `speed_law`.
    """
    _check_model(torque_model)
    ball = ball or table1_ball()
    w = ball.weight if weight is None else weight
    if ageing is not None:
        if speed_law is not None:
            raise InputError("ageing", "has its own slip-speed law; give it or speed_law")
        a_dwell = (
            patch_radius
            if patch_radius
            else hertz_patch_radius(w, ball.radius, gap, seat_material="lucite")
        )
        mu_s, speed_law = ageing.friction(mu_s, a_dwell, ball.radius, spin_rate)
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
@fill_doc(case_inputs=CASE_INPUTS_DOC)
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
    theta_cr: float | None = None,
) -> Case:
    """Flight case (Table 1 "aerodynamic model", thesis Eqs. 43-55, 63).

    The ball is pressed on the bore ring by F_p = pi r_p^2 (P_2 - P_1) behind the
    normal bow shock (Eqs. 1, 3, 43). Give either ``p1`` [Pa] or
    ``altitude_m`` [m] (standard atmosphere), or ``pressure_force`` [N] directly.

    Parameters
    ----------
    {case_inputs}
    torque_model : {"thesis", "coulomb"}
        Appendix A's two-point arm, or exact Coulomb friction at ``n_contacts``
        ring points.
    patch_radius : float or None
        Contact patch radius of the "coulomb" model [m]; None: the Hertz
        radius of the steel ball in a steel socket under each contact's load;
        0: point contacts. Ignored by "thesis".
    theta_cr : float or None
        Stop angle [rad]; None: first light, beta_s (the flight studies stop at the
        tube's start angle instead).
    """
    _check_model(torque_model)
    from ..flow import flight_pressure_force

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
        theta_cr=theta_cr,
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


def _check_derived_weight(s: Mapping[str, Any], ball: BoredBall) -> None:
    """Name the geometry input (as the config spells it) that makes the rig ball's weight
    W = rho g V [N] impossible, before the friction model reports the derived W."""
    if 0.0 <= ball.weight <= MAX_RIG_WEIGHT:
        return
    key = next(k for k in ("ball_radius", "hole_radius", "density") if k in s)
    par = PARAMS[key]
    raise InputError(
        par.config or key,
        f"{s[key]:g} {par.unit} makes the rig ball weigh W = rho g V = {ball.weight:.3g} N, "
        f"outside the allowed [0, {MAX_RIG_WEIGHT:g}] N (Table 1: R_s = 7.899 mm, "
        "rho = 7669.6 kg/m^3); a number without a unit is in SI units: write e.g. '7.899 mm'",
    )


def case_from_settings(s: Mapping[str, Any]) -> Case:
    """The :class:`Case` of merged settings: config file, flags or a study's point.

    Parameters
    ----------
    s : mapping of str to object
        Canonical field names (:data:`obturator.params.PARAMS`, plus ``case``,
        ``torque_model``, ``spin_mode``, ``n_contacts``), SI floats. Anything
        not given takes the factory's Table 1 default. On the rig the normal
        load is Table 1's measured W unless ``weight`` is given or the ball's
        geometry (``ball_radius``, ``hole_radius``, ``density``) is: then the
        weight follows the ball (W = rho g V), as in the thesis's geometry
        studies (Figs. 16-17).
    """
    name = check_choice("case", s.get("case", "spin-rig"), CASE_NAMES)
    check_choice("torque_model", s.get("torque_model", "thesis"), TORQUE_MODELS)
    check_choice("spin_mode", s.get("spin_mode", "constant"), SPIN_MODES)
    geometry_changed = any(k in s for k in ("ball_radius", "hole_radius", "density"))
    ball = table1_ball(
        radius=s.get("ball_radius"), hole_radius=s.get("hole_radius"), density=s.get("density")
    )
    common: dict[str, Any] = {
        "ball": ball,
        "torque_model": s.get("torque_model", "thesis"),
        "spin_mode": s.get("spin_mode", "constant"),
    }
    for key in ("theta0_deg", "gap", "viscosity", "t_max"):
        if key in s:
            common[key] = s[key]
    if "patch_radius" in s:
        if common["torque_model"] != "coulomb":
            raise InputError("patch_radius", "applies to torque_model 'coulomb' only")
        common["patch_radius"] = s["patch_radius"]
    for key in ("spin_rate", "mu_s"):
        if key in s:
            common[key] = s[key]
    if "p1" in s and "altitude_m" in s:
        raise InputError("altitude", "give either p1 or altitude (which sets P1), not both")
    if "n_contacts" in s and common["torque_model"] != "coulomb":
        raise InputError("n_contacts", "applies to torque_model 'coulomb' only")
    rig_only = ("theta_dot0", "release_phase", "speed_law", "speed_ratio", "slip_speed")
    if name == "spin-rig":
        if any(k in s for k in ("speed_ratio", "slip_speed")) and "speed_law" not in s:
            raise InputError("speed_law", "give the law (weakening or strengthening) too")
        if s.get("speed_law", "constant") != "constant":
            common["speed_law"] = SlipSpeedLaw(
                s["speed_law"], s.get("speed_ratio", 0.5), s.get("slip_speed", 0.05)
            )
        common["release_rate"] = (s.get("theta_dot0", 0.0), 0.0, 0.0)
        common["release_phase"] = s.get("release_phase", 0.0)
        flight_keys = ("mach", "altitude_m", "p1", "n_contacts", "bore_radius")
        extra = sorted(k for k in flight_keys if k in s)
        if extra:
            raise InputError(extra[0], "applies to --case flight only")
        if "weight" in s:
            common["weight"] = s["weight"]
        elif geometry_changed:
            _check_derived_weight(s, ball)
            common["weight"] = None  # the weight follows the modified ball
        return rig_case(**common)
    if "weight" in s:
        raise InputError("weight", "applies to --case spin-rig only")
    extra = sorted(k for k in rig_only if k in s)
    if extra:
        raise InputError(extra[0], "applies to --case spin-rig only")
    for key in ("mach", "n_contacts", "bore_radius"):
        if key in s:
            common[key] = s[key]
    if "altitude_m" in s:
        common["altitude_m"] = s["altitude_m"]
        common["p1"] = None
    elif "p1" in s:
        common["p1"] = s["p1"]
    return flight_case(**common)
