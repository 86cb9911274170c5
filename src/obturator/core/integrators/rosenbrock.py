"""Compiled stiff integrator: Shampine's L-stable Rosenbrock pair (ode23s).

The method is the second-order Rosenbrock formula with a third-order error
estimate and free dense output of Shampine & Reichelt (SIAM J. Sci. Comput.
18, 1997), the one behind MATLAB's ode23s. It is L-stable, so the stiff
sticking phases of the regularised Coulomb friction (Jacobian ~ mu N R_s / (A
delta)) cost no more steps than their accuracy needs. The Jacobian is formed
by forward differences every step (:func:`.common.jacobian`); the 8x8
iteration matrix is factored by :func:`.linalg.lu_factor`.

:func:`integrate` keeps the contract of :mod:`.contract`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..dynamics import nutation_angle_of_state, rhs
from ..jit_flags import REFCOUNT
from ..layout import N_STATE, P_THETA_CR
from .common import (
    append_row,
    bracket_closed,
    crossed,
    illinois_trial,
    illinois_update,
    jacobian,
    record_row,
    rms_norm,
    start,
    underflow,
)
from .contract import RawSolution, Status
from .linalg import lu_factor, lu_solve

__all__ = ["integrate"]

_D = 1.0 / (2.0 + math.sqrt(2.0))
_E32 = 6.0 + math.sqrt(2.0)


@njit(cache=True, fastmath=False, error_model="python", **REFCOUNT)
def _step(t, y, h, f0, jac, p, lu, piv, k1, k2, k3, f1, f2, ynew, work) -> bool:
    """One ode23s step of size h; fills ynew, k1, k2 and the error in k3."""
    n = N_STATE
    for i in range(n):
        for j in range(n):
            lu[i, j] = -h * _D * jac[i, j]
        lu[i, i] += 1.0
    if not lu_factor(lu, piv):
        return False
    for i in range(n):
        k1[i] = f0[i]
    lu_solve(lu, piv, k1)
    for i in range(n):
        work[i] = y[i] + 0.5 * h * k1[i]
    rhs(t + 0.5 * h, work, p, f1)
    for i in range(n):
        k2[i] = f1[i] - k1[i]
    lu_solve(lu, piv, k2)
    for i in range(n):
        k2[i] += k1[i]
        ynew[i] = y[i] + h * k2[i]
    rhs(t + h, ynew, p, f2)
    for i in range(n):
        k3[i] = f2[i] - _E32 * (k2[i] - f1[i]) - 2.0 * (k1[i] - f0[i])
    lu_solve(lu, piv, k3)
    for i in range(n):
        k3[i] = h / 6.0 * (k1[i] - 2.0 * k2[i] + k3[i])  # local error estimate
    return True


# nogil: the CLI watcher thread can stop a long run
@njit(cache=True, nogil=True, fastmath=False, error_model="python", **REFCOUNT)
def integrate(problem, controls):
    """Integrate from t = t0 until theta = theta_cr (event) or t_max; see :mod:`.contract`."""
    p, scale = problem.p, problem.scale
    t_max, rtol, atol, h0, h_max, max_steps, t_eval, record, terminal, event_tol, _, _ = controls
    n = N_STATE
    theta_cr = p[P_THETA_CR]
    t, y, ts, ys, n_out, y_event = start(problem, controls)
    f0 = np.empty(n)
    f1 = np.empty(n)
    f2 = np.empty(n)
    k1 = np.empty(n)
    k2 = np.empty(n)
    k3 = np.empty(n)
    ynew = np.empty(n)
    ytry = np.empty(n)
    work = np.empty(n)
    fwork = np.empty(n)
    jac = np.empty((n, n))
    lu = np.empty((n, n))
    piv = np.empty(n, dtype=np.int64)
    n_eval = t_eval.shape[0]
    use_eval = n_eval > 0
    i_eval = 0
    nfev = 0
    njev = 0
    n_steps = 0
    n_rej = 0
    status = Status.T_MAX
    t_event = math.nan
    rhs(t, y, p, f0)
    nfev += 1
    h = min(h0, h_max, t_max - t)
    g_old = nutation_angle_of_state(y, p) - theta_cr
    jac_fresh = False
    while t < t_max:
        if n_steps >= max_steps:
            status = Status.STEP_LIMIT
            break
        if not jac_fresh:
            jacobian(t, y, f0, p, scale, jac, work, fwork)
            nfev += n
            njev += 1
            jac_fresh = True
        h = min(h, t_max - t)
        ok = _step(t, y, h, f0, jac, p, lu, piv, k1, k2, k3, f1, f2, ynew, work)
        nfev += 2
        err = rms_norm(k3, y, ynew, rtol, atol, scale) if ok else 1e10
        if not (err == err):
            err = 1e10
        if err > 1.0:
            n_rej += 1
            h *= max(0.2, 0.9 * err ** (-1.0 / 3.0))
            if underflow(h, t):
                status = Status.FAILED
                break
            continue
        # accepted: dense output on t_eval inside (t, t+h]
        t_new = t + h
        if use_eval:
            while i_eval < n_eval and t_eval[i_eval] <= t_new:
                s = (t_eval[i_eval] - t) / h
                b1 = s * (1.0 - s) / (1.0 - 2.0 * _D)
                b2 = s * (s - 2.0 * _D) / (1.0 - 2.0 * _D)
                ts[n_out] = t_eval[i_eval]
                for i in range(n):
                    ys[n_out, i] = y[i] + h * (b1 * k1[i] + b2 * k2[i])
                n_out += 1
                i_eval += 1
        g_new = nutation_angle_of_state(ynew, p) - theta_cr
        if crossed(g_old, g_new, t_event):
            # Locate theta = theta_cr by re-stepping from (t, y) with a shorter step:
            # each trial is as accurate as the accepted step (Illinois false position).
            s_lo, s_hi = 0.0, 1.0
            g_lo, g_hi = g_old, g_new
            side = 0
            for _ in range(200):
                if bracket_closed(s_lo, s_hi, h, event_tol):
                    break
                s = illinois_trial(s_lo, g_lo, s_hi, g_hi)
                _step(t, y, s * h, f0, jac, p, lu, piv, k1, k2, k3, f1, f2, ytry, work)
                nfev += 2
                g = nutation_angle_of_state(ytry, p) - theta_cr
                s_lo, g_lo, s_hi, g_hi, side = illinois_update(s, g, s_lo, g_lo, s_hi, g_hi, side)
            _step(t, y, s_hi * h, f0, jac, p, lu, piv, k1, k2, k3, f1, f2, y_event, work)
            nfev += 2
            t_event = t + s_hi * h
            if terminal:
                status = Status.OPENED
                ts, ys, n_out = record_row(ts, ys, n_out, t_event, y_event, record, use_eval)
                y[:] = y_event
                t = t_event
                break
            # the step below recomputed k's for the accepted step: redo it
            _step(t, y, h, f0, jac, p, lu, piv, k1, k2, k3, f1, f2, ynew, work)
            nfev += 2
        g_old = g_new
        t = t_new
        for i in range(n):
            y[i] = ynew[i]
            f0[i] = f2[i]
        jac_fresh = False
        n_steps += 1
        if record and not use_eval:  # a call per step costs reference counts
            ts, ys, n_out = append_row(ts, ys, n_out, t, y)
        h = min(h * min(5.0, max(0.2, 0.9 * err ** (-1.0 / 3.0))) if err > 0 else 5.0 * h, h_max)
        if not (y[0] == y[0]):
            status = Status.FAILED
            break
    return RawSolution(
        status, t_event, y_event, ts[:n_out], ys[:n_out], nfev, njev, n_steps, n_rej, t, y
    )
