"""Batched DOP853: many trajectories advanced together in lanes (structure of arrays).

:func:`integrate_lanes` runs the method of :mod:`.dop853` on a whole set of
points at once. ``n_lanes`` trajectories are held side by side, component by
component (state ``Y[i, lane]``, stages ``K[s, i, lane]``), so each stage's
right-hand side is one loop over lanes that the compiler vectorises (SIMD);
every lane keeps its own time, step size, error control, stiffness test,
opening event and termination. A lane whose trajectory ends (opened, t_max,
step limit, failure, or stiff) is refilled at once with the next point of the
queue, so no lane waits for the slowest one; when the queue is empty the live
lanes are packed to the front, so the per-lane bookkeeping shortens. Points enter in the order
given (callers put the costliest first, so the tail is short).

Same answers as the one-trajectory path: per lane the arithmetic is that of
:func:`.dop853.integrate` (same stages, error norm, step-size control,
stiffness test, event location by re-stepping), and the right-hand side of
the thesis's kernel (:mod:`obturator.core.specialised`) is the same compiled
function in both; ``tests/test_lanes.py`` compares every point of sweeps with
the scalar path. Lanes that turn stiff end with status ``STIFF`` and their
last accepted state, for the caller to hand to Radau IIA exactly as ``auto``
does (:func:`obturator.core.integrators.integrate`). Points with the generic
kernel run here too, calling the scalar right-hand side lane by lane.

The vector loops always run over all :data:`LANES` lanes, live or not: with a
trip count below the vector width part of the lanes would run through LLVM's
scalar remainder loop, whose FMA contraction may differ, and a point's t_cr
would depend on how many points shared its batch (observed at the last digit).

Only the opening time is returned (no recorded steps, no t_eval): this is the
path of sweeps, Monte Carlo and fits.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, uint64

from ..dynamics import nutation_angle_of_state, rhs
from ..layout import KERNEL_THESIS, N_STATE, P_DERIVED, P_KERNEL, P_THETA_CR, P_VISC
from ..specialised import thesis_rates
from .common import crossed, underflow
from .contract import Status
from .dop853 import (
    STEP_ALLOWANCE,
    STEPS_PER_PERIOD,
    STIFF_HLAMBDA,
    STIFF_STEPS,
    TOL_FACTOR,
    locate_event,
    step_factor,
    stiffness_product,
)
from .lane_sums import error_sums, stage_sum
from .lanes_layout import LANE_KERNEL, LANES, NO_REFCOUNT

__all__ = ["integrate_lanes", "LANES", "DEFAULT_LANES"]

DEFAULT_LANES = LANES


@njit(**LANE_KERNEL)
def _rhs_thesis_lanes(y, p, dy, do) -> None:
    """:func:`~obturator.core.specialised.thesis_rates` of every lane, one vector loop.

    A lane kernel (:data:`.lanes_layout.LANE_KERNEL`: no reference counting), kept
    apart from the generic right-hand side, which allocates. The loop evaluates the
    laminar viscous branch; if any lane's slip reached the turbulent transition it
    is run again with the turbulent branch (same results as the scalar kernel).
    """
    if _thesis_lanes(y, p, dy, do, False):
        _thesis_lanes(y, p, dy, do, True)


@njit(inline="always", **LANE_KERNEL)
def _thesis_lanes(y, p, dy, do, turbulent) -> int:
    """The loop of :func:`_rhs_thesis_lanes`; returns the lanes at or above the turbulent
    transition.

    Indices are cast to unsigned (see :mod:`.lane_sums`): with signed offsets numba's
    negative-index wrap-around kept this loop scalar (measured ~32 ns per lane and
    call against ~10 ns vectorised).
    """
    d = P_DERIVED
    n_above = 0
    for j in range(LANES):
        c = (
            p[uint64((P_VISC + 1) * LANES + j)],
            p[uint64((P_VISC + 2) * LANES + j)],
            p[uint64((P_VISC + 3) * LANES + j)],
            p[uint64(d * LANES + j)],
            p[uint64((d + 1) * LANES + j)],
            p[uint64((d + 2) * LANES + j)],
            p[uint64((d + 3) * LANES + j)],
            p[uint64((d + 4) * LANES + j)],
            p[uint64((d + 5) * LANES + j)],
            p[uint64((d + 6) * LANES + j)],
            p[uint64((d + 7) * LANES + j)],
        )
        r0, r1, r2, r3, r4, r5, r6, r7, above = thesis_rates(
            y[j], y[uint64(j + LANES)], y[uint64(j + 2 * LANES)],
            y[uint64(j + 3 * LANES)], y[uint64(j + 4 * LANES)], y[uint64(j + 5 * LANES)],
            y[uint64(j + 6 * LANES)], y[uint64(j + 7 * LANES)], c, turbulent,
        )  # fmt: skip
        n_above += above
        o = do + j
        dy[uint64(o)] = r0
        dy[uint64(o + LANES)] = r1
        dy[uint64(o + 2 * LANES)] = r2
        dy[uint64(o + 3 * LANES)] = r3
        dy[uint64(o + 4 * LANES)] = r4
        dy[uint64(o + 5 * LANES)] = r5
        dy[uint64(o + 6 * LANES)] = r6
        dy[uint64(o + 7 * LANES)] = r7
    return n_above


@njit(cache=True, error_model="numpy")
def _rhs_generic_lanes(y, p, dy, do, nl) -> None:
    """The generic right-hand side (:func:`~obturator.core.dynamics.rhs`) lane by lane."""
    n_par = p.shape[0] // LANES
    ys = np.empty(N_STATE)
    ds = np.empty(N_STATE)
    ps = np.empty(n_par)
    for j in range(nl):
        for i in range(N_STATE):
            ys[i] = y[i * LANES + j]
        for i in range(n_par):
            ps[i] = p[i * LANES + j]
        rhs(0.0, ys, ps, ds)
        for i in range(N_STATE):
            dy[do + i * LANES + j] = ds[i]


_KS = N_STATE * LANES  # stride of one stage in K


@njit(**LANE_KERNEL)
def _stages_thesis_lanes(y, h, p, k, ynew, work) -> None:
    """Stages k[1..11] and the 8th-order solution of every lane (k[0] given), thesis kernel."""
    for s in range(1, 12):
        stage_sum(s, y, h, k, work)
        _rhs_thesis_lanes(work, p, k, s * _KS)
    stage_sum(12, y, h, k, ynew)


@njit(cache=True, fastmath={"contract"}, error_model="numpy")
def _stages_generic_lanes(y, h, p, k, ynew, work, nl) -> None:
    """:func:`_stages_thesis_lanes` with the generic right-hand side in lanes 0..nl-1."""
    for s in range(1, 12):
        stage_sum(s, y, h, k, work)
        _rhs_generic_lanes(work, p, k, s * _KS, nl)
    stage_sum(12, y, h, k, ynew)


@njit(**LANE_KERNEL)
def _error_lanes(k, h, y, ynew, rtol, atol, scale, err, s5, s3) -> None:
    """DOP853's combined error estimate of every lane (as :func:`.dop853._error_norm`)."""
    error_sums(k, y, ynew, rtol, atol, scale, s5, s3)
    for j in range(LANES):
        if s5[j] == 0.0 and s3[j] == 0.0:
            err[j] = 0.0
        else:
            err[j] = abs(h[j]) * s5[j] / math.sqrt((s5[j] + 0.01 * s3[j]) * N_STATE)


