"""Batched DOP853: many trajectories advanced together in lanes (structure of arrays).

:func:`integrate_lanes` runs the method of :mod:`obturator.core.integrators.dop853` on
a whole set of points at once. ``n_lanes`` trajectories are held side by side,
component by component (state ``y[i * LANES + lane]``, stages
``k[(s * N_STATE + i) * LANES + lane]``), so each stage's right-hand side is one loop
over lanes that the compiler vectorises (SIMD); every lane keeps its own time, step
size, error control, stiffness test, opening event and termination. A lane whose
trajectory ends (opened, t_max, step limit, failure, or stiff) is refilled at once with
the next point of the queue, so no lane waits for the slowest one; when the queue is
empty the live lanes are packed to the front, so the per-lane bookkeeping shortens.
Points enter in the order given (callers put the costliest first, so the tail is short).

Same answers as the one-trajectory path: per lane the arithmetic is that of
:func:`obturator.core.integrators.dop853.integrate` (same stages, error norm, step-size
control, stiffness test, event location by re-stepping), and the right-hand side of
the thesis's kernel (:mod:`obturator.core.specialised`) is the same compiled function
in both; ``tests/core/test_lanes.py`` compares every point of sweeps with the scalar path.
Lanes that turn stiff end with status ``STIFF`` and their last accepted state, for the
caller to hand to Radau IIA exactly as ``auto`` does
(:func:`obturator.core.integrators.integrate`). Points with the generic kernel run here
too, calling the scalar right-hand side lane by lane.

The lanes' state is two named tuples of arrays, :class:`Lanes` (what a lane carries
from step to step) and :class:`Attempt` (one trial step's workspace); after the arrays
are allocated the whole loop runs in one function compiled without reference counting
(:func:`_run`), its phases inlined into it.

Only the opening time is returned (no recorded steps, no t_eval): this is the path of
sweeps, Monte Carlo and fits.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit, uint64

from ...dynamics import nutation_angle_of_state, rhs
from ...layout import KERNEL_GENERIC, N_STATE, P_KERNEL, P_THETA_CR
from ..common import crossed, underflow
from ..contract import Status
from ..dop853 import TOL_FACTOR, locate_event, step_factor, stiffness_product
from ..stick_slip_modes import slip
from ..switching import STEPS_PER_PERIOD, STIFF_SIGNAL, over_step_budget, stiffness_count
from .dop853_sums import error_sums, stage_sum
from .points import Outcome, Points, copy_lane, finish, new_outcome, pack_lanes
from .rates import cos_nutation_lanes, rhs_generic_lanes, rhs_thesis_lanes
from .simd import DRIVER_PHASE, LANE_KERNEL, LANES, NO_REFCOUNT, REFCOUNT

__all__ = ["integrate_lanes", "LANES", "DEFAULT_LANES"]

DEFAULT_LANES = LANES

_N = N_STATE
_KS = N_STATE * LANES  # stride of one stage in k


class Lanes(NamedTuple):
    """What each lane carries from step to step (:func:`_move_lane` copies all of it)."""

    y: np.ndarray  #: state (N_STATE * LANES)
    k: np.ndarray  #: stages (12 * N_STATE * LANES); k_0 = f(y)
    p: np.ndarray  #: parameters (N_PARAM * LANES)
    scale: np.ndarray  #: error-weight scales (N_STATE * LANES)
    t: np.ndarray  #: time [s]
    t0: np.ndarray  #: start time [s] (the step budget counts from it)
    h: np.ndarray  #: next step [s]
    t_max: np.ndarray  #: end time [s]
    h_max: np.ndarray  #: largest step [s]
    slip_floor: np.ndarray  #: |omega_r| below which the point ends [rad/s] (0: none)
    steps_per_s: np.ndarray  #: step budget per second of simulated time
    g_old: np.ndarray  #: theta - theta_cr at the step start (inf: not computed)
    cos_cr: np.ndarray  #: cos(theta_cr)
    max_steps: np.ndarray  #: int: accepted-step limit
    idx: np.ndarray  #: int: the point in the lane
    cnt: np.ndarray  #: int (5, LANES): nfev, steps, rejected, stiff run, calm run
    rejected: np.ndarray  #: bool: the last attempt was rejected
    live: np.ndarray  #: bool: the lane holds a point


class Attempt(NamedTuple):
    """One trial step of every lane, and one lane's copies for the scalar routines."""

    ynew: np.ndarray  #: the 8th-order solution (N_STATE * LANES)
    work: np.ndarray  #: stage argument, then y_12 (N_STATE * LANES)
    f1: np.ndarray  #: f(ynew) (N_STATE * LANES)
    err: np.ndarray  #: error estimate
    s5: np.ndarray  #: error sums, then stiffness numerator
    s3: np.ndarray  #: error sums, then stiffness denominator
    cos_n: np.ndarray  #: cos(theta) at the step ends (quaternion form)
    fac: np.ndarray  #: step factor 0.9 err^(-1/8)
    hl: np.ndarray  #: stiffness estimate h |lambda|
    ys: np.ndarray  #: one lane's state
    yn: np.ndarray  #: one lane's new state
    ps: np.ndarray  #: one lane's parameters
    ks: np.ndarray  #: (12, N_STATE) one lane's stages (event location)
    y_event: np.ndarray  #: event state
    scratch: tuple  #: (work, trial state, derivative) of the scalar routines


