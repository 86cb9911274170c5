"""Plain-Python baseline of the obturator model, as a careful user would write it.

The benchmark compares :mod:`obturator` with this file: the same equations
(quaternion attitude, Euler's equations for the axisymmetric ball, thesis
Eqs. 5a-5c), the same torques (Nakabayashi viscous torque, Eqs. 39-42; rig
sliding friction, Eq. 61; flight sliding friction with the Appendix A arm),
the same regularisation of the Coulomb direction
|omega_r| / sqrt(|omega_r|^2 + delta^2) (magnitude only; arm from the true
direction) and the same parameters, written in
NumPy without any compilation and integrated with
``scipy.integrate.solve_ivp(method="LSODA")`` with a terminal event at
theta = theta_cr.

Nothing here imports the package's compiled kernels: the parameters are read
from the public dataclasses of a :class:`~obturator.model.case.Case` (ball inertias,
torque coefficients), which is how a user of the thesis's tables would get them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from obturator.model.case import Case
from obturator.model.torques import NakabayashiViscous, ThesisFlightFriction, ThesisRigFriction

__all__ = ["BaselineModel", "model_from_case", "initial_state", "solve_baseline"]


@dataclass(frozen=True)
class BaselineModel:
    """Plain parameters of one case (SI units).

    Attributes
    ----------
    a, c : float
        Transverse and axial moments of inertia of the ball [kg m^2].
    spin_rate : float
        Projectile spin omega_p, held constant (driven rig) [rad/s].
    viscous : float
        Laminar viscous coefficient S [N m s] (Eq. 42).
    viscous_turbulent : float
        K of the turbulent branch M = K |omega_r|^1.75 [N m s^1.75] (Eq. 39).
    transition_rate : float
        |omega_r| above which the turbulent branch applies [rad/s].
    friction : float
        Sliding-friction moment scale [N m]: mu_s W R_s (rig) or
        mu_s F_p cos(beta) R_s (flight).
    flight : bool
        Flight arm (Appendix A) instead of the rig arm (Eq. 61).
    contact_angle : float
        beta [rad] (flight only).
    delta : float
        Regularisation width of the Coulomb direction [rad/s].
    theta0, theta_cr : float
        Initial and opening nutation angles [rad].
    t_max : float
        Integration limit [s].
    """

    a: float
    c: float
    spin_rate: float
    viscous: float
    viscous_turbulent: float
    transition_rate: float
    friction: float
    flight: bool
    contact_angle: float
    delta: float
    theta0: float
    theta_cr: float
    t_max: float

    def rhs(self, t: float, y: np.ndarray) -> np.ndarray:
        """Time derivative of [q0, q1, q2, q3, w1, w2, w3, omega_p].

        Parameters
        ----------
        t : float
            Time [s] (unused: autonomous).
        y : ndarray, shape (8,)
            Attitude quaternion (body -> inertial), body rates [rad/s], spin [rad/s].

        Returns
        -------
        ndarray, shape (8,)
        """
        q = y[:4] / np.linalg.norm(y[:4])
        w = y[4:7]
        rot = _rotation(q)
        w_rel = rot @ w - np.array([0.0, 0.0, y[7]])  # omega_r in inertial axes (Eq. 35)
        speed = np.linalg.norm(w_rel)
        k = self.viscous
        if speed >= self.transition_rate:
            k = self.viscous_turbulent * speed**0.75
        torque = -k * w_rel
        if speed > 0.0:
            # thesis arm from the true slip direction; only the magnitude is regularised
            e = w_rel / speed
            x = speed / self.delta
            if self.flight:
                sb, cb = math.sin(self.contact_angle), math.cos(self.contact_angle)
                arm2 = 1.0 - sb * sb * e[0] ** 2 - cb * cb * e[2] ** 2
            else:
                arm2 = 1.0 - e[0] ** 2
            sat = x / math.sqrt(1.0 + x * x)
            torque = torque - self.friction * math.sqrt(max(arm2, 0.0)) * sat * e
        g = rot.T @ torque  # body axes
        a, c = self.a, self.c
        dw = np.array(
            [
                (g[0] - (c - a) * w[1] * w[2]) / a,
                (g[1] + (c - a) * w[0] * w[2]) / a,
                g[2] / c,
            ]
        )
        q0, q1, q2, q3 = y[:4]
        dq = 0.5 * np.array(
            [
                -q1 * w[0] - q2 * w[1] - q3 * w[2],
                q0 * w[0] + q2 * w[2] - q3 * w[1],
                q0 * w[1] + q3 * w[0] - q1 * w[2],
                q0 * w[2] + q1 * w[1] - q2 * w[0],
            ]
        )
        return np.concatenate([dq, dw, [0.0]])

    def nutation(self, t: float, y: np.ndarray) -> float:
        """Event function theta - theta_cr [rad] (terminal, decreasing)."""
        q = y[:4] / np.linalg.norm(y[:4])
        r = _rotation(q)
        theta = math.atan2(math.hypot(r[0, 2], r[1, 2]), r[2, 2])
        return theta - self.theta_cr


def _rotation(q: np.ndarray) -> np.ndarray:
    q0, q1, q2, q3 = q
    return np.array(
        [
            [1 - 2 * (q2 * q2 + q3 * q3), 2 * (q1 * q2 - q0 * q3), 2 * (q1 * q3 + q0 * q2)],
            [2 * (q1 * q2 + q0 * q3), 1 - 2 * (q1 * q1 + q3 * q3), 2 * (q2 * q3 - q0 * q1)],
            [2 * (q1 * q3 - q0 * q2), 2 * (q2 * q3 + q0 * q1), 1 - 2 * (q1 * q1 + q2 * q2)],
        ]
    )


def model_from_case(case: Case, friction_width: float = 1e-6) -> BaselineModel:
    """Plain parameters of a thesis-torque, constant-spin :class:`Case`.

    Parameters
    ----------
    case : Case
        Built by :func:`obturator.model.cases.rig_case` or
        :func:`obturator.model.cases.flight_case` with ``torque_model="thesis"``.
    friction_width : float
        delta / omega_p [-] (the package's ``SolverOptions.friction_width``).

    Returns
    -------
    BaselineModel
    """
    if case.spin_mode != "constant":
        raise ValueError("the baseline covers the constant-spin model only")
    visc = case.torque.viscous
    fric = case.torque.friction
    if not isinstance(visc, NakabayashiViscous):
        raise ValueError("the baseline covers the Nakabayashi viscous torque only")
    if not isinstance(fric, ThesisRigFriction | ThesisFlightFriction):
        raise ValueError("the baseline covers the thesis friction torques only")
    flight = isinstance(fric, ThesisFlightFriction)
    return BaselineModel(
        a=case.ball.transverse_inertia,
        c=case.ball.axial_inertia,
        spin_rate=case.spin_rate,
        viscous=visc.coefficient,
        viscous_turbulent=visc.turbulent_coefficient,
        transition_rate=visc.transition_rate if visc.turbulent else math.inf,
        friction=fric.moment_scale,
        flight=flight,
        contact_angle=fric.contact_angle if flight else math.pi / 2,
        delta=friction_width * case.spin_rate,
        theta0=case.theta0,
        theta_cr=case.opening_angle,
        t_max=case.t_max,
    )


def initial_state(model: BaselineModel) -> np.ndarray:
    """Co-rotating release (thesis p. 45): theta = theta_0, psi = phi = 0, psi_dot = omega_p."""
    th = model.theta0
    w = model.spin_rate
    q = [math.cos(th / 2), math.sin(th / 2), 0.0, 0.0]  # rotation by theta about x
    return np.array([*q, 0.0, w * math.sin(th), w * math.cos(th), w])


def solve_baseline(
    model: BaselineModel, rtol: float = 1e-6, atol: float = 1e-9
) -> tuple[float, int, object]:
    """Integrate with LSODA to theta = theta_cr (terminal event) or t_max.

    Returns
    -------
    tuple
        (t_cr [s] or NaN, nfev, the solve_ivp result).
    """

    def event(t: float, y: np.ndarray) -> float:
        return model.nutation(t, y)

    event.terminal = True  # type: ignore[attr-defined]
    event.direction = -1  # type: ignore[attr-defined]
    sol = solve_ivp(
        model.rhs,
        (0.0, model.t_max),
        initial_state(model),
        method="LSODA",
        rtol=rtol,
        atol=atol,
        events=event,
    )
    t_cr = float(sol.t_events[0][0]) if len(sol.t_events[0]) else math.nan
    return t_cr, int(sol.nfev), sol