@njit(cache=True, error_model="numpy", **NO_REFCOUNT)  # no contract: as dop853.integrate
def _control_lanes(err, fac, hl, h, f1, k, ynew, work, num, den) -> None:
    """Step-size factor and stiffness estimate of every lane, in vector loops.

    As :func:`.dop853.integrate` computes them (compiled, like it, without FMA
    contraction; same operations in the same order): a NaN error counts as
    1e10, ``fac = step_factor(err)``, ``hl = stiffness_product(h, num, den)``
    with num = |f(y_new) - k_12|^2 and den = |y_new - y_12|^2. num and den
    reuse the error sums' scratch arrays.
    """
    for j in range(LANES):
        e = err[j]
        e = e if e == e else 1e10
        err[j] = e
        fac[j] = step_factor(e)
        num[j] = 0.0
        den[j] = 0.0
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            num[j] += (f1[u] - k[uint64(11 * _KS + r + j)]) ** 2
            den[j] += (ynew[u] - work[u]) ** 2
    for j in range(LANES):
        hl[j] = stiffness_product(h[j], num[j], den[j])


@njit(**LANE_KERNEL)
def _cos_nutation_lanes(y, out) -> None:
    """cos(theta) = 1 - 2 (q1^2 + q2^2) / |q|^2 of quaternion-form lanes (vectorised)."""
    for j in range(LANES):
        q0 = y[j]
        q1 = y[uint64(LANES + j)]
        q2 = y[uint64(2 * LANES + j)]
        q3 = y[uint64(3 * LANES + j)]
        out[j] = 1.0 - 2.0 * (q1 * q1 + q2 * q2) / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)