@njit(cache=True, fastmath=False, error_model="numpy", **REFCOUNT)
def _new_lanes(n_par: int) -> Lanes:
    f = np.zeros(LANES)
    i = np.zeros(LANES, dtype=np.int64)
    b = np.zeros(LANES, dtype=np.bool_)
    return Lanes(
        y=np.zeros(_N * LANES),
        k=np.zeros(12 * _KS),
        p=np.zeros(n_par * LANES),
        scale=np.ones(_N * LANES),
        t=f.copy(),
        t0=f.copy(),
        h=f.copy(),
        t_max=f.copy(),
        h_max=f.copy(),
        slip_floor=f.copy(),
        steps_per_s=f.copy(),
        g_old=f.copy(),
        cos_cr=f.copy(),
        max_steps=i.copy(),
        idx=i.copy(),
        cnt=np.zeros((5, LANES), dtype=np.int64),
        rejected=b.copy(),
        live=b.copy(),
    )


@njit(cache=True, fastmath=False, error_model="numpy", **REFCOUNT)
def _new_attempt(n_par: int) -> Attempt:
    v = np.zeros(_N * LANES)
    f = np.zeros(LANES)
    s = np.zeros(_N)
    return Attempt(
        ynew=v.copy(),
        work=v.copy(),
        f1=v.copy(),
        err=f.copy(),
        s5=f.copy(),
        s3=f.copy(),
        cos_n=f.copy(),
        fac=f.copy(),
        hl=f.copy(),
        ys=s.copy(),
        yn=s.copy(),
        ps=np.zeros(n_par),
        ks=np.zeros((12, _N)),
        y_event=s.copy(),
        scratch=(s.copy(), s.copy(), s.copy()),
    )


