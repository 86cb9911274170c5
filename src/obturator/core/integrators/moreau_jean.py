"""Moreau-Jean time-stepping of the friction law with the exact set: a cross-check.

An event-capturing scheme (Moreau 1988; Jean 1999; Acary and Brogliato, *Numerical
Methods for Nonsmooth Dynamical Systems*, Springer 2008, ch. 10), independent of the
event-driven :mod:`.stick_slip`: fixed steps h, no mode, no event location; the friction
enters as an impulse P = h G_f solved at the end of each step with the set-valued law
of ``docs/stick_slip.md`` (thesis Eqs. 56-64, Appendix A):

* angular momentum (inertial) L_{k+1} = L_k + P, rates omega_{k+1} = I_k^{-1} L_{k+1}
  (I_k = R_k diag(A, A, C) R_k^T: the gyroscopic terms are those of L conserved);
* the one-step law: stick, omega_r,k+1 = 0, with P = -I_k omega_r,free, if P / h lies
  in the admissible set F (:func:`~obturator.core.friction_sets.stick_margin`);
  otherwise slip, omega_r,k+1 = v != 0 solving v = omega_r,free + h I_k^{-1} G(v) with
  G the law at full magnitude (and the viscous moment, Eq. 42), by Newton's method
  from v along -P (the direction in which a saturated friction gives way);
* attitude q_{k+1} = exp(h omega_{k+1} / 2) q_k (inertial rotation vector), body rates
  from L_{k+1} at q_{k+1}.

First order in h (the impulse is implicit, the inertia taken at the step start). The
opening is the first step with theta <= theta_cr, its time interpolated linearly
within the step. Constant spin only (the rig), quaternion formulation; ``h0`` of the
controls is the step; no recorded steps or output times.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ...errors import InputError
from ..dynamics import applied_torque
from ..friction_sets import relative_rate, stick_margin, turn_by
from ..jit_flags import REFCOUNT
from ..layout import (
    FORM_QUATERNION,
    P_A,
    P_C,
    P_FORM,
    P_SPIN_MODE,
    P_THETA_CR,
    P_WIDTH,
    SPIN_CONSTANT,
)
from .contract import Controls, Problem, RawSolution, Status
from .stick_slip_modes import check_set_valued_law

__all__ = ["integrate"]


def integrate(problem: Problem, controls: Controls) -> RawSolution:
    """Moreau-Jean steps of ``controls.h0`` [s] from t0 to the opening or t_max.

    Raises
    ------
    InputError
        Outside its scope: not the quaternion formulation, not a constant spin, not
        a law without a set-valued form (:func:`.stick_slip_modes.check_set_valued_law`),
        or recorded steps / output times asked for.
    """
    p = np.array(problem.p, dtype=float)
    if p[P_FORM] != FORM_QUATERNION:
        raise InputError("formulation", "Moreau-Jean integrates 'quaternion' only")
    if p[P_SPIN_MODE] != SPIN_CONSTANT:
        raise InputError("spin_mode", "Moreau-Jean takes a constant spin only")
    check_set_valued_law(p, "Moreau-Jean")
    if controls.record or controls.t_eval.shape[0] > 0:
        raise InputError("t_eval", "Moreau-Jean returns the opening time only")
    p[P_WIDTH] = 0.0
    status, t, t_event, y, n_steps, nfev = _steps(
        np.array(problem.y0, dtype=float), p, problem.t0, controls.t_max, controls.h0,
        controls.max_steps,
    )  # fmt: skip
    y_event = y.copy() if status == Status.OPENED else np.full(y.shape[0], math.nan)
    empty = np.empty(0)
    return RawSolution(
        status, t_event, y_event, empty, np.empty((0, y.shape[0])), nfev, 0, n_steps, 0, t, y
    )


@njit(cache=True, **REFCOUNT, fastmath=False, error_model="python")
def _rotation(y: np.ndarray) -> np.ndarray:
    """R(q / |q|), body -> inertial."""
    n = math.sqrt(y[0] ** 2 + y[1] ** 2 + y[2] ** 2 + y[3] ** 2)
    q0, q1, q2, q3 = y[0] / n, y[1] / n, y[2] / n, y[3] / n
    r = np.empty((3, 3))
    r[0, 0] = 1.0 - 2.0 * (q2 * q2 + q3 * q3)
    r[0, 1] = 2.0 * (q1 * q2 - q0 * q3)
    r[0, 2] = 2.0 * (q1 * q3 + q0 * q2)
    r[1, 0] = 2.0 * (q1 * q2 + q0 * q3)
    r[1, 1] = 1.0 - 2.0 * (q1 * q1 + q3 * q3)
    r[1, 2] = 2.0 * (q2 * q3 - q0 * q1)
    r[2, 0] = 2.0 * (q1 * q3 - q0 * q2)
    r[2, 1] = 2.0 * (q2 * q3 + q0 * q1)
    r[2, 2] = 1.0 - 2.0 * (q1 * q1 + q2 * q2)
    return r


@njit(cache=True, **REFCOUNT, fastmath=False, error_model="python")
def _nutation(y: np.ndarray) -> float:
    """theta [rad]: the angle of the hole axis z from Z, z_Z = 1 - 2 (q1^2 + q2^2) / |q|^2."""
    zz = 1.0 - 2.0 * (y[1] ** 2 + y[2] ** 2) / (y[0] ** 2 + y[1] ** 2 + y[2] ** 2 + y[3] ** 2)
    return math.acos(min(1.0, max(-1.0, zz)))


@njit(cache=True, **REFCOUNT, fastmath=False, error_model="python")
def _residual(v, w_free, h, inv_i, p):
    """v - omega_r,free - h I^{-1} G(v): zero at the slip of the step's end."""
    g = applied_torque(v[0], v[1], v[2], p)
    out = np.empty(3)
    for i in range(3):
        out[i] = (
            v[i] - w_free[i] - h * (inv_i[i, 0] * g[0] + inv_i[i, 1] * g[1] + inv_i[i, 2] * g[2])
        )
    return out