@njit(cache=True)
def _locate_event(t, h, y, k0, p, g_old, g_new, ynew, event_tol):
    """:func:`.dop853.locate_event` for one lane; returns (t_event, y_event, nfev)."""
    k = np.empty((12, N_STATE))
    for i in range(N_STATE):
        k[0, i] = k0[i]
    y_event = ynew.copy()
    t_ev, nfev = locate_event(
        t, y, h, p, k, np.empty(N_STATE), np.empty(N_STATE), y_event, g_old, g_new, event_tol
    )
    return t_ev, y_event, nfev


@njit(cache=True, nogil=True, fastmath={"contract"}, error_model="numpy")
def integrate_lanes(
    y0, t0, p, scale, t_max, h0, h_max, max_steps, order, rtol, atol, event_tol, n_lanes
):
    """Integrate points until theta = theta_cr (terminal) or t_max, `n_lanes` at a time.

    Parameters
    ----------
    y0 : ndarray, shape (n, 8)
        Initial states.
    t0 : ndarray, shape (n,)
        Start times [s] (0 at release; later where ``auto`` comes back from Radau IIA).
    p : ndarray, shape (n, N_PARAM)
        Packed parameters; every row must have the same ``P_KERNEL``.
    scale : ndarray, shape (n, 8)
        Error-weight scales (as in :class:`.contract.Problem`).
    t_max, h0, h_max : ndarray, shape (n,)
        End time, initial step and largest step of each point [s].
    max_steps : ndarray of int, shape (n,)
        Accepted-step limit per point.
    order : ndarray of int, shape (n,)
        The order in which points enter the lanes (a permutation of 0..n-1).
    rtol, atol : float
        Tolerances (transformed as in :mod:`.dop853`).
    event_tol : float
        Bracket width of the event time [s].
    n_lanes : int
        Lanes advanced together, 1 to :data:`LANES`.

    Returns
    -------
    tuple
        (status int8 (n,), t_event (n,), t_end (n,), y_end (n, 8), nfev (n,),
        n_steps (n,), n_rejected (n,)); statuses as :func:`.dop853.integrate`
        (``STIFF`` with the last accepted state in y_end / t_end).
    """
    n_pts = y0.shape[0]
    n = N_STATE
    n_par = p.shape[1]
    kernel = p[0, P_KERNEL] if n_pts > 0 else 0.0
    nl = max(1, min(n_lanes, LANES, n_pts))
    out = (
        np.zeros(n_pts, dtype=np.int8),
        np.full(n_pts, math.nan),
        np.zeros(n_pts),
        np.zeros((n_pts, n)),
        np.zeros(n_pts, dtype=np.int64),
        np.zeros(n_pts, dtype=np.int64),
        np.zeros(n_pts, dtype=np.int64),
    )
    # lane state, flat and component-major (x[i * LANES + lane])
    Y = np.zeros(n * LANES)
    YN = np.zeros(n * LANES)
    W = np.zeros(n * LANES)
    F1 = np.zeros(n * LANES)
    K = np.zeros(12 * n * LANES)
    PL = np.zeros(n_par * LANES)
    SC = np.ones(n * LANES)
    T = np.zeros(LANES)
    H = np.zeros(LANES)
    ERR = np.zeros(LANES)
    S5 = np.zeros(LANES)
    S3 = np.zeros(LANES)
    COSN = np.zeros(LANES)  # cos(theta) at the step ends (quaternion form)
    FAC = np.zeros(LANES)  # step factor 0.9 err^(-1/8)
    HL = np.zeros(LANES)  # stiffness estimate h |lambda|
    T0 = np.zeros(LANES)  # start time (the step budget counts from it)
    TMAX = np.zeros(LANES)
    HMAX = np.zeros(LANES)
    MAXST = np.zeros(LANES, dtype=np.int64)
    SPT = np.zeros(LANES)  # step budget per second of simulated time
    GOLD = np.zeros(LANES)
    COS_CR = np.zeros(LANES)
    IDX = np.zeros(LANES, dtype=np.int64)
    CNT = np.zeros((5, LANES), dtype=np.int64)  # nfev, steps, rejected, stiff run, calm run
    REJ = np.zeros(LANES, dtype=np.bool_)
    LIVE = np.zeros(LANES, dtype=np.bool_)
    lanes = (Y, K, PL, SC, T, T0, H, TMAX, HMAX, MAXST, SPT, GOLD, COS_CR, IDX, CNT, REJ, LIVE)
    quaternion = kernel == KERNEL_THESIS  # the thesis kernel is quaternion-form
    tol_f = max(TOL_FACTOR, 1e-14 / rtol)
    rtol = tol_f * rtol
    atol = tol_f * atol
    ys = np.empty(n)
    ps = np.empty(n_par)
    fs = np.empty(n)
    yn_s = np.empty(n)
    k0s = np.empty(n)
    nxt = 0  # next entry of `order` to load
    while True:
        # ---- (re)fill free lanes; a point may end before its first step ----
        for j in range(nl):
            while not LIVE[j] and nxt < n_pts:
                q = order[nxt]
                nxt += 1
                IDX[j] = q
                w0 = 0.0
                for i in range(n_par):
                    PL[i * LANES + j] = p[q, i]
                    ps[i] = p[q, i]
                for i in range(n):
                    Y[i * LANES + j] = y0[q, i]
                    SC[i * LANES + j] = scale[q, i]
                    w0 = max(w0, scale[q, i])
                    ys[i] = y0[q, i]
                rhs(0.0, ys, ps, fs)
                for i in range(n):
                    K[i * LANES + j] = fs[i]
                T[j] = t0[q]
                T0[j] = t0[q]
                TMAX[j] = t_max[q]
                HMAX[j] = h_max[q]
                MAXST[j] = max_steps[q]
                SPT[j] = STEPS_PER_PERIOD * w0 / (2.0 * math.pi)
                H[j] = min(h0[q], h_max[q], t_max[q] - t0[q])
                GOLD[j] = nutation_angle_of_state(ys, ps) - ps[P_THETA_CR]
                COS_CR[j] = math.cos(ps[P_THETA_CR])
                CNT[:, j] = 0
                CNT[0, j] = 1
                REJ[j] = False
                code, H[j] = _top_of_step(T[j], T0[j], H[j], TMAX[j], SPT[j], 0, 0, MAXST[j])
                LIVE[j] = code == _GO_ON or _finish(j, code, math.nan, Y, T, IDX, CNT, out)
        # ---- once the queue is empty, pack the live lanes to the front ----
        if nxt >= n_pts:
            j = 0
            while j < nl:
                if LIVE[j]:
                    j += 1
                    continue
                if nl - 1 > j:
                    _move_lane(nl - 1, j, lanes)
                nl -= 1
            if nl == 0:
                break
        # ---- one trial step in every lane ----
        if quaternion:
            _stages_thesis_lanes(Y, H, PL, K, YN, W)
            _rhs_thesis_lanes(YN, PL, F1, 0)
            _cos_nutation_lanes(YN, COSN)
        else:
            _stages_generic_lanes(Y, H, PL, K, YN, W, nl)
            _rhs_generic_lanes(YN, PL, F1, 0, nl)
        _error_lanes(K, H, Y, YN, rtol, atol, SC, ERR, S5, S3)
        _control_lanes(ERR, FAC, HL, H, F1, K, YN, W, S5, S3)
        for j in range(nl):
            CNT[0, j] += 11
            err = ERR[j]
            if err > 1.0:
                CNT[2, j] += 1
                REJ[j] = True
                H[j] *= max(0.2, FAC[j])
                if underflow(H[j], T[j]):
                    LIVE[j] = _finish(j, Status.STIFF, math.nan, Y, T, IDX, CNT, out)
                    continue
            else:
                CNT[0, j] += 1
                h = H[j]
                t_new = T[j] + h
                # Hairer's stiffness test, as in dop853.integrate
                if HL[j] > STIFF_HLAMBDA:
                    CNT[4, j] = 0
                    CNT[3, j] += 1
                    if CNT[3, j] >= STIFF_STEPS:
                        LIVE[j] = _finish(j, Status.STIFF, math.nan, Y, T, IDX, CNT, out)
                        continue
                else:
                    CNT[4, j] += 1
                    if CNT[4, j] >= 6:
                        CNT[3, j] = 0
                # opening test: theta_new is well above theta_cr unless cos(theta_new)
                # comes near cos(theta_cr); only then the exact g = theta - theta_cr
                # of dop853.integrate (atan2) is needed
                if quaternion and COSN[j] < COS_CR[j] - 1e-9:
                    g_new = math.inf  # positive: its sign is all the test needs
                else:
                    for i in range(n):
                        yn_s[i] = YN[i * LANES + j]
                    for i in range(n_par):
                        ps[i] = PL[i * LANES + j]
                    g_new = nutation_angle_of_state(yn_s, ps) - ps[P_THETA_CR]
                if crossed(GOLD[j], g_new, math.nan):  # g_new <= 0: yn_s, ps filled above
                    for i in range(n):
                        ys[i] = Y[i * LANES + j]
                        k0s[i] = K[i * LANES + j]
                    if GOLD[j] == math.inf:  # the exact g at the step start
                        GOLD[j] = nutation_angle_of_state(ys, ps) - ps[P_THETA_CR]
                    t_ev, y_ev, nf = _locate_event(
                        T[j], h, ys, k0s, ps, GOLD[j], g_new, yn_s, event_tol
                    )
                    CNT[0, j] += nf
                    for i in range(n):
                        Y[i * LANES + j] = y_ev[i]
                    T[j] = t_ev
                    LIVE[j] = _finish(j, Status.OPENED, t_ev, Y, T, IDX, CNT, out)
                    continue
                GOLD[j] = g_new
                T[j] = t_new
                for i in range(n):
                    Y[i * LANES + j] = YN[i * LANES + j]
                    K[i * LANES + j] = F1[i * LANES + j]
                CNT[1, j] += 1
                if not (Y[j] == Y[j]):
                    LIVE[j] = _finish(j, Status.STIFF, math.nan, Y, T, IDX, CNT, out)
                    continue
                fac = min(10.0, max(0.2, FAC[j]))
                if REJ[j]:
                    fac = min(fac, 1.0)
                REJ[j] = False
                H[j] = min(h * fac, HMAX[j])
            code, H[j] = _top_of_step(
                T[j], T0[j], H[j], TMAX[j], SPT[j], CNT[1, j], CNT[2, j], MAXST[j]
            )
            LIVE[j] = code == _GO_ON or _finish(j, code, math.nan, Y, T, IDX, CNT, out)
    return out