@njit(cache=True, nogil=True, fastmath=False, error_model="numpy", **REFCOUNT)
def integrate_lanes(
    y0, t0, p, scale, t_max, h0, h_max, max_steps, order, rtol, atol, event_tol, n_lanes,
    slip_floor,
):  # fmt: skip
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
        Error-weight scales (as in :class:`obturator.core.integrators.contract.Problem`).
    t_max, h0, h_max : ndarray, shape (n,)
        End time, initial step and largest step of each point [s].
    max_steps : ndarray of int, shape (n,)
        Accepted-step limit per point.
    order : ndarray of int, shape (n,)
        The order in which points enter the lanes (a permutation of 0..n-1).
    rtol, atol : float
        Tolerances (transformed as in :mod:`obturator.core.integrators.dop853`).
    event_tol : float
        Bracket width of the event time [s].
    n_lanes : int
        Lanes advanced together, 1 to :data:`LANES`.
    slip_floor : ndarray, shape (n,)
        Slip speed [rad/s] below which a point ends with ``STIFF`` after an accepted
        step (0: never): for the set-valued solver's last slips at zero width, whose
        direction is singular at zero slip (:mod:`..stick_slip_lanes`).

    Returns
    -------
    tuple
        (status int8 (n,), t_event (n,), t_end (n,), y_end (n, 8), nfev (n,),
        n_steps (n,), n_rejected (n,)); statuses as
        :func:`obturator.core.integrators.dop853.integrate` (``STIFF`` with the last
        accepted state in y_end / t_end).
    """
    n_pts = y0.shape[0]
    no_hand_back = np.zeros(n_pts, dtype=np.bool_)
    pts = Points(y0, t0, p, scale, t_max, h0, h_max, max_steps, no_hand_back, slip_floor, order)
    out = new_outcome(n_pts)
    quaternion = n_pts > 0 and p[0, P_KERNEL] != KERNEL_GENERIC  # the thesis kernel's form
    nl = max(1, min(n_lanes, LANES, n_pts))
    tol_f = max(TOL_FACTOR, 1e-14 / rtol)
    ln = _new_lanes(p.shape[1])
    at = _new_attempt(p.shape[1])
    _run(pts, ln, at, out, nl, quaternion, tol_f * rtol, tol_f * atol, event_tol)
    cnt = out.counts
    return out.status, out.t_event, out.t_end, out.y_end, cnt[0], cnt[1], cnt[2]


@njit(cache=True, fastmath=False, error_model="numpy", **NO_REFCOUNT)
def _run(
    pts: Points, ln: Lanes, at: Attempt, out: Outcome, nl, quaternion, rtol, atol, event_tol
) -> None:
    """The loop of :func:`integrate_lanes`: refill, pack, one trial step in every lane,
    then each lane's decision, until every point has ended."""
    n_pts = pts.y0.shape[0]
    nxt = 0  # next entry of `order` to load
    while True:
        for j in range(nl):  # (re)fill free lanes; a point may end before its first step
            while not ln.live[j] and nxt < n_pts:
                ln.live[j] = _load(pts, ln, at, out, j, pts.order[nxt])
                nxt += 1
        if nxt >= n_pts:  # the queue is empty: pack the live lanes to the front
            nl = pack_lanes(ln, nl, _move_lane)
            if nl == 0:
                break
        _attempt(ln, at, nl, quaternion, rtol, atol)
        for j in range(nl):
            if _settle(ln, at, out, j, quaternion, event_tol):
                ln.live[j] = _next_step(ln, out, j)


@njit(**DRIVER_PHASE)
def _load(pts: Points, ln: Lanes, at: Attempt, out: Outcome, j, q) -> bool:
    """Load point q into lane j, as :func:`~obturator.core.integrators.dop853.integrate`
    starts a run; whether it goes on (False: it ended before its first step)."""
    ys, ps, fs = at.ys, at.ps, at.scratch[2]
    ln.idx[j] = q
    w0 = 0.0
    for i in range(ps.shape[0]):
        ln.p[i * LANES + j] = pts.p[q, i]
        ps[i] = pts.p[q, i]
    for i in range(_N):
        ln.y[i * LANES + j] = pts.y0[q, i]
        ln.scale[i * LANES + j] = pts.scale[q, i]
        w0 = max(w0, pts.scale[q, i])
        ys[i] = pts.y0[q, i]
    rhs(0.0, ys, ps, fs)
    for i in range(_N):
        ln.k[i * LANES + j] = fs[i]
    t0, t_max, h_max = pts.t0[q], pts.t_max[q], pts.h_max[q]
    ln.t[j] = t0
    ln.t0[j] = t0
    ln.t_max[j] = t_max
    ln.h_max[j] = h_max
    ln.slip_floor[j] = pts.slip_floor[q]
    ln.max_steps[j] = pts.max_steps[q]
    ln.steps_per_s[j] = STEPS_PER_PERIOD * w0 / (2.0 * math.pi)
    ln.h[j] = min(pts.h0[q], h_max, t_max - t0)
    ln.g_old[j] = nutation_angle_of_state(ys, ps) - ps[P_THETA_CR]
    ln.cos_cr[j] = math.cos(ps[P_THETA_CR])
    for c in range(5):
        ln.cnt[c, j] = 0
    ln.cnt[0, j] = 1
    ln.rejected[j] = False
    return _next_step(ln, out, j)


