"""Batched Radau IIA: the stiff points of a sweep advanced together in lanes.

:func:`integrate_radau_lanes` runs the method of :mod:`.radau` (same Newton
iteration, error estimate, step-size and Jacobian-reuse rules, same event
location) on many points at once, in the structure-of-arrays layout of
:mod:`.lanes` (``x[i * LANES + lane]``; matrices ``a[(i * N + j) * LANES +
lane]``). It takes the lanes that DOP853 found stiff (near-stick rig points)
from their last accepted state, as ``auto`` hands one trajectory to Radau.

Every attempted step runs in lock step over all lanes, in phases that are one
vectorised loop each:

1. the forward-difference Jacobian, for the lanes whose Jacobian is stale
   (computed for all, stored only for those);
2. the real and the complex LU of every lane (:mod:`.lane_linalg`), every
   attempt: with an unchanged h and J the factors are the same numbers the
   scalar code keeps, and refactoring all lanes costs less than selecting;
3. the simplified Newton iterations: each iteration evaluates the three
   stages and solves both systems for all lanes; a lane that has converged or
   failed keeps its iterate while the others go on;
4. the embedded error estimate (and its filtered second estimate where the
   scalar code takes it).

The per-lane decisions (convergence, acceptance, step size, Jacobian reuse,
the event test) are the scalar code's, lane by lane. The opening is located
with :func:`.radau.locate_opening` on the lane's data, as in the scalar code.

Only the thesis kernel (quaternion form) runs here; other kernels keep the
scalar hand-over. The results are those of the scalar Radau IIA to rounding
(the vectorised LU may round differently); ``tests/test_lanes.py`` checks the
opening times against it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..dynamics import nutation_angle_of_state, slip_and_spin
from ..layout import N_STATE, P_THETA_CR, P_WIDTH
from .common import increment_cap, underflow
from .contract import Status
from .lane_linalg import (
    lu_factor_complex_lanes,
    lu_factor_lanes,
    lu_solve_lanes,
    lu_solve_pair_lanes,
)
from .lanes import _cos_nutation_lanes, _rhs_thesis_lanes
from .lanes_layout import LANES
from .radau import _UROUND, locate_opening
from .radau_control import (
    _LIM_SHRINK,
    _NIT,
    _THET,
    newton_contraction,
    next_step,
    sliding_resumed,
    step_quotient,
)
from .radau_lane_steps import (
    NW_F,
    NW_R1,
    NW_R2,
    NW_R3,
    NW_SCAL,
    NW_SIZE,
    NW_Z,
    build_lanes,
    error_lanes,
    error_rhs_lanes,
    f0_masked,
    guess_lanes,
    jacobian_lanes,
    lane_vector,
    node_states,
    residual_lanes,
    stages_rhs,
    to_w,
    update_lanes,
    wnorm_lanes,
)

__all__ = ["integrate_radau_lanes"]

_N = N_STATE
_V = N_STATE * LANES  # one vector of every lane
_M = N_STATE * N_STATE * LANES  # one matrix of every lane
# Newton outcome of a lane in the current attempt
_RUNNING, _CONVERGED, _FAILED, _IDLE = 0, 1, 2, 3


@njit(cache=True, nogil=True, fastmath={"contract"}, error_model="numpy")
def integrate_radau_lanes(
    y0, t0, p, scale, t_max, h0, h_max, max_steps, hand_back, order, rtol, atol, event_tol,
    n_lanes, vw,
):  # fmt: skip
    """Radau IIA from (t0, y0) of many points until theta = theta_cr or t_max, in lanes.

    Parameters
    ----------
    y0 : ndarray, shape (n, 8)
        Start states (DOP853's last accepted states).
    t0 : ndarray, shape (n,)
        Start times [s].
    p : ndarray, shape (n, N_PARAM)
        Packed parameters, thesis kernel (``P_KERNEL = KERNEL_THESIS``) in every row.
    scale : ndarray, shape (n, 8)
        Error-weight scales.
    t_max, h0, h_max : ndarray, shape (n,)
        End time, initial step and largest step [s].
    max_steps : ndarray of int, shape (n,)
        Accepted-step limit per point.
    hand_back : ndarray of bool, shape (n,)
        Stop a point with ``NONSTIFF`` once sliding has resumed (as ``Controls.hand_back``
        in :func:`.radau.integrate`).
    order : ndarray of int, shape (n,)
        The order in which points enter the lanes.
    rtol, atol : float
        Tolerances (transformed as in :mod:`.radau`).
    event_tol : float
        Bracket width of the event time [s].
    n_lanes : int
        Lanes advanced together, 1 to :data:`LANES`.
    vw : int
        :data:`LANES`, passed at run time: the trip count of the vector loops (see
        :mod:`.lane_linalg`: with the constant LLVM unrolls them into scalar code).

    Returns
    -------
    tuple
        (status int8 (n,), t_event (n,), t_end (n,), y_end (n, 8), nfev (n,), n_steps (n,),
        n_rejected (n,)), statuses as :func:`.radau.integrate` (``NONSTIFF`` with the
        state where sliding had resumed in y_end / t_end).
    """
    if vw != LANES:
        raise ValueError("vw must be LANES")
    n_pts = y0.shape[0]
    n_par = p.shape[1]
    nl = max(1, min(n_lanes, LANES, n_pts))
    out = (
        np.zeros(n_pts, dtype=np.int8),
        np.full(n_pts, math.nan),
        np.zeros(n_pts),
        np.zeros((n_pts, _N)),
        np.zeros((3, n_pts), dtype=np.int64),
    )
    # vectors and matrices of every lane
    Y = np.zeros(_V)
    YN = np.zeros(_V)
    F0 = np.zeros(_V)
    SC = np.ones(_V)
    # the Newton workspace (radau_lane_steps.NW_*), and views of its vectors
    NW = np.zeros(NW_SIZE)
    F = NW[NW_F : NW_F + 3 * _V]
    Z = NW[NW_Z : NW_Z + 3 * _V]
    WORK = NW[NW_R1 : NW_R1 + _V]
    CBR = NW[NW_R2 : NW_R2 + _V]
    CBI = NW[NW_R3 : NW_R3 + _V]
    SCAL = NW[NW_SCAL : NW_SCAL + _V]
    for u in range(_V):
        SCAL[u] = 1.0
    CAP = np.ones(_V)
    FW = np.zeros(_V)
    ERRV = np.zeros(_V)
    ZACC = np.zeros(3 * _V)
    JAC = np.zeros(_M)
    LUR = np.zeros(_M)
    LUCR = np.zeros(_M)
    LUCI = np.zeros(_M)
    PIVR = np.zeros(_V)
    PIVC = np.zeros(_V)
    SWR = np.zeros(_N, dtype=np.bool_)
    SWC = np.zeros(_N, dtype=np.bool_)
    PL = np.zeros(n_par * LANES)
    # per lane
    T = np.zeros(LANES)
    H = np.ones(LANES)
    HACC = np.ones(LANES)
    TMAX = np.zeros(LANES)
    HMAX = np.zeros(LANES)
    HLIM = np.zeros(LANES)
    HGUS = np.zeros(LANES)
    ERRGUS = np.ones(LANES)
    FACCON = np.ones(LANES)
    THETA = np.zeros(LANES)
    DYNOLD = np.ones(LANES)
    THQOLD = np.ones(LANES)
    DYNO = np.zeros(LANES)
    ERR = np.zeros(LANES)
    HFAC = np.ones(LANES)
    GOLD = np.zeros(LANES)
    TSTICK = np.zeros(LANES)  # last time the slip speed was below saturation (hand_back)
    COS_CR = np.zeros(LANES)
    COSN = np.zeros(LANES)
    COSK = np.zeros(LANES)
    VMAX = np.zeros(LANES)
    MAXST = np.zeros(LANES, dtype=np.int64)
    IDX = np.zeros(LANES, dtype=np.int64)
    NEWT = np.zeros(LANES, dtype=np.int64)
    CNT = np.zeros((3, LANES), dtype=np.int64)  # nfev, steps, rejected
    STATE = np.zeros(LANES, dtype=np.int64)  # Newton outcome this attempt
    OK = np.ones(LANES, dtype=np.bool_)
    FIN = np.ones(LANES, dtype=np.bool_)
    RUN = np.zeros(LANES, dtype=np.bool_)
    NJ = np.zeros(LANES, dtype=np.bool_)
    FRESH = np.zeros(LANES, dtype=np.bool_)
    POLY = np.zeros(LANES, dtype=np.bool_)
    FIRST = np.zeros(LANES, dtype=np.bool_)
    HB = np.zeros(LANES, dtype=np.bool_)
    REJ = np.zeros(LANES, dtype=np.bool_)
    ACC = np.zeros(LANES, dtype=np.bool_)
    LIVE = np.zeros(LANES, dtype=np.bool_)
    # RADAU5's tolerance transformation and Newton stopping tolerance (as radau.integrate)
    quot_tol = atol / rtol
    rtol = 0.1 * rtol ** (2.0 / 3.0)
    atol = rtol * quot_tol
    fnewt = max(10.0 * _UROUND / rtol, min(0.03, math.sqrt(rtol)))
    # one lane's data for the scalar routines (event location)
    ys = np.empty(_N)
    yns = np.empty(_N)
    ps = np.empty(n_par)
    scals = np.empty(_N)
    zs = np.empty((3, _N))
    jacs = np.empty((_N, _N))
    scratch_s = (np.empty(_N), np.empty(_N), np.empty(_N))
    ytry_s = np.empty(_N)
    zacc_s = np.empty((3, _N))
    stage_s = (np.empty((3, _N)), np.empty((3, _N)), np.empty((3, _N)))
    lu_s = (
        np.empty((_N, _N)), np.empty(_N, dtype=np.int64), np.empty((_N, _N)),
        np.empty((_N, _N)), np.empty(_N, dtype=np.int64),
    )  # fmt: skip
    y_ev = np.empty(_N)
    nxt = 0
    while True:
        # ---- refill free lanes, then the checks at the top of the scalar loop ----
        for j in range(nl):
            while True:
                if not LIVE[j]:
                    if nxt >= n_pts:
                        break
                    _fill(j, order[nxt], y0, t0, p, scale, t_max, h0, h_max, max_steps,
                          hand_back, PL, Y, SC, CAP, T, H, HACC, TMAX, HMAX, MAXST, GOLD,
                          TSTICK, COS_CR, IDX, CNT, NJ, FRESH, POLY, FIRST, HB, REJ, FACCON,
                          HGUS, ERRGUS, HLIM, ys, ps)  # fmt: skip
                    LIVE[j] = True
                    nxt += 1
                if not T[j] < TMAX[j]:
                    LIVE[j] = _finish(j, Status.T_MAX, math.nan, Y, T, IDX, CNT, out)
                elif CNT[1, j] >= MAXST[j]:
                    LIVE[j] = _finish(j, Status.STEP_LIMIT, math.nan, Y, T, IDX, CNT, out)
                else:
                    break
        if nxt >= n_pts:
            j = 0
            while j < nl:
                if LIVE[j]:
                    j += 1
                    continue
                if nl - 1 > j:
                    _move(nl - 1, j, PL, Y, F0, SC, CAP, ZACC, JAC, T, H, HACC, TMAX, HMAX,
                          HLIM, HGUS, ERRGUS, FACCON, GOLD, TSTICK, COS_CR, MAXST, IDX, CNT,
                          NJ, FRESH, POLY, FIRST, HB, REJ, LIVE)  # fmt: skip
                nl -= 1
            if nl == 0:
                break
        # idle lanes run the vector loops on harmless numbers
        for j in range(nl, LANES):
            H[j] = 1.0
            HACC[j] = 1.0
            NJ[j] = False
        # f(y) of lanes just filled (after a step it is computed with the accepted state)
        for j in range(nl):
            if FIRST[j] and CNT[0, j] == 0:
                ACC[j] = True
            else:
                ACC[j] = False
        f0_masked(Y, PL, F0, FW, ACC, CNT, vw)
        # ---- phase 1: Jacobian where stale ----
        any_jac = False
        for j in range(nl):
            if NJ[j]:
                any_jac = True
        if any_jac:
            jacobian_lanes(Y, F0, PL, SC, JAC, NJ, WORK, FW, CAP, VMAX, vw)
            for j in range(nl):
                if NJ[j]:
                    CNT[0, j] += _N
                    NJ[j] = False
                    FRESH[j] = True
        for j in range(nl):
            if T[j] + 1.01 * H[j] >= TMAX[j]:
                H[j] = TMAX[j] - T[j]
        # ---- phase 2: LU of every lane ----
        build_lanes(JAC, H, LUR, LUCR, LUCI, vw)
        for j in range(vw):
            OK[j] = True
        lu_factor_lanes(LUR, PIVR, SWR, OK, VMAX, vw)
        lu_factor_complex_lanes(LUCR, LUCI, PIVC, SWC, OK, VMAX, vw)
        for j in range(nl):
            STATE[j] = _RUNNING
            if not OK[j]:
                CNT[2, j] += 1
                H[j] *= 0.5
                STATE[j] = _IDLE
                if underflow(H[j], T[j]):
                    LIVE[j] = _finish(j, Status.FAILED, math.nan, Y, T, IDX, CNT, out)
        for j in range(nl, LANES):
            STATE[j] = _IDLE
        # ---- phase 3: simplified Newton ----
        for i in range(_N):
            for j in range(vw):
                u = i * LANES + j
                SCAL[u] = 1.0 / (atol * SC[u] + rtol * abs(Y[u]))
        guess_lanes(NW, ZACC, H, HACC, POLY, vw)
        to_w(NW, vw)
        for j in range(nl):
            if STATE[j] == _RUNNING:
                FACCON[j] = max(FACCON[j], _UROUND) ** 0.8
            THETA[j] = _THET
            DYNOLD[j] = 1.0
            THQOLD[j] = 1.0
            NEWT[j] = 0
        while True:
            running = False
            for j in range(nl):
                if STATE[j] == _RUNNING:
                    if NEWT[j] >= _NIT:
                        STATE[j] = _FAILED
                        HFAC[j] = 0.5
                    else:
                        running = True
            if not running:
                break
            stages_rhs(Y, Z, PL, F, WORK, vw)
            residual_lanes(NW, H, FIN, vw)
            lu_solve_pair_lanes(LUR, PIVR, SWR, WORK, LUCR, LUCI, PIVC, SWC, CBR, CBI, vw)
            wnorm_lanes(NW, DYNO, vw)
            for j in range(vw):
                RUN[j] = False
            for j in range(nl):
                if STATE[j] != _RUNNING:
                    continue
                NEWT[j] += 1
                CNT[0, j] += 3
                newt = NEWT[j]
                if not FIN[j]:
                    STATE[j] = _FAILED
                    HFAC[j] = 0.5
                    continue
                dyno = DYNO[j]
                failed, THETA[j], THQOLD[j], FACCON[j], HFAC[j] = newton_contraction(
                    newt, dyno, DYNOLD[j], THQOLD[j], THETA[j], FACCON[j], fnewt
                )
                if failed:
                    STATE[j] = _FAILED
                    continue
                DYNOLD[j] = max(dyno, _UROUND)
                RUN[j] = True
            update_lanes(NW, RUN, vw)
            for j in range(nl):
                if RUN[j] and FACCON[j] * DYNO[j] <= fnewt:
                    STATE[j] = _CONVERGED
        for j in range(nl):
            if STATE[j] == _FAILED:
                HLIM[j] = min(HLIM[j], H[j] * _LIM_SHRINK)
                CNT[2, j] += 1
                REJ[j] = True
                H[j] *= HFAC[j]
                if not FRESH[j]:
                    NJ[j] = True
                if underflow(H[j], T[j]):
                    LIVE[j] = _finish(j, Status.FAILED, math.nan, Y, T, IDX, CNT, out)
        # ---- phase 4: embedded error estimate ----
        error_rhs_lanes(Y, Z, F0, H, YN, ERRV, WORK, vw)
        lu_solve_lanes(LUR, PIVR, SWR, WORK, vw)
        error_lanes(Y, YN, WORK, rtol, atol, SC, ERR, vw)
        any_filter = False
        for j in range(vw):
            ACC[j] = (j < nl and STATE[j] == _CONVERGED and ERR[j] >= 1.0
                      and (FIRST[j] or REJ[j]))  # fmt: skip
            any_filter = any_filter or ACC[j]
        if any_filter:
            # the estimate is unreliable for very stiff components: filter once more
            for u in range(_N * vw):
                CBR[u] = Y[u] + WORK[u]
            _rhs_thesis_lanes(CBR, PL, FW, 0)
            for u in range(_N * vw):
                CBI[u] = FW[u] + ERRV[u] - F0[u]
            lu_solve_lanes(LUR, PIVR, SWR, CBI, vw)
            error_lanes(Y, YN, CBI, rtol, atol, SC, DYNO, vw)
            for j in range(nl):
                if ACC[j]:
                    CNT[0, j] += 1
                    ERR[j] = DYNO[j]
        # largest cos(theta) over the nodes c1, c2 and the step end (the opening pre-test)
        _cos_nutation_lanes(YN, COSN)
        for k in range(2):
            node_states(Y, Z, k, WORK, vw)
            _cos_nutation_lanes(WORK, COSK)
            for j in range(vw):
                COSN[j] = max(COSN[j], COSK[j])
        # ---- per lane: acceptance, event, step size ----
        for j in range(nl):
            ACC[j] = False
            if STATE[j] != _CONVERGED or not LIVE[j]:
                continue
            err = ERR[j]
            if not (err == err):
                err = 1e10
            h = H[j]
            quot, quot_std = step_quotient(err, NEWT[j], h, FIRST[j], HGUS[j], ERRGUS[j])
            if err >= 1.0:
                CNT[2, j] += 1
                REJ[j] = True
                H[j] = h * 0.1 if FIRST[j] else h / quot_std
                if not FRESH[j]:
                    NJ[j] = True
                if underflow(H[j], T[j]):
                    LIVE[j] = _finish(j, Status.FAILED, math.nan, Y, T, IDX, CNT, out)
                continue
            h_new = h / quot
            HGUS[j] = h
            ERRGUS[j] = max(1e-2, err)
            # opening: the nodes and the step end are well above theta_cr unless one of
            # their cos(theta) comes near cos(theta_cr); only then the scalar test
            if COSN[j] >= COS_CR[j] - 1e-9 or not (COSN[j] == COSN[j]):
                for i in range(n_par):
                    ps[i] = PL[i * LANES + j]
                lane_vector(Y, j, 0, ys)
                lane_vector(YN, j, 0, yns)
                for k in range(3):
                    lane_vector(Z, j, k, zs[k])
                theta_cr = ps[P_THETA_CR]
                if GOLD[j] == math.inf:  # the exact g at the step start
                    GOLD[j] = nutation_angle_of_state(ys, ps) - theta_cr
                g_new = nutation_angle_of_state(yns, ps) - theta_cr
                if GOLD[j] > 0.0:
                    lane_vector(SCAL, j, 0, scals)
                    for i in range(_N):
                        for c in range(_N):
                            jacs[i, c] = JAC[(i * _N + c) * LANES + j]
                    found, t_ev, nf = locate_opening(
                        T[j], ys, h, zs, yns, GOLD[j], g_new, ps, scals, jacs, zacc_s,
                        stage_s, lu_s, scratch_s, fnewt, event_tol, ytry_s, y_ev,
                    )  # fmt: skip
                    CNT[0, j] += nf
                    if found:
                        LIVE[j] = _finish(j, Status.OPENED, t_ev, Y, T, IDX, CNT, out)
                        continue
                GOLD[j] = g_new
            else:
                GOLD[j] = math.inf
            for u in range(3 * _N):
                ZACC[u * LANES + j] = Z[u * LANES + j]
            HACC[j] = h
            POLY[j] = True
            T[j] = T[j] + h
            for i in range(_N):
                Y[i * LANES + j] = YN[i * LANES + j]
            ACC[j] = True
            CNT[1, j] += 1
            if not (Y[j] == Y[j]):
                LIVE[j] = _finish(j, Status.FAILED, math.nan, Y, T, IDX, CNT, out)
                ACC[j] = False
                continue
            if HB[j]:
                lane_vector(Y, j, 0, ys)
                for i in range(n_par):
                    ps[i] = PL[i * LANES + j]
                slip, spin = slip_and_spin(ys, ps)
                back, TSTICK[j] = sliding_resumed(T[j], TSTICK[j], slip, spin, ps[P_WIDTH])
                if back:
                    CNT[0, j] += 1  # the scalar code has evaluated f at the new state
                    LIVE[j] = _finish(j, Status.NONSTIFF, math.nan, Y, T, IDX, CNT, out)
                    ACC[j] = False
                    continue
            H[j], HLIM[j], slow = next_step(h, h_new, HLIM[j], HMAX[j], REJ[j], THETA[j])
            NJ[j] = NJ[j] or slow
            FIRST[j] = False
            REJ[j] = False
            FRESH[j] = False
        for j in range(nl, LANES):
            ACC[j] = False
        f0_masked(Y, PL, F0, FW, ACC, CNT, vw)
    st_out, tev_out, tend_out, yend_out, cnt_out = out
    return st_out, tev_out, tend_out, yend_out, cnt_out[0], cnt_out[1], cnt_out[2]


@njit(cache=True)
def _fill(j, q, y0, t0, p, scale, t_max, h0, h_max, max_steps, hand_back, PL, Y, SC, CAP, T,
          H, HACC, TMAX, HMAX, MAXST, GOLD, TSTICK, COS_CR, IDX, CNT, NJ, FRESH, POLY, FIRST,
          HB, REJ, FACCON, HGUS, ERRGUS, HLIM, ys, ps) -> None:  # fmt: skip
    """Load point q into lane j, as :func:`.radau.integrate` starts a run."""
    n_par = p.shape[1]
    IDX[j] = q
    for i in range(n_par):
        PL[i * LANES + j] = p[q, i]
        ps[i] = p[q, i]
    w_ref = 1.0
    for i in range(_N):
        w_ref = max(w_ref, scale[q, i])
    for i in range(_N):
        Y[i * LANES + j] = y0[q, i]
        SC[i * LANES + j] = scale[q, i]
        ys[i] = y0[q, i]
        CAP[i * LANES + j] = increment_cap(scale[q, i], ps[P_WIDTH], w_ref, True)
    T[j] = t0[q]
    TMAX[j] = t_max[q]
    HMAX[j] = h_max[q]
    MAXST[j] = max_steps[q]
    H[j] = min(h0[q], h_max[q], t_max[q] - t0[q])
    HACC[j] = 1.0
    GOLD[j] = nutation_angle_of_state(ys, ps) - ps[P_THETA_CR]
    TSTICK[j] = t0[q]
    HB[j] = hand_back[q]
    COS_CR[j] = math.cos(ps[P_THETA_CR])
    CNT[:, j] = 0
    NJ[j] = True
    FRESH[j] = False
    POLY[j] = False
    FIRST[j] = True
    REJ[j] = False
    FACCON[j] = 1.0
    HGUS[j] = 0.0
    ERRGUS[j] = 1.0
    HLIM[j] = math.inf


@njit(cache=True)
def _finish(j, status, t_event, Y, T, IDX, CNT, out) -> bool:
    """Write lane j's outcome (and its time and state) to its point; False (the lane is
    free)."""
    st_out, tev_out, tend_out, yend_out, cnt_out = out
    q = IDX[j]
    st_out[q] = status
    tev_out[q] = t_event
    tend_out[q] = T[j]
    for i in range(_N):
        yend_out[q, i] = Y[i * LANES + j]
    for c in range(3):
        cnt_out[c, q] = CNT[c, j]
    return False


@njit(cache=True)
def _move(
    a, b, PL, Y, F0, SC, CAP, ZACC, JAC, T, H, HACC, TMAX, HMAX, HLIM, HGUS, ERRGUS, FACCON,
    GOLD, TSTICK, COS_CR, MAXST, IDX, CNT, NJ, FRESH, POLY, FIRST, HB, REJ, LIVE,
) -> None:  # fmt: skip
    """Copy everything lane a carries from step to step into lane b."""
    for i in range(PL.shape[0] // LANES):
        PL[i * LANES + b] = PL[i * LANES + a]
    for i in range(_N):
        for X in (Y, F0, SC, CAP):
            X[i * LANES + b] = X[i * LANES + a]
    for u in range(3 * _N):
        ZACC[u * LANES + b] = ZACC[u * LANES + a]
    for u in range(_N * _N):
        JAC[u * LANES + b] = JAC[u * LANES + a]
    for X in (T, H, HACC, TMAX, HMAX, HLIM, HGUS, ERRGUS, FACCON, GOLD, TSTICK, COS_CR):
        X[b] = X[a]
    MAXST[b] = MAXST[a]
    IDX[b] = IDX[a]
    CNT[:, b] = CNT[:, a]
    for X in (NJ, FRESH, POLY, FIRST, HB, REJ, LIVE):
        X[b] = X[a]
    LIVE[a] = False
