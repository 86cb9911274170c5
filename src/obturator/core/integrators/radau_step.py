"""One Radau IIA collocation step: the LU of the Newton matrices, the simplified Newton
iterations, the embedded error estimate, the collocation polynomial (stage guess and
dense output) and the opening event inside a step (Hairer & Wanner, *Solving Ordinary
Differential Equations II*, Sec. IV.8; see :mod:`.radau` for the method's notes).

Used through the phases of :mod:`.radau` by its driver and :mod:`.stick_slip`, and by
the lanes (:mod:`.lanes.radau`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..dynamics import nutation_angle_of_state, rhs
from ..jit_flags import NO_REFCOUNT, REFCOUNT
from ..layout import FORM_EULER, N_STATE, P_FORM, P_THETA_CR
from .common import bracket_closed, illinois_trial, illinois_update, rms_norm
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
from .radau_control import _NIT, _THET, _UROUND, FACCON_POWER, NEWTON_CUT, newton_contraction

__all__ = [
    "EventWork",
    "RadauWork",
    "dense_rows",
    "error_estimate",
    "guess_stages",
    "locate_opening_at",
    "new_work",
    "_colloc_weights",
    "_dense",
    "_factor",
    "_newton",
]


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
def _colloc_weights(s: float) -> tuple[float, float, float]:
    """Weights of Z1, Z2, Z3 in the collocation polynomial at t0 + s h (s may exceed 1)."""
    l1 = s * (s - C2) * (s - 1.0) * RD1
    l2 = s * (s - C1) * (s - 1.0) * RD2
    l3 = s * (s - C1) * (s - C2) * RD3
    return l1, l2, l3


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
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


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
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
    faccon = max(faccon0, _UROUND) ** FACCON_POWER
    theta = _THET
    dynold = 1.0
    thqold = 1.0
    fr = GAMMA / h
    ar = ALPHA / h
    br = BETA / h
    newt = 0
    while True:
        if newt >= _NIT:
            return False, newt, theta, faccon, NEWTON_CUT
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
            return False, newt, theta, faccon, NEWTON_CUT
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


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
def _dense(y, z, s, out) -> None:
    """Collocation polynomial of the step (y, z) at t0 + s h, written into out."""
    l1, l2, l3 = _colloc_weights(s)
    for i in range(N_STATE):
        out[i] = y[i] + l1 * z[0, i] + l2 * z[1, i] + l3 * z[2, i]


class EventWork(NamedTuple):
    """The arrays the event location writes (:func:`locate_opening_at`)."""

    zacc: np.ndarray  #: (3, N_STATE): receives the accepted step's stage increments
    stage: tuple  #: (z, w, f) of the trial steps (:func:`_newton`)
    lu: tuple  #: the trial steps' factors (:func:`_factor`)
    scratch: tuple  #: (work, cbr, cbi)
    ytry: np.ndarray  #: a trial state
    y_event: np.ndarray  #: the event state


class RadauWork(NamedTuple):
    """The arrays of one :func:`integrate` run (:func:`new_work`)."""

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


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
def _cos_nutation(y, p) -> float:
    """cos(theta) of a state, without the atan2 of nutation_angle_of_state."""
    if p[P_FORM] == FORM_EULER:
        return math.cos(y[0])
    q2 = y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3]
    return 1.0 - 2.0 * (y[1] * y[1] + y[2] * y[2]) / q2


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
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


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
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


@njit(cache=True, fastmath=False, error_model="numpy", **REFCOUNT)
def new_work() -> RadauWork:
    """The arrays of one run (allocated once per run)."""
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


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
def guess_stages(z, zacc, h, h_acc, have_poly) -> None:
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


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
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


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
def dense_rows(t, y, h, z, t_stop, t_eval, i_eval, ts, ys, n_out, ytry) -> tuple[int, int]:
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