@njit(**DRIVER_PHASE)
def _move_lane(ln: Lanes, a, b) -> None:
    """Copy every per-lane quantity of lane a into lane b; lane a is then free."""
    for x in (ln.y, ln.k, ln.p, ln.scale):  # vectors
        copy_lane(x, a, b)
    for x in (ln.t, ln.t0, ln.h, ln.t_max, ln.h_max, ln.slip_floor):
        copy_lane(x, a, b)
    for x in (ln.steps_per_s, ln.g_old, ln.cos_cr):
        copy_lane(x, a, b)
    copy_lane(ln.max_steps, a, b)
    copy_lane(ln.idx, a, b)
    copy_lane(ln.rejected, a, b)
    copy_lane(ln.live, a, b)
    for c in range(5):
        ln.cnt[c, b] = ln.cnt[c, a]
    ln.live[a] = False


@njit(**DRIVER_PHASE)
def _attempt(ln: Lanes, at: Attempt, nl, quaternion, rtol, atol) -> None:
    """One trial step of every lane: stages, f(y_new), error estimate, step factor and
    stiffness estimate (and cos(theta) at the step ends in quaternion form)."""
    if quaternion:
        _stages_thesis_lanes(ln.y, ln.h, ln.p, ln.k, at.ynew, at.work)
        rhs_thesis_lanes(at.ynew, ln.p, at.f1, 0)
        cos_nutation_lanes(at.ynew, at.cos_n)
    else:
        one = (at.ys, at.scratch[2], at.ps)
        _stages_generic_lanes(ln.y, ln.h, ln.p, ln.k, at.ynew, at.work, nl, one)
        rhs_generic_lanes(at.ynew, ln.p, at.f1, 0, nl, one)
    _error_lanes(ln.k, ln.h, ln.y, at.ynew, rtol, atol, ln.scale, at.err, at.s5, at.s3)
    _control_lanes(at.err, at.fac, at.hl, ln.h, at.f1, ln.k, at.ynew, at.work, at.s5, at.s3)


