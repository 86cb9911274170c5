"""Compiled stiff integrator: Shampine's L-stable Rosenbrock pair (ode23s).

Only :mod:`obturator.solve` calls into this module. The method is the
second-order Rosenbrock formula with a third-order error estimate and free
dense output of Shampine & Reichelt (SIAM J. Sci. Comput. 18, 1997), the one
behind MATLAB's ode23s. It is L-stable, so the stiff sticking phases of the
regularised Coulomb friction (Jacobian ~ mu N R_s / (A delta)) cost no more
steps than their accuracy needs. The Jacobian is formed by forward differences
every step; LU of the 8x8 iteration matrix is hand-written (no LAPACK call).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .dynamics import N_STATE, nutation_angle_of_state, rhs

_D = 1.0 / (2.0 + math.sqrt(2.0))
_E32 = 6.0 + math.sqrt(2.0)

STATUS_FAILED = -1
STATUS_T_MAX = 0
STATUS_OPENED = 1
STATUS_MAX_STEPS = 2


@njit(cache=True)
def _lu_factor(m: np.ndarray, piv: np.ndarray) -> bool:
    n = m.shape[0]
    for k in range(n):
        imax = k
        vmax = abs(m[k, k])
        for i in range(k + 1, n):
            if abs(m[i, k]) > vmax:
                vmax = abs(m[i, k])
                imax = i
        piv[k] = imax
        if vmax == 0.0:
            return False
        if imax != k:
            for j in range(n):
                tmp = m[k, j]
                m[k, j] = m[imax, j]
                m[imax, j] = tmp
        inv = 1.0 / m[k, k]
        for i in range(k + 1, n):
            m[i, k] *= inv
            f = m[i, k]
            if f != 0.0:
                for j in range(k + 1, n):
                    m[i, j] -= f * m[k, j]
    return True


@njit(cache=True)
def _lu_solve(lu: np.ndarray, piv: np.ndarray, b: np.ndarray) -> None:
    n = lu.shape[0]
    for k in range(n):
        j = piv[k]
        if j != k:
            tmp = b[k]
            b[k] = b[j]
            b[j] = tmp
    for i in range(n):
        s = b[i]
        for j in range(i):
            s -= lu[i, j] * b[j]
        b[i] = s
    for i in range(n - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, n):
            s -= lu[i, j] * b[j]
        b[i] = s / lu[i, i]


@njit(cache=True)
def output_buffers(t_eval, record, y0):
    """Output arrays sized for t_eval (or growing per step), holding y0 first when recording."""
    n_eval = t_eval.shape[0]
    cap = max(n_eval if n_eval > 0 else (1024 if record else 1), 1)
    ts = np.empty(cap)
    ys = np.empty((cap, y0.shape[0]))
    n_out = 0
    if record and n_eval == 0:
        ts[0] = 0.0
        ys[0, :] = y0
        n_out = 1
    return ts, ys, n_out


@njit(cache=True)
def illinois_trial(s_lo, g_lo, s_hi, g_hi):
    """Next trial point of Illinois false position on the bracket [s_lo, s_hi]."""
    s = (s_lo * g_hi - s_hi * g_lo) / (g_hi - g_lo)
    if not (s_lo < s < s_hi):
        s = 0.5 * (s_lo + s_hi)
    return s


@njit(cache=True)
def illinois_update(s, g, s_lo, g_lo, s_hi, g_hi, side):
    """Shrink the bracket with the trial (s, g); halve the stale end's g (Illinois)."""
    if g > 0.0:
        s_lo, g_lo = s, g
        if side == -1:
            g_hi *= 0.5
        side = -1
    else:
        s_hi, g_hi = s, g
        if side == 1:
            g_lo *= 0.5
        side = 1
    return s_lo, g_lo, s_hi, g_hi, side


@njit(cache=True)
def append_row(ts, ys, n_out, t, y):
    """Store (t, y) as row `n_out`, doubling the buffers when full; return them and n_out + 1."""
    if n_out >= ts.shape[0]:
        cap = 2 * ts.shape[0]
        ts2 = np.empty(cap)
        ys2 = np.empty((cap, ys.shape[1]))
        ts2[:n_out] = ts[:n_out]
        ys2[:n_out] = ys[:n_out]
        ts = ts2
        ys = ys2
    ts[n_out] = t
    ys[n_out, :] = y
    return ts, ys, n_out + 1


