"""Compiled stiff integrator: fifth-order Radau IIA collocation (3 stages).

:func:`integrate` keeps the contract of :mod:`.contract`; the coefficients are
in :mod:`.radau_coefficients`, the LU routines in :mod:`.linalg`.

Why a fully implicit method: the regularised Coulomb friction saturates over a
width delta, so near sticking the stiffness is strongly *nonlinear*. A
linearly-implicit (Rosenbrock) step trusts the Jacobian at the step start over
the whole step and is forced to steps of order 1e-7 s there; Radau IIA solves
its stage equations by (simplified) Newton iterations, follows the
nonlinearity and takes steps limited by accuracy only.

The method is the one of Hairer & Wanner, *Solving Ordinary Differential
Equations II*, 2nd ed., Sec. IV.8 (the scheme behind their RADAU5 code); the
published data used here are the Butcher tableau (nodes (4 -+ sqrt 6)/10, 1),
the embedded error estimate (gamma0 = 1/(3 + 3^(2/3) - 3^(1/3)), weights
(-13 - 7 sqrt 6, -13 + 7 sqrt 6, -1)/3), the Newton stopping and step-size
rules, and the collocation polynomial as dense output. Implementation notes:

* Newton system: A^-1 is brought to block-diagonal form gamma (+) [alpha,
  -beta; beta, alpha] by a real similarity computed once at import (from the
  eigenvectors of A^-1), so each simplified-Newton iteration solves one real
  and one complex 8x8 system instead of the 24x24 one; the real and the
  complex substitutions of a Newton iteration run interleaved in one loop.
  All compiled functions allow FMA contraction (fastmath "contract" only:
  no reassociation, NaN checks intact), a rounding-level difference.
* Tolerances are transformed as in RADAU5 (rtol' = 0.1 rtol^(2/3)): the error
  estimate is that of an embedded order-3 solution while the solution kept is
  of order 5, so the raw estimate would over-resolve. With this the t_cr error
  stays below about 3e-7 relative at rtol = 1e-8 on the thesis cases.
* The Jacobian (forward differences, :func:`.common.jacobian`,
  increments capped below delta on purpose) is kept across steps while Newton
  contracts fast (RADAU5's rule, threshold tuned for an 8-equation system whose
  Jacobian costs 8 evaluations); the LU and the step are kept when the
  controller asks for a change of less than 20 %.
* Newton-limited steps: with Coulomb point contacts the stiff subspace is
  fixed in the laboratory while the state is in body axes, so a frozen
  Jacobian fails beyond some step size however accurate the step is. After a
  Newton failure the step is capped below the failed size and the cap relaxes
  by 20 % per accepted step, instead of letting the error controller retry
  8x longer steps that fail again.
* The opening event theta = theta_cr (downward crossing) is looked for at the
  collocation nodes of every step, so a dip below theta_cr inside a step is
  not missed, and located by re-solving the step from its start with a
  shorter step (Illinois false position on g(s) = theta(y(t + s h)) -
  theta_cr), so the event state is as accurate as any accepted step.
* Dense output (t_eval) is the collocation polynomial (order 3 between nodes).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..dynamics import nutation_angle_of_state, rhs, slip_and_spin
from ..jit_flags import NO_REFCOUNT, REFCOUNT
from ..layout import FORM_EULER, N_STATE, P_FORM, P_THETA_CR, P_WIDTH
from .common import (
    append_row,
    bracket_closed,
    illinois_trial,
    illinois_update,
    jacobian,
    record_row,
    rms_norm,
    start,
    underflow,
)
from .contract import RawSolution, Status
from .linalg import lu_factor, lu_factor_complex, lu_solve, lu_solve_pair
from .radau_coefficients import (
    ALPHA,
    BETA,
    C1,
    C2,
    E1,
    E2,
    E3,
    GAMMA,
    RD1,
    RD2,
    RD3,
    T00,
    T01,
    T02,
    T10,
    T11,
    T12,
    T20,
    T21,
    T22,
    TI00,
    TI01,
    TI02,
    TI10,
    TI11,
    TI12,
    TI20,
    TI21,
    TI22,
)
from .radau_control import (
    _LIM_SHRINK,
    _NIT,
    _THET,
    newton_contraction,
    next_step,
    sliding_resumed,
    step_quotient,
)

__all__ = ["integrate"]

_UROUND = 2.220446049250313e-16


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _colloc_weights(s: float) -> tuple[float, float, float]:
    """Weights of Z1, Z2, Z3 in the collocation polynomial at t0 + s h (s may exceed 1)."""
    l1 = s * (s - C2) * (s - 1.0) * RD1
    l2 = s * (s - C1) * (s - 1.0) * RD2
    l3 = s * (s - C1) * (s - C2) * RD3
    return l1, l2, l3


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _factor(h, jac, lu) -> bool:
    """LU of gamma/h I - J (real) and (alpha + i beta)/h I - J (complex, split storage).

    `lu` holds the factors: (lu_r, piv_r, lu_cr, lu_ci, piv_c).
    """
    lu_r, piv_r, lu_cr, lu_ci, piv_c = lu
    n = N_STATE
    fr = GAMMA / h
    ar = ALPHA / h
    br = BETA / h
    for i in range(n):
        for j in range(n):
            lu_r[i, j] = -jac[i, j]
            lu_cr[i, j] = -jac[i, j]
            lu_ci[i, j] = 0.0
        lu_r[i, i] += fr
        lu_cr[i, i] += ar
        lu_ci[i, i] = br
    if not lu_factor(lu_r, piv_r):
        return False
    return lu_factor_complex(lu_cr, lu_ci, piv_c)


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _newton(t, y, h, p, scal, stage, lu, scratch, faccon0, fnewt):
    """Simplified Newton iterations for the stage increments Z (initial guess in z).

    scal holds the reciprocal error weights 1 / (atol scale_i + rtol |y_i|);
    stage = (z, w, f): the stage increments Z, their transform W and the stage
    derivatives; lu the factors of :func:`_factor`; scratch = (work, cbr, cbi).

    Returns
    -------
    tuple
        (converged, n_iter, theta, faccon, h_factor): theta is the observed
        contraction rate (_THET when one iteration sufficed), h_factor the step
        reduction to apply when not converged.
    """
    z, w, f = stage
    work, cbr, cbi = scratch
    lu_r, piv_r, lu_cr, lu_ci, piv_c = lu
    n = N_STATE
    for i in range(n):  # W = (T^-1 x I) Z
        w[0, i] = TI00 * z[0, i] + TI01 * z[1, i] + TI02 * z[2, i]
        w[1, i] = TI10 * z[0, i] + TI11 * z[1, i] + TI12 * z[2, i]
        w[2, i] = TI20 * z[0, i] + TI21 * z[1, i] + TI22 * z[2, i]
    faccon = max(faccon0, _UROUND) ** 0.8
    theta = _THET
    dynold = 1.0
    thqold = 1.0
    fr = GAMMA / h
    ar = ALPHA / h
    br = BETA / h
    newt = 0
    while True:
        if newt >= _NIT:
            return False, newt, theta, faccon, 0.5
        for k in range(3):
            ck = C1 if k == 0 else (C2 if k == 1 else 1.0)
            for i in range(n):
                work[i] = y[i] + z[k, i]
            rhs(t + ck * h, work, p, f[k])
        newt += 1
        finite = True
        for i in range(n):
            # residual G - (Lambda/h) W in the transformed variables
            g1 = TI00 * f[0, i] + TI01 * f[1, i] + TI02 * f[2, i]
            g2 = TI10 * f[0, i] + TI11 * f[1, i] + TI12 * f[2, i]
            g3 = TI20 * f[0, i] + TI21 * f[1, i] + TI22 * f[2, i]
            r1 = g1 - fr * w[0, i]
            r2 = g2 - (ar * w[1, i] - br * w[2, i])
            r3 = g3 - (br * w[1, i] + ar * w[2, i])
            if not (r1 == r1 and r2 == r2 and r3 == r3):
                finite = False
            work[i] = r1
            cbr[i] = r2
            cbi[i] = r3
        if not finite:
            return False, newt, theta, faccon, 0.5
        lu_solve_pair(lu_r, piv_r, work, lu_cr, lu_ci, piv_c, cbr, cbi)
        dyno = 0.0
        for i in range(n):
            d1 = work[i] * scal[i]
            d2 = cbr[i] * scal[i]
            d3 = cbi[i] * scal[i]
            dyno += d1 * d1 + d2 * d2 + d3 * d3
        dyno = math.sqrt(dyno / (3 * n))
        failed, theta, thqold, faccon, hfac = newton_contraction(
            newt, dyno, dynold, thqold, theta, faccon, fnewt
        )
        if failed:
            return False, newt, theta, faccon, hfac
        dynold = max(dyno, _UROUND)
        for i in range(n):
            w[0, i] += work[i]
            w[1, i] += cbr[i]
            w[2, i] += cbi[i]
            z[0, i] = T00 * w[0, i] + T01 * w[1, i] + T02 * w[2, i]
            z[1, i] = T10 * w[0, i] + T11 * w[1, i] + T12 * w[2, i]
            z[2, i] = T20 * w[0, i] + T21 * w[1, i] + T22 * w[2, i]
        if faccon * dyno <= fnewt:
            return True, newt, theta, faccon, 1.0


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _cos_nutation(y, p) -> float:
    """cos(theta) of a state, without the atan2 of nutation_angle_of_state."""
    if p[P_FORM] == FORM_EULER:
        return math.cos(y[0])
    q2 = y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]
    return 1.0 - 2.0 * (y[1] * y[1] + y[2] * y[2]) / q2


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _dense(y, z, s, out) -> None:
    """Collocation polynomial of the step (y, z) at t0 + s h, written into out."""
    l1, l2, l3 = _colloc_weights(s)
    for i in range(N_STATE):
        out[i] = y[i] + l1 * z[0, i] + l2 * z[1, i] + l3 * z[2, i]


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _restep(t, y, h, s, p, scal, jac, zacc, stage, lu, scratch, fnewt, ytry) -> int:
    """Re-solve the step from (t, y) with length s h (event location); result in ytry.

    The stage guess comes from the accepted step's collocation polynomial
    (zacc); if Newton does not converge the polynomial value itself is used.
    Returns the number of right-hand-side evaluations spent.
    """
    n = N_STATE
    z = stage[0]
    hs = s * h
    for k in range(3):
        ck = C1 if k == 0 else (C2 if k == 1 else 1.0)
        l1, l2, l3 = _colloc_weights(s * ck)
        for i in range(n):
            z[k, i] = l1 * zacc[0, i] + l2 * zacc[1, i] + l3 * zacc[2, i]
    nfev = 0
    ok = _factor(hs, jac, lu)
    if ok:
        ok, newt, _, _, _ = _newton(t, y, hs, p, scal, stage, lu, scratch, 1.0, fnewt)
        nfev = 3 * newt
    if ok:
        for i in range(n):
            ytry[i] = y[i] + z[2, i]
    else:
        _dense(y, zacc, s, ytry)
    return nfev


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def locate_opening(
    t, y, h, z, ynew, g_old, g_new, p, scal, jac, zacc, stage, lu, scratch, fnewt, event_tol,
    ytry, y_event,
):  # fmt: skip
    """Look for the opening inside the accepted step (t, y, h, z) and locate it.

    The first node (c1, c2, 1) at which the collocation solution is past
    theta_cr brackets the crossing (g_old > 0 at the step start, g_new at its
    end); Illinois false position on g(s) = theta(step(y, s h)) - theta_cr then
    re-solves the step from its start (:func:`_restep`), so the event state is
    as accurate as an accepted step. `zacc` receives a copy of z, `lu` and
    `stage` are overwritten (trial steps). Shared by :func:`integrate` and the
    batched Radau lanes.

    Returns
    -------
    tuple
        (found, t_event, nfev); the event state is written into `y_event`.
    """
    n = N_STATE
    theta_cr = p[P_THETA_CR]
    cos_cr = math.cos(theta_cr)
    s_hi = 0.0
    g_hi = 0.0
    for k in range(2):
        for i in range(n):
            ytry[i] = y[i] + z[k, i]
        if _cos_nutation(ytry, p) >= cos_cr:  # cheap pre-test, then the angle
            gk = nutation_angle_of_state(ytry, p) - theta_cr
            if gk <= 0.0:
                s_hi = C1 if k == 0 else C2
                g_hi = gk
                break
    if s_hi == 0.0 and g_new <= 0.0:
        s_hi = 1.0
        g_hi = g_new
        for i in range(n):
            ytry[i] = ynew[i]
    if s_hi == 0.0:
        return False, math.nan, 0
    for k in range(3):
        for i in range(n):
            zacc[k, i] = z[k, i]
    for i in range(n):
        y_event[i] = ytry[i]
    s_lo = 0.0
    g_lo = g_old
    side = 0
    nfev = 0
    for _ in range(200):
        if bracket_closed(s_lo, s_hi, h, event_tol):
            break
        s = illinois_trial(s_lo, g_lo, s_hi, g_hi)
        nfev += _restep(t, y, h, s, p, scal, jac, zacc, stage, lu, scratch, fnewt, ytry)
        g = nutation_angle_of_state(ytry, p) - theta_cr
        s_lo, g_lo, s_hi, g_hi, side = illinois_update(s, g, s_lo, g_lo, s_hi, g_hi, side)
        if not g > 0.0:  # same branch as illinois_update (NaN included)
            for i in range(n):
                y_event[i] = ytry[i]
    return True, t + s_hi * h, nfev


@njit(cache=True, nogil=True, fastmath={"contract"}, error_model="python", **REFCOUNT)
def integrate(problem, controls):
    """Integrate from t = t0 until theta = theta_cr (event) or t_max; see :mod:`.contract`."""
    p, scale = problem.p, problem.scale
    t_max, rtol, atol, h0, h_max, max_steps, t_eval, record, terminal, event_tol, hand_back = (
        controls
    )
    n = N_STATE
    theta_cr = p[P_THETA_CR]
    t, y, ts, ys, n_out, y_event = start(problem, controls)
    f0 = np.empty(n)
    ynew = np.empty(n)
    ytry = np.empty(n)
    work = np.empty(n)
    fwork = np.empty(n)
    scal = np.empty(n)
    err_v = np.empty(n)
    z = np.zeros((3, n))
    w = np.zeros((3, n))
    f = np.empty((3, n))
    zacc = np.zeros((3, n))  # stage increments of the last accepted step
    zev = np.zeros((3, n))
    wev = np.zeros((3, n))
    jac = np.empty((n, n))
    lu_r = np.empty((n, n))
    lu_cr = np.empty((n, n))
    lu_ci = np.empty((n, n))
    piv_r = np.empty(n, dtype=np.int64)
    piv_c = np.empty(n, dtype=np.int64)
    cbr = np.empty(n)
    cbi = np.empty(n)
    lu = (lu_r, piv_r, lu_cr, lu_ci, piv_c)
    scratch = (work, cbr, cbi)
    stage = (z, w, f)
    stage_ev = (zev, wev, f)  # the event re-steps keep the accepted step's z and w
    n_eval = t_eval.shape[0]
    use_eval = n_eval > 0
    i_eval = 0
    nfev = 0
    njev = 0
    n_steps = 0
    n_rej = 0
    status = Status.T_MAX
    t_event = math.nan
    # RADAU5's tolerance transformation: the embedded estimate is of order 3 while
    # the solution is of order 5, so the estimate is compared with a looser
    # tolerance; this keeps the achieved accuracy roughly proportional to rtol.
    quot_tol = atol / rtol
    rtol = 0.1 * rtol ** (2.0 / 3.0)
    atol = rtol * quot_tol
    # Newton stopping tolerance relative to the error weights (RADAU5's FNEWT)
    fnewt = max(10.0 * _UROUND / rtol, min(0.03, math.sqrt(rtol)))
    rhs(t, y, p, f0)
    nfev += 1
    h = min(h0, h_max, t_max - t)
    h_lu = math.nan  # step size the LU factors belong to
    need_jac = True
    jac_fresh = False
    have_poly = False
    h_acc = 0.0  # length of the last accepted step (for the stage predictor)
    first = True
    rejected = False
    faccon = 1.0
    h_gus = 0.0  # previous accepted step and error (predictive controller)
    err_gus = 1.0
    g_old = nutation_angle_of_state(y, p) - theta_cr
    h_lim = math.inf
    t_stick = t  # last time the slip speed was below saturation (hand_back)
    while t < t_max:
        if n_steps >= max_steps:
            status = Status.STEP_LIMIT
            break
        if need_jac:
            jacobian(t, y, f0, p, scale, jac, work, fwork)
            nfev += n
            njev += 1
            need_jac = False
            jac_fresh = True
            h_lu = math.nan
        if t + 1.01 * h >= t_max:
            h = t_max - t
        if h != h_lu:
            if not _factor(h, jac, lu):
                n_rej += 1
                h *= 0.5
                h_lu = math.nan
                if underflow(h, t):
                    status = Status.FAILED
                    break
                continue
            h_lu = h
        for i in range(n):  # reciprocal error weights: the Newton norm multiplies
            scal[i] = 1.0 / (atol * scale[i] + rtol * abs(y[i]))
        # stage guess: extrapolate the last collocation polynomial
        if have_poly:
            for k in range(3):
                ck = C1 if k == 0 else (C2 if k == 1 else 1.0)
                l1, l2, l3 = _colloc_weights(1.0 + ck * h / h_acc)
                for i in range(n):
                    z[k, i] = l1 * zacc[0, i] + l2 * zacc[1, i] + l3 * zacc[2, i] - zacc[2, i]
        else:
            z[:, :] = 0.0
        ok, newt, theta, faccon, hfac = _newton(t, y, h, p, scal, stage, lu, scratch, faccon, fnewt)
        nfev += 3 * newt
        if not ok:
            # Newton failed: shorter step, and a Jacobian at this point if it was stale
            h_lim = min(h_lim, h * _LIM_SHRINK)
            n_rej += 1
            rejected = True
            h *= hfac
            if not jac_fresh:
                need_jac = True
            if underflow(h, t):
                status = Status.FAILED
                break
            continue
        # embedded error estimate (H&W IV.8): (gamma/h - J)^-1 (f0 + sum e_k Z_k / h)
        for i in range(n):
            ynew[i] = y[i] + z[2, i]
            err_v[i] = f0[i] + (E1 * z[0, i] + E2 * z[1, i] + E3 * z[2, i]) / h
        for i in range(n):
            work[i] = err_v[i]
        lu_solve(lu_r, piv_r, work)
        err = rms_norm(work, y, ynew, rtol, atol, scale)
        if err >= 1.0 and (first or rejected):
            # the estimate is unreliable for very stiff components: filter once more
            for i in range(n):
                ytry[i] = y[i] + work[i]
            rhs(t, ytry, p, fwork)
            nfev += 1
            for i in range(n):
                work[i] = fwork[i] + err_v[i] - f0[i]
            lu_solve(lu_r, piv_r, work)
            err = rms_norm(work, y, ynew, rtol, atol, scale)
        if not (err == err):
            err = 1e10
        quot, quot_std = step_quotient(err, newt, h, first, h_gus, err_gus)
        if err >= 1.0:
            n_rej += 1
            rejected = True
            h = h * 0.1 if first else h / quot_std
            if not jac_fresh:
                need_jac = True
            if underflow(h, t):
                status = Status.FAILED
                break
            continue
        # ---- accepted ----
        h_new = h / quot
        h_gus = h
        err_gus = max(1e-2, err)
        t_new = t + h
        t_stop = t_new
        g_new = nutation_angle_of_state(ynew, p) - theta_cr
        if g_old > 0.0 and t_event != t_event:
            found, t_ev, nf = locate_opening(
                t, y, h, z, ynew, g_old, g_new, p, scal, jac, zacc, stage_ev, lu, scratch,
                fnewt, event_tol, ytry, y_event,
            )  # fmt: skip
            nfev += nf
            if found:
                h_lu = math.nan  # the LU now belongs to a trial step
                t_event = t_ev
                if terminal:
                    status = Status.OPENED
                    t_stop = t_event
        # dense output on t_eval inside (t, t_stop]
        if use_eval:
            while i_eval < n_eval and t_eval[i_eval] <= t_stop:
                _dense(y, z, (t_eval[i_eval] - t) / h, ytry)
                ts[n_out] = t_eval[i_eval]
                ys[n_out, :] = ytry
                n_out += 1
                i_eval += 1
        if status == Status.OPENED:
            ts, ys, n_out = record_row(ts, ys, n_out, t_event, y_event, record, use_eval)
            y[:] = y_event
            t = t_event
            break
        g_old = g_new
        for k in range(3):
            for i in range(n):
                zacc[k, i] = z[k, i]
        h_acc = h
        have_poly = True
        t = t_new
        for i in range(n):
            y[i] = ynew[i]
        rhs(t, y, p, f0)
        nfev += 1
        n_steps += 1
        if record and not use_eval:  # a call per step costs reference counts
            ts, ys, n_out = append_row(ts, ys, n_out, t, y)
        if not (y[0] == y[0]):
            status = Status.FAILED
            break
        if hand_back:
            slip, spin = slip_and_spin(y, p)
            back, t_stick = sliding_resumed(t, t_stick, slip, spin, p[P_WIDTH])
            if back:
                status = Status.NONSTIFF
                break
        h, h_lim, slow = next_step(h, h_new, h_lim, h_max, rejected, theta)
        need_jac = need_jac or slow
        first = False
        rejected = False
        jac_fresh = False
    return RawSolution(
        status, t_event, y_event, ts[:n_out], ys[:n_out], nfev, njev, n_steps, n_rej, t, y
    )