#: Going on: what :func:`_top_of_step` returns when the lane's point goes on; the
#: codes that end it, as plain ints (numba has no ``int(IntEnum)``).
_GO_ON = -100
_T_MAX, _STEP_LIMIT, _STIFF = int(Status.T_MAX), int(Status.STEP_LIMIT), int(Status.STIFF)


@njit(cache=True)
def _top_of_step(t, t0, h, t_max, steps_per_s, n_steps, n_rejected, max_steps):
    """The checks at the top of :func:`.dop853.integrate`'s loop for one lane (started
    at t0).

    Returns (code, h): ``_GO_ON`` with the step cut to end at t_max where needed,
    or the status that ends the point (``T_MAX``, ``STEP_LIMIT``, or ``STIFF`` for an
    exhausted step budget). Scalars only: the same checks taking the lane arrays,
    even inlined, had numba reference-count ~15 arrays per lane and step (atomic
    increments and decrements, measured at ~40 % of the lanes' time).
    """
    if not t < t_max:
        return _T_MAX, h
    if n_steps >= max_steps:
        return _STEP_LIMIT, h
    if n_steps + n_rejected > steps_per_s * (t - t0) + STEP_ALLOWANCE:
        return _STIFF, h
    if t + 1.01 * h >= t_max:
        h = t_max - t
    return _GO_ON, h


