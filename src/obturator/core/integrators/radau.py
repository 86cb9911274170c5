"""Compiled stiff integrator: fifth-order Radau IIA collocation (3 stages).

:func:`integrate` keeps the contract of :mod:`.contract`; the coefficients are
in :mod:`.radau_coefficients`, the LU routines in :mod:`.linalg`, one collocation
step (LU, Newton iterations, collocation polynomial) in :mod:`.radau_step`.

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
from typing import NamedTuple

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
from .linalg import lu_solve
from .radau_coefficients import (
    C1,
    C2,
    E1,
    E2,
    E3,
)
from .radau_control import (
    _LIM_SHRINK,
    next_step,
    radau5_tolerances,
    sliding_resumed,
    step_quotient,
)
from .radau_control import _UROUND as _UROUND  # re-exported: the lanes, stick_slip
from .radau_step import _colloc_weights, _dense, _factor, _newton

__all__ = ["integrate", "locate_opening_at", "EventWork"]


class EventWork(NamedTuple):
    """The arrays the event location writes (:func:`locate_opening_at`)."""

    zacc: np.ndarray  #: (3, N_STATE): receives the accepted step's stage increments
    stage: tuple  #: (z, w, f) of the trial steps (:func:`_newton`)
    lu: tuple  #: the trial steps' factors (:func:`_factor`)
    scratch: tuple  #: (work, cbr, cbi)
    ytry: np.ndarray  #: a trial state
    y_event: np.ndarray  #: the event state


class RadauWork(NamedTuple):
    """The arrays of one :func:`integrate` run (:func:`_new_work`)."""

    f0: np.ndarray  #: f(t, y)
    ynew: np.ndarray  #: y + Z_3: the step's end
    fwork: np.ndarray  #: right-hand side scratch
    scal: np.ndarray  #: reciprocal error weights 1 / (atol scale_i + rtol |y_i|)
    err_v: np.ndarray  #: right side of the error estimate
    jac: np.ndarray  #: (N_STATE, N_STATE) Jacobian
    stage: tuple  #: (z, w, f): stage increments, their transform, stage derivatives
    lu: tuple  #: (lu_r, piv_r, lu_cr, lu_ci, piv_c) of :func:`_factor`
    scratch: tuple  #: (work, cbr, cbi)
    event: EventWork  #: its zacc: the last accepted step's z; its stage keeps z and w


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _cos_nutation(y, p) -> float:
    """cos(theta) of a state, without the atan2 of nutation_angle_of_state."""
    if p[P_FORM] == FORM_EULER:
        return math.cos(y[0])
    q2 = y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]
    return 1.0 - 2.0 * (y[1] * y[1] + y[2] * y[2]) / q2


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _restep(t, y, h, s, p, scal, jac, fnewt, ev) -> int:
    """Re-solve the step from (t, y) with length s h (event location); result in ev.ytry.

    The stage guess comes from the accepted step's collocation polynomial
    (ev.zacc); if Newton does not converge the polynomial value itself is used.
    Returns the number of right-hand-side evaluations spent.
    """
    n = N_STATE
    zacc, ytry = ev.zacc, ev.ytry
    z = ev.stage[0]
    hs = s * h
    for k in range(3):
        ck = C1 if k == 0 else (C2 if k == 1 else 1.0)
        l1, l2, l3 = _colloc_weights(s * ck)
        for i in range(n):
            z[k, i] = l1 * zacc[0, i] + l2 * zacc[1, i] + l3 * zacc[2, i]
    nfev = 0
    ok = _factor(hs, jac, ev.lu)
    if ok:
        ok, newt, _, _, _ = _newton(t, y, hs, p, scal, ev.stage, ev.lu, ev.scratch, 1.0, fnewt)
        nfev = 3 * newt
    if ok:
        for i in range(n):
            ytry[i] = y[i] + z[2, i]
    else:
        _dense(y, zacc, s, ytry)
    return nfev


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def locate_opening_at(step, p, scal, jac, fnewt, event_tol, ev):
    """Look for the opening inside an accepted step and locate it.

    `step` is (t, y, h, z, ynew, g_old, g_new): the step from (t, y) of length h
    with stage increments z to ynew, g = theta - theta_cr at its start (> 0) and
    end. The first node (c1, c2, 1) at which the collocation solution is past
    theta_cr brackets the crossing; Illinois false position on g(s) = theta(step(y,
    s h)) - theta_cr then re-solves the step from its start (:func:`_restep`), so
    the event state is as accurate as an accepted step. `ev` (:class:`EventWork`):
    its zacc receives a copy of z, its lu and stage are overwritten (trial steps).
    Shared by :func:`integrate` and the batched Radau lanes.

    Returns
    -------
    tuple
        (found, t_event, nfev); the event state is written into ``ev.y_event``.
    """
    t, y, h, z, ynew, g_old, g_new = step
    ytry, y_event = ev.ytry, ev.y_event
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
            ev.zacc[k, i] = z[k, i]
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
        nfev += _restep(t, y, h, s, p, scal, jac, fnewt, ev)
        g = nutation_angle_of_state(ytry, p) - theta_cr
        s_lo, g_lo, s_hi, g_hi, side = illinois_update(s, g, s_lo, g_lo, s_hi, g_hi, side)
        if not g > 0.0:  # same branch as illinois_update (NaN included)
            for i in range(n):
                y_event[i] = ytry[i]
    return True, t + s_hi * h, nfev


@njit(cache=True, fastmath={"contract"}, error_model="numpy", **REFCOUNT)
def _new_work() -> RadauWork:
    """The arrays of one run (allocated once per :func:`integrate` call)."""
    n = N_STATE
    z = np.zeros((3, n))
    f = np.empty((3, n))
    piv = np.empty(n, dtype=np.int64)
    lu = (np.empty((n, n)), piv, np.empty((n, n)), np.empty((n, n)), piv.copy())
    scratch = (np.empty(n), np.empty(n), np.empty(n))
    # the event re-steps keep the accepted step's z and w (their own), and share f
    event = EventWork(
        np.zeros((3, n)), (np.zeros((3, n)), np.zeros((3, n)), f), lu, scratch, np.empty(n),
        np.empty(n),
    )  # fmt: skip
    return RadauWork(
        np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty((n, n)),
        (z, np.zeros((3, n)), f), lu, scratch, event,
    )  # fmt: skip


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _guess_stages(z, zacc, h, h_acc, have_poly) -> None:
    """The Newton start: the last step's collocation polynomial extrapolated to this
    step's nodes, or zero before the first accepted step."""
    n = N_STATE
    for k in range(3):
        ck = C1 if k == 0 else (C2 if k == 1 else 1.0)
        if have_poly:
            l1, l2, l3 = _colloc_weights(1.0 + ck * h / h_acc)
            for i in range(n):
                z[k, i] = l1 * zacc[0, i] + l2 * zacc[1, i] + l3 * zacc[2, i] - zacc[2, i]
        else:
            for i in range(n):
                z[k, i] = 0.0


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def error_estimate(t, y, h, p, scale, rtol, atol, once_more, ws) -> tuple[float, int]:
    """The embedded error estimate of a converged step (H&W IV.8).

    (gamma/h - J)^-1 (f0 + sum e_k Z_k / h) in the real LU of ``ws.lu``, with ynew =
    y + Z_3 written into ``ws.ynew``; where it is >= 1 and `once_more` (first or
    rejected step) it is filtered once more, as it is unreliable for very stiff
    components. Returns (its RMS norm, 1e10 for NaN; right-hand sides spent).
    """
    n = N_STATE
    z = ws.stage[0]
    f0, ynew, err_v, fwork = ws.f0, ws.ynew, ws.err_v, ws.fwork
    work, ytry = ws.scratch[0], ws.event.ytry
    lu_r, piv_r = ws.lu[0], ws.lu[1]
    for i in range(n):
        ynew[i] = y[i] + z[2, i]
        err_v[i] = f0[i] + (E1 * z[0, i] + E2 * z[1, i] + E3 * z[2, i]) / h
    for i in range(n):
        work[i] = err_v[i]
    lu_solve(lu_r, piv_r, work)
    err = rms_norm(work, y, ynew, rtol, atol, scale)
    nfev = 0
    if err >= 1.0 and once_more:
        for i in range(n):
            ytry[i] = y[i] + work[i]
        rhs(t, ytry, p, fwork)
        nfev = 1
        for i in range(n):
            work[i] = fwork[i] + err_v[i] - f0[i]
        lu_solve(lu_r, piv_r, work)
        err = rms_norm(work, y, ynew, rtol, atol, scale)
    if not (err == err):
        err = 1e10
    return err, nfev


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _dense_rows(t, y, h, z, t_stop, t_eval, i_eval, ts, ys, n_out, ytry) -> tuple[int, int]:
    """Dense output (the step's collocation polynomial) at the output times inside
    (t, t_stop]; returns the next output time's index and the row count."""
    while i_eval < t_eval.shape[0] and t_eval[i_eval] <= t_stop:
        _dense(y, z, (t_eval[i_eval] - t) / h, ytry)
        ts[n_out] = t_eval[i_eval]
        for i in range(N_STATE):
            ys[n_out, i] = ytry[i]
        n_out += 1
        i_eval += 1
    return i_eval, n_out


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
    ws = _new_work()
    ev = ws.event
    ev = EventWork(ev.zacc, ev.stage, ev.lu, ev.scratch, ev.ytry, y_event)
    f0, ynew, jac, scal, z, zacc = ws.f0, ws.ynew, ws.jac, ws.scal, ws.stage[0], ev.zacc
    use_eval = t_eval.shape[0] > 0
    i_eval = 0
    nfev = 0
    njev = 0
    n_steps = 0
    n_rej = 0
    status = Status.T_MAX
    t_event = math.nan
    rtol, atol, fnewt = radau5_tolerances(rtol, atol)
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
            jacobian(t, y, f0, p, scale, jac, ws.scratch[0], ws.fwork)
            nfev += n
            njev += 1
            need_jac = False
            jac_fresh = True
            h_lu = math.nan
        if t + 1.01 * h >= t_max:
            h = t_max - t
        if h != h_lu:
            if not _factor(h, jac, ws.lu):
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
        _guess_stages(z, zacc, h, h_acc, have_poly)
        ok, newt, theta, faccon, hfac = _newton(
            t, y, h, p, scal, ws.stage, ws.lu, ws.scratch, faccon, fnewt
        )
        nfev += 3 * newt
        if ok:
            err, nf = error_estimate(t, y, h, p, scale, rtol, atol, first or rejected, ws)
            nfev += nf
            quot, quot_std = step_quotient(err, newt, h, first, h_gus, err_gus)
            h_retry = h * 0.1 if first else h / quot_std
        else:  # Newton failed: a shorter step, capped below this one
            err, quot = math.inf, 1.0
            h_lim = min(h_lim, h * _LIM_SHRINK)
            h_retry = h * hfac
        if err >= 1.0:  # rejected: a Jacobian at this point if it was stale
            n_rej += 1
            rejected = True
            h = h_retry
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
            step = (t, y, h, z, ynew, g_old, g_new)
            found, t_ev, nf = locate_opening_at(step, p, scal, jac, fnewt, event_tol, ev)
            nfev += nf
            if found:
                h_lu = math.nan  # the LU now belongs to a trial step
                t_event = t_ev
                if terminal:
                    status = Status.OPENED
                    t_stop = t_event
        if use_eval:
            i_eval, n_out = _dense_rows(t, y, h, z, t_stop, t_eval, i_eval, ts, ys, n_out, ev.ytry)
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