@njit(**DRIVER_PHASE)
def _settle(ln: Lanes, at: Attempt, out: Outcome, j, quaternion, event_tol) -> bool:
    """Lane j's decision on its trial step, as :func:`~obturator.core.integrators.dop853
    .integrate` takes it: reject (shorter step), accept (stiffness test, opening test,
    next step size) or end the point. Returns whether its point goes on."""
    ln.cnt[0, j] += 11
    if at.err[j] > 1.0:
        ln.cnt[2, j] += 1
        ln.rejected[j] = True
        ln.h[j] *= max(0.2, at.fac[j])
        if underflow(ln.h[j], ln.t[j]):
            ln.live[j] = _end(ln, out, j, STIFF_SIGNAL)
            return False
        return True
    ln.cnt[0, j] += 1
    h = ln.h[j]
    t_new = ln.t[j] + h
    # Hairer's stiffness test, as in dop853.integrate (switching.stiffness_count)
    n_stiff, n_calm, stiff = stiffness_count(at.hl[j], ln.cnt[3, j], ln.cnt[4, j])
    ln.cnt[3, j] = n_stiff
    ln.cnt[4, j] = n_calm
    if stiff:
        ln.live[j] = _end(ln, out, j, STIFF_SIGNAL)
        return False
    g_new = _g_new(ln, at, j, quaternion)
    if crossed(ln.g_old[j], g_new, math.nan):  # g_new <= 0: at.yn, at.ps filled
        ln.live[j] = _opening(ln, at, out, j, g_new, event_tol)
        return False
    ln.g_old[j] = g_new
    ln.t[j] = t_new
    for i in range(_N):
        ln.y[i * LANES + j] = at.ynew[i * LANES + j]
        ln.k[i * LANES + j] = at.f1[i * LANES + j]
    ln.cnt[1, j] += 1
    if not (ln.y[j] == ln.y[j]) or (
        ln.slip_floor[j] > 0.0 and _slip_speed(ln, at, j) < ln.slip_floor[j]
    ):
        ln.live[j] = _end(ln, out, j, STIFF_SIGNAL)
        return False
    fac = min(10.0, max(0.2, at.fac[j]))
    if ln.rejected[j]:
        fac = min(fac, 1.0)
    ln.rejected[j] = False
    ln.h[j] = min(h * fac, ln.h_max[j])
    return True


@njit(**DRIVER_PHASE)
def _slip_speed(ln: Lanes, at: Attempt, j) -> float:
    """|omega_r| of lane j's state [rad/s]."""
    for i in range(_N):
        at.ys[i] = ln.y[i * LANES + j]
    return slip(at.ys)[3]


@njit(**DRIVER_PHASE)
def _g_new(ln: Lanes, at: Attempt, j, quaternion) -> float:
    """theta - theta_cr at lane j's step end, or +inf where cos(theta_new) is well below
    cos(theta_cr) (theta well above theta_cr: the sign is all the test needs); the exact
    g (atan2) of dop853.integrate only near the opening, with at.yn, at.ps filled."""
    if quaternion and at.cos_n[j] < ln.cos_cr[j] - 1e-9:
        return math.inf
    for i in range(_N):
        at.yn[i] = at.ynew[i * LANES + j]
    for i in range(at.ps.shape[0]):
        at.ps[i] = ln.p[i * LANES + j]
    return nutation_angle_of_state(at.yn, at.ps) - at.ps[P_THETA_CR]


@njit(**DRIVER_PHASE)
def _opening(ln: Lanes, at: Attempt, out: Outcome, j, g_new, event_tol) -> bool:
    """Locate the opening inside lane j's accepted step
    (:func:`~obturator.core.integrators.dop853.locate_event`) and end its point there."""
    ys, ps, ks = at.ys, at.ps, at.ks
    for i in range(_N):
        ys[i] = ln.y[i * LANES + j]
        ks[0, i] = ln.k[i * LANES + j]
        at.y_event[i] = at.yn[i]
    if ln.g_old[j] == math.inf:  # the exact g at the step start
        ln.g_old[j] = nutation_angle_of_state(ys, ps) - ps[P_THETA_CR]
    work, ytry, _ = at.scratch
    t, h, g_old = ln.t[j], ln.h[j], ln.g_old[j]
    t_ev, nf = locate_event(t, ys, h, ps, ks, work, ytry, at.y_event, g_old, g_new, event_tol)
    ln.cnt[0, j] += nf
    for i in range(_N):
        ln.y[i * LANES + j] = at.y_event[i]
    ln.t[j] = t_ev
    return finish(out, j, Status.OPENED, t_ev, ln.y, ln.t, ln.idx, ln.cnt)


@njit(**DRIVER_PHASE)
def _end(ln: Lanes, out: Outcome, j, status) -> bool:
    """End lane j's point with `status` at its last accepted state; False."""
    return finish(out, j, status, math.nan, ln.y, ln.t, ln.idx, ln.cnt)