@njit(cache=True, **REFCOUNT, fastmath=False, error_model="python")
def _slip_of_step(v, w_free, h, inv_i, p):
    """Newton's method (finite-difference Jacobian, halving steps) for the slip at the
    step's end from the guess `v`; returns it and the residual evaluations."""
    nfev = 0
    res = _residual(v, w_free, h, inv_i, p)
    nfev += 1
    jac = np.empty((3, 3))
    for _ in range(60):
        norm = math.sqrt(res[0] ** 2 + res[1] ** 2 + res[2] ** 2)
        vn = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
        if norm <= 1e-15 * vn:
            break
        d = 1e-7 * vn
        for j in range(3):
            vj = v.copy()
            vj[j] += d
            jac[:, j] = (_residual(vj, w_free, h, inv_i, p) - res) / d
        nfev += 3
        step = np.linalg.solve(jac, -res)
        lam = 1.0
        while lam > 1e-6:
            trial = v + lam * step
            rt = _residual(trial, w_free, h, inv_i, p)
            nfev += 1
            if math.sqrt(rt[0] ** 2 + rt[1] ** 2 + rt[2] ** 2) < norm:
                v, res = trial, rt
                break
            lam *= 0.5
        else:
            break
    return v, nfev


@njit(cache=True, **REFCOUNT, fastmath=False, error_model="python")
def _steps(y, p, t, t_max, h, max_steps):
    """The stepping loop; returns (status, t, t_event, y, steps, residual evaluations)."""
    a, c = p[P_A], p[P_C]
    wp = y[7]
    theta_cr = p[P_THETA_CR]
    j_diag = np.array([a, a, c])
    nfev = 0
    theta_old = _nutation(y)
    for k in range(max_steps):
        if t >= t_max:
            return Status.T_MAX, t, math.nan, y, k, nfev
        r = _rotation(y)
        inv_i = r @ np.diag(1.0 / j_diag) @ r.T
        big_l = r @ (j_diag * y[4:7])
        wr = np.array(relative_rate(y, wp))  # omega_r,free: L_k at I_k
        # stick: the impulse that zeroes the slip at the step's end
        p_stick = -(r @ np.diag(j_diag) @ r.T) @ wr
        if stick_margin(p_stick[0] / h, p_stick[1] / h, p_stick[2] / h, p) >= 0.0:
            v = np.zeros(3)
            impulse = p_stick
        else:
            g_s = p_stick / h
            gn = math.sqrt(g_s[0] ** 2 + g_s[1] ** 2 + g_s[2] ** 2)
            radius = gn + stick_margin(g_s[0], g_s[1], g_s[2], p)
            guess = h * (inv_i @ (g_s * (radius / gn) - g_s))
            if math.sqrt(guess[0] ** 2 + guess[1] ** 2 + guess[2] ** 2) == 0.0:
                guess = -1e-12 * abs(wp) * g_s / gn
            v, nf = _slip_of_step(guess, wr, h, inv_i, p)
            nfev += nf
            impulse = big_l * 0.0
            g = applied_torque(v[0], v[1], v[2], p)
            for i in range(3):
                impulse[i] = h * g[i]
        big_l = big_l + impulse
        omega = inv_i @ big_l  # = v + omega_p Z
        turn_by(y, h * omega[0], h * omega[1], h * omega[2])
        r1 = _rotation(y)
        w_body = (r1.T @ big_l) / j_diag
        y[4], y[5], y[6] = w_body[0], w_body[1], w_body[2]
        t += h
        theta = _nutation(y)
        if theta <= theta_cr < theta_old:
            t_event = t - h * (theta_cr - theta) / (theta_old - theta)
            return Status.OPENED, t, t_event, y, k + 1, nfev
        theta_old = theta
    return Status.STEP_LIMIT, t, math.nan, y, max_steps, nfev