@njit(cache=True)
def _finish(j, status, t_event, Y, T, IDX, CNT, out) -> bool:
    """Write the outcome of lane j to its point's slots; False (the lane is free)."""
    st, tev, tend, yend, nfev, steps, rej = out[:7]
    q = IDX[j]
    st[q] = status
    tev[q] = t_event
    tend[q] = T[j]
    for i in range(N_STATE):
        yend[q, i] = Y[i * LANES + j]
    nfev[q] = CNT[0, j]
    steps[q] = CNT[1, j]
    rej[q] = CNT[2, j]
    return False


@njit(cache=True)
def _move_lane(a, b, lanes) -> None:
    """Copy every per-lane quantity of lane a into lane b."""
    Y, K, PL, SC, T, T0, H, TMAX, HMAX, MAXST, SPT, GOLD, COS_CR, IDX, CNT, REJ, LIVE = lanes
    for i in range(N_STATE):
        Y[i * LANES + b] = Y[i * LANES + a]
        SC[i * LANES + b] = SC[i * LANES + a]
        for s in range(12):
            K[s * _KS + i * LANES + b] = K[s * _KS + i * LANES + a]
    for i in range(PL.shape[0] // LANES):
        PL[i * LANES + b] = PL[i * LANES + a]
    T[b] = T[a]
    T0[b] = T0[a]
    H[b] = H[a]
    TMAX[b] = TMAX[a]
    HMAX[b] = HMAX[a]
    MAXST[b] = MAXST[a]
    SPT[b] = SPT[a]
    GOLD[b] = GOLD[a]
    COS_CR[b] = COS_CR[a]
    IDX[b] = IDX[a]
    CNT[:, b] = CNT[:, a]
    REJ[b] = REJ[a]
    LIVE[b] = LIVE[a]
    LIVE[a] = False