@njit(**DRIVER_PHASE)
def _next_step(ln: Lanes, out: Outcome, j) -> bool:
    """The checks at the top of dop853.integrate's loop for lane j (:func:`_top_of_step`);
    whether its point goes on (else it has ended)."""
    steps, rejected = ln.cnt[1, j], ln.cnt[2, j]
    code, ln.h[j] = _top_of_step(
        ln.t[j], ln.t0[j], ln.h[j], ln.t_max[j], ln.steps_per_s[j], steps, rejected, ln.max_steps[j]
    )
    return code == _GO_ON or _end(ln, out, j, code)


@njit(**LANE_KERNEL)
def _stages_thesis_lanes(y, h, p, k, ynew, work) -> None:
    """Stages k[1..11] and the 8th-order solution of every lane (k[0] given), thesis kernel."""
    for s in range(1, 12):
        stage_sum(s, y, h, k, work)
        rhs_thesis_lanes(work, p, k, s * _KS)
    stage_sum(12, y, h, k, ynew)


@njit(cache=True, fastmath=False, error_model="numpy", **NO_REFCOUNT)
def _stages_generic_lanes(y, h, p, k, ynew, work, nl, one) -> None:
    """:func:`_stages_thesis_lanes` with the generic right-hand side in lanes 0..nl-1."""
    for s in range(1, 12):
        stage_sum(s, y, h, k, work)
        rhs_generic_lanes(work, p, k, s * _KS, nl, one)
    stage_sum(12, y, h, k, ynew)


@njit(**LANE_KERNEL)
def _error_lanes(k, h, y, ynew, rtol, atol, scale, err, s5, s3) -> None:
    """DOP853's combined error estimate of every lane (as dop853._error_norm)."""
    error_sums(k, y, ynew, rtol, atol, scale, s5, s3)
    for j in range(LANES):
        if s5[j] == 0.0 and s3[j] == 0.0:
            err[j] = 0.0
        else:
            err[j] = abs(h[j]) * s5[j] / math.sqrt((s5[j] + 0.01 * s3[j]) * N_STATE)


# no contract: as dop853.integrate, whose step control this mirrors
@njit(cache=True, fastmath=False, error_model="numpy", **NO_REFCOUNT)
def _control_lanes(err, fac, hl, h, f1, k, ynew, work, num, den) -> None:
    """Step-size factor and stiffness estimate of every lane, in vector loops.

    As :func:`obturator.core.integrators.dop853.integrate` computes them (compiled,
    like it, without FMA contraction; same operations in the same order): a NaN error
    counts as 1e10, ``fac = step_factor(err)``, ``hl = stiffness_product(h, num,
    den)`` with num = |f(y_new) - k_12|^2 and den = |y_new - y_12|^2. num and den
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


#: Going on: what :func:`_top_of_step` returns when the lane's point goes on; the
#: codes that end it, as plain ints (numba has no ``int(IntEnum)``).
_GO_ON = -100
_T_MAX, _STEP_LIMIT, _STIFF = int(Status.T_MAX), int(Status.STEP_LIMIT), STIFF_SIGNAL


@njit(cache=True, fastmath=False, error_model="numpy", **NO_REFCOUNT)
def _top_of_step(t, t0, h, t_max, steps_per_s, n_steps, n_rejected, max_steps):
    """The checks at the top of dop853.integrate's loop for one lane (started at t0).

    Returns (code, h): ``_GO_ON`` with the step cut to end at t_max where needed,
    or the status that ends the point (``T_MAX``, ``STEP_LIMIT``, or ``STIFF`` for an
    exhausted step budget). Scalars only.
    """
    if not t < t_max:
        return _T_MAX, h
    if n_steps >= max_steps:
        return _STEP_LIMIT, h
    if over_step_budget(n_steps + n_rejected, steps_per_s, t, t0):
        return _STIFF, h
    if t + 1.01 * h >= t_max:
        h = t_max - t
    return _GO_ON, h