@njit(cache=True)
def _jacobian(t, y, f0, p, scale, jac, work, fwork) -> None:
    # Forward differences. Near sticking the friction torque varies on the
    # scale of the regularisation width delta, so increments on the rate-like
    # components must be far below delta or the Jacobian error (~increment /
    # delta) spoils the L-stability the stiff phase relies on.
    # Attitude components move omega_r by about omega_p per unit, so their
    # increments are capped at 1e-4 delta / omega_p.
    eps = math.sqrt(2.220446049250313e-16)
    delta = p[6]
    w_ref = 1.0
    for j in range(N_STATE):
        w_ref = max(w_ref, scale[j])
    for j in range(N_STATE):
        for i in range(N_STATE):
            work[i] = y[i]
        dj = eps * max(abs(y[j]), scale[j])
        if delta > 0.0:
            if scale[j] != 1.0:
                dj = min(dj, 1e-4 * delta)
            elif p[5] == 0.0:  # quaternion components (Euler angles fare better uncapped)
                dj = min(dj, 1e-4 * delta / w_ref)
        work[j] = y[j] + dj
        dj = work[j] - y[j]
        rhs(t, work, p, fwork)
        for i in range(N_STATE):
            jac[i, j] = (fwork[i] - f0[i]) / dj


@njit(cache=True)
def _step(t, y, h, f0, jac, p, lu, piv, k1, k2, k3, f1, f2, ynew, work) -> bool:
    """One ode23s step of size h; fills ynew, k1, k2 and the error in k3."""
    n = N_STATE
    for i in range(n):
        for j in range(n):
            lu[i, j] = -h * _D * jac[i, j]
        lu[i, i] += 1.0
    if not _lu_factor(lu, piv):
        return False
    for i in range(n):
        k1[i] = f0[i]
    _lu_solve(lu, piv, k1)
    for i in range(n):
        work[i] = y[i] + 0.5 * h * k1[i]
    rhs(t + 0.5 * h, work, p, f1)
    for i in range(n):
        k2[i] = f1[i] - k1[i]
    _lu_solve(lu, piv, k2)
    for i in range(n):
        k2[i] += k1[i]
        ynew[i] = y[i] + h * k2[i]
    rhs(t + h, ynew, p, f2)
    for i in range(n):
        k3[i] = f2[i] - _E32 * (k2[i] - f1[i]) - 2.0 * (k1[i] - f0[i])
    _lu_solve(lu, piv, k3)
    for i in range(n):
        k3[i] = h / 6.0 * (k1[i] - 2.0 * k2[i] + k3[i])  # local error estimate
    return True


@njit(cache=True, nogil=True)
def integrate(
    y0, p, t_max, rtol, atol, scale, h0, h_max, max_steps, t_eval, record, terminal, event_tol
):
    """Integrate from t = 0 until theta = theta_cr (event) or t_max.

    Returns
    -------
    tuple
        (status, t_event, y_event, ts, ys, nfev, njev, n_steps, n_rejected, t_end, y_end)
    """
    n = N_STATE
    theta_cr = p[7]
    y = y0.copy()
    t = 0.0
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
    ts, ys, n_out = output_buffers(t_eval, record, y)
    i_eval = 0
    nfev = 0
    njev = 0
    n_steps = 0
    n_rej = 0
    status = STATUS_T_MAX
    t_event = math.nan
    y_event = np.full(n, math.nan)
    rhs(t, y, p, f0)
    nfev += 1
    h = min(h0, h_max, t_max)
    g_old = nutation_angle_of_state(y, p) - theta_cr
    jac_fresh = False
    while t < t_max:
        if n_steps >= max_steps:
            status = STATUS_MAX_STEPS
            break
        if not jac_fresh:
            _jacobian(t, y, f0, p, scale, jac, work, fwork)
            nfev += n
            njev += 1
            jac_fresh = True
        h = min(h, t_max - t)
        ok = _step(t, y, h, f0, jac, p, lu, piv, k1, k2, k3, f1, f2, ynew, work)
        nfev += 2
        err = 0.0
        if ok:
            for i in range(n):
                sc = atol * scale[i] + rtol * max(abs(y[i]), abs(ynew[i]))
                e = k3[i] / sc
                err += e * e
            err = math.sqrt(err / n)
        if not ok or not (err == err):
            err = 1e10
        if err > 1.0:
            n_rej += 1
            h *= max(0.2, 0.9 * err ** (-1.0 / 3.0))
            if h < 1e-14 * max(t, 1e-6):
                status = STATUS_FAILED
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
        if g_old > 0.0 and g_new <= 0.0 and t_event != t_event:
            # Locate theta = theta_cr by re-stepping from (t, y) with a shorter step:
            # each trial is as accurate as the accepted step (Illinois false position).
            s_lo, s_hi = 0.0, 1.0
            g_lo, g_hi = g_old, g_new
            side = 0
            for _ in range(200):
                if (s_hi - s_lo) * h <= event_tol:
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
                status = STATUS_OPENED
                if record and not use_eval:
                    ts, ys, n_out = append_row(ts, ys, n_out, t_event, y_event)
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
        if record and not use_eval:
            ts, ys, n_out = append_row(ts, ys, n_out, t, y)
        h = min(h * min(5.0, max(0.2, 0.9 * err ** (-1.0 / 3.0))) if err > 0 else 5.0 * h, h_max)
        if not (y[0] == y[0]):
            status = STATUS_FAILED
            break
    return (status, t_event, y_event, ts[:n_out], ys[:n_out], nfev, njev, n_steps, n_rej, t, y)
