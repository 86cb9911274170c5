"""The obturator design of the flight studies and its constant-load (thesis) opening.

:class:`ObturatorDesign` is the ball, socket and friction of one design (Table 1 by
default) that the envelope studies vary; :func:`constant_case` is the thesis's flight
case at the muzzle conditions (constant load, Eqs. 1, 3, 43) and
:func:`constant_opening` its t_cr with the convergence check. The trajectory-coupled
opening of the same design is :mod:`obturator.envelope.coupled`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from dataclasses import dataclass, fields
from typing import Any

from ..errors import InputError, check_range, replace_fields
from ..flow import pressure_force
from ..model.case import Case
from ..model.cases import TABLE1, flight_case
from ..model.geometry import BoredBall
from ..model.start import START_BOUNDS, start_angle
from ..solve import SolverOptions, convergence_check, opening_time
from .trajectory import Launch

__all__ = ["ObturatorDesign", "constant_case", "constant_opening"]


@functools.lru_cache(maxsize=8192)
def _start_angle(
    mach: float, ball: BoredBall, bore_radius: float, gamma: float, altitude_m: float, bound: str
) -> float:
    """:func:`~obturator.model.start.start_angle` (the bore as capture area), memoised:
    a pure function of its arguments, asked for the same Mach numbers by every run of a
    flight at one altitude. Each call computes only its bound: the nominal one Eq. 2 on
    the lens and the inverse of the open area, the early one that and the inverse of
    the turned window, the late one the friction factor and the Fanno relations before the
    inverse of the open area (a root search each)."""
    return start_angle(mach, ball, bore_radius, bound, gamma=gamma, altitude_m=altitude_m)


@dataclass(frozen=True)
class ObturatorDesign:
    """Ball, socket and bore of the obturator (Table 1 flight column by default).

    Parameters
    ----------
    mu_s : float
        Sliding friction coefficient [-] (Table 1: 0.35).
    theta0_deg : float
        Initial nutation theta_0 [deg] (87.25).
    gap : float
        Ball-socket gap h [m] (5.08e-5).
    hole_radius : float
        Hole radius of the ball r_s [m] (4.72e-3).
    ball_radius : float
        Ball radius R_s [m] (7.899e-3).
    density : float
        Ball density rho [kg/m^3] (7669.6).
    bore_radius : float
        Projectile bore radius r_p [m] (4.72e-3): sets F_p and the contact
        angle beta = asin(r_p / R_s) (Eq. 47).
    viscosity : float
        Gap fluid viscosity mu_f [Pa s] (1.917e-5).
    torque_model : {"thesis", "coulomb"}
        Friction model of :func:`obturator.model.cases.flight_case`.
    gamma : float
        Ratio of specific heats of air [-] (1.4).
    n_contacts : int, optional
        Coulomb contacts of ``torque_model="coulomb"`` (default that of
        :func:`obturator.model.cases.flight_case`, 2).
    patch_radius : float, optional
        Contact patch radius of ``torque_model="coulomb"`` [m] (default the Hertz radius).
    """

    mu_s: float = TABLE1["mu_s"]
    theta0_deg: float = TABLE1["theta0_deg"]
    gap: float = TABLE1["gap"]
    hole_radius: float = TABLE1["hole_radius"]
    ball_radius: float = TABLE1["ball_radius"]
    density: float = TABLE1["density"]
    bore_radius: float = TABLE1["bore_radius"]
    viscosity: float = TABLE1["viscosity"]
    torque_model: str = "thesis"
    gamma: float = TABLE1["gamma"]
    n_contacts: int | None = None
    patch_radius: float | None = None

    def __post_init__(self) -> None:
        for name in ("n_contacts", "patch_radius"):
            if getattr(self, name) is not None and self.torque_model != "coulomb":
                raise InputError(name, "applies to torque_model 'coulomb' only")
        check_range("mu_s", self.mu_s, 0.0, 2.0)
        check_range("gap", self.gap, 0.0, 1e-3, lo_open=True, unit="m")
        check_range("viscosity", self.viscosity, 0.0, lo_open=True, unit="Pa s")
        check_range("gamma", self.gamma, 1.0, 3.0, lo_open=True)
        check_range(
            "bore_radius",
            self.bore_radius,
            0.0,
            self.ball_radius,
            lo_open=True,
            hi_open=True,
            unit="m",
        )
        # builds the ball and the case once: geometry and theta_0 > beta_s
        self.case(1.0, 1.0, 1.0)

    def ball(self) -> BoredBall:
        """The bored ball (R_s, r_s, rho)."""
        return self._ball

    @functools.cached_property
    def _ball(self) -> BoredBall:
        # built once per design (immutable): the flight studies build a case a segment
        return BoredBall(self.ball_radius, self.hole_radius, self.density)

    @property
    def mass(self) -> float:
        """Ball mass [kg]."""
        return self.ball().mass

    def case(
        self, force: float, spin_rate: float, t_max: float, theta_cr: float | None = None
    ) -> Case:
        """Thesis flight case with load F_p = `force` [N] and spin `spin_rate` [rad/s].

        Parameters
        ----------
        force : float
            F_p [N].
        spin_rate : float
            omega_p [rad/s].
        t_max : float
            Integration limit [s].
        theta_cr : float, optional
            Stop angle [rad]; default first light, beta_s.
        """
        return flight_case(
            spin_rate,
            self.mu_s,
            theta0_deg=self.theta0_deg,
            torque_model=self.torque_model,  # type: ignore[arg-type]
            pressure_force=force,
            ball=self.ball(),
            bore_radius=self.bore_radius,
            gap=self.gap,
            viscosity=self.viscosity,
            t_max=t_max,
            theta_cr=theta_cr,
            **{
                k: v
                for k, v in (("n_contacts", self.n_contacts), ("patch_radius", self.patch_radius))
                if v is not None
            },
        )

    def start_angle(
        self, altitude_m: float = 0.0, bound: str = "nominal"
    ) -> Callable[[float], float]:
        """theta_start(M) [rad] of this design (NaN where the tube cannot start).

        :func:`obturator.model.start.start_angle` with the bore as capture
        area, memoised per process (:func:`_start_angle`). `bound`
        ``"nominal"`` is Eq. 2 on the frictionless lens, ``"late"`` the late bound
        (wall friction and the lowest discharge coefficient; NaN where it never
        starts), ``"early"`` the flow turned through the hole.
        """
        ball = self.ball()
        if bound not in START_BOUNDS:
            raise InputError("bound", f"{bound!r}; allowed: {', '.join(START_BOUNDS)}")

        def angle(mach: float) -> float:
            return _start_angle(mach, ball, self.bore_radius, self.gamma, altitude_m, bound)

        return angle

    def with_(self, **changes: Any) -> ObturatorDesign:
        """A copy with fields replaced (validated again)."""
        return replace_fields(self, "design", changes)

    def to_dict(self) -> dict[str, Any]:
        """Field values (SI) as a JSON-ready dict."""
        out = {f.name: getattr(self, f.name) for f in fields(self)}
        # the Coulomb contacts only where given: a design without them keeps its identity
        return {k: v for k, v in out.items() if v is not None}


def constant_case(design: ObturatorDesign, launch: Launch, t_max: float) -> Case:
    """The thesis's constant-load flight case at the muzzle conditions of `launch`.

    F_p from the normal shock at the muzzle Mach number and the launch
    altitude's pressure, omega_p the muzzle spin (:attr:`Launch.muzzle_spin`).
    """
    p1 = _pressure(launch.altitude_m)
    force = float(pressure_force(launch.mach, p1, design.bore_radius, design.gamma))
    return design.case(force, launch.muzzle_spin, t_max)


def _pressure(altitude_m: float) -> float:
    from .trajectory import air_state

    return air_state(altitude_m)[0]


def constant_opening(
    design: ObturatorDesign,
    launch: Launch,
    options: SolverOptions | None = None,
    *,
    t_max: float = 1.0,
    check: bool = True,
    start: bool = False,
    bound: str = "nominal",
) -> tuple[float, dict[str, Any] | None]:
    """Constant-load t_cr [s] at the muzzle conditions and its convergence check.

    With ``start=True`` the time is t_start, to theta_start(M_0) of
    :meth:`ObturatorDesign.start_angle` (NaN where the tube cannot start), of its
    `bound` (``"nominal"``, ``"late"``, ``"early"``).

    Returns
    -------
    (float, dict or None)
        t_cr (NaN if not opened by `t_max`) and
        :meth:`obturator.solve.ConvergenceCheck.to_dict` (None with ``check=False``).
    """
    case = constant_case(design, launch, t_max)
    if start:  # run on to theta_start at the muzzle Mach, the closed-bore load kept
        theta = design.start_angle(launch.altitude_m, bound)(launch.mach)
        if not math.isfinite(theta):
            return math.nan, None
        case = case.with_(theta_cr=theta)
    t = opening_time(case, options)
    if not check:
        return t, None
    return t, convergence_check(case, options, opening_time_s=t).to_dict()
