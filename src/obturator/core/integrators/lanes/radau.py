"""Batched Radau IIA: the stiff points of a sweep advanced together in lanes.

:func:`integrate_radau_lanes` runs the method of :mod:`obturator.core.integrators.radau`
(same Newton iteration, error estimate, step-size and Jacobian-reuse rules, same event
location) on many points at once, in the structure-of-arrays layout of the lanes
(``x[i * LANES + lane]``; matrices ``a[(i * N + j) * LANES + lane]``). It takes the
lanes that DOP853 found stiff (near-stick rig points) from their last accepted state,
as ``auto`` hands one trajectory to Radau.

Every attempted step runs in lock step over all lanes, in phases that are one
vectorised loop each (:mod:`.radau_steps`):

1. the forward-difference Jacobian, for the lanes whose Jacobian is stale
   (computed for all, stored only for those);
2. the real and the complex LU of every lane (:mod:`.lu`, :mod:`.solves`), every
   attempt: with an unchanged h and J the factors are the same numbers the
   scalar code keeps, and refactoring all lanes costs less than selecting;
3. the simplified Newton iterations: each iteration evaluates the three
   stages and solves both systems for all lanes; a lane that has converged or
   failed keeps its iterate while the others go on;
4. the embedded error estimate (and its filtered second estimate where the
   scalar code takes it).

The per-lane decisions (convergence, acceptance, step size, Jacobian reuse,
the event test) are the scalar code's, lane by lane. The opening is located
with :func:`obturator.core.integrators.radau.locate_opening_at` on the lane's data, as in
the scalar code.

The state is named tuples of arrays (:mod:`.radau_state`): what a lane carries from
step to step, one attempted step's workspace and one lane's copies for the scalar event
location; after they are allocated the loop runs
in one function compiled without reference counting (:func:`_run`), its phases
inlined into it.

Every kernel runs here, the thesis kernel in one vector loop over the lanes and the
generic right-hand side (every torque model and friction family, either formulation)
lane by lane; :func:`.rates.rates_lanes` makes that choice, from the rows'
``P_KERNEL``, in one place. The results are those of the scalar Radau IIA to rounding
(the vectorised LU may round differently); ``tests/core/test_radau_lanes.py`` checks the
opening times against it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ...dynamics import nutation_angle_of_state, slip_and_spin
from ...layout import (
    FORM_QUATERNION,
    KERNEL_GENERIC,
    N_STATE,
    P_FORM,
    P_KERNEL,
    P_THETA_CR,
    P_WIDTH,
)
from ..common import increment_cap, underflow
from ..contract import Status
from ..radau import locate_opening_at
from ..radau_control import (
    _LIM_SHRINK,
    _NIT,
    _THET,
    _UROUND,
    ERR_GUS_MIN,
    FACCON_POWER,
    FIRST_CUT,
    NEWTON_CUT,
    newton_contraction,
    next_step,
    radau5_tolerances,
    step_quotient,
)
from ..switching import NONSTIFF_SIGNAL, sliding_resumed
from .lu import lu_factor_complex_lanes, lu_factor_lanes
from .points import Outcome, Points, copy_lane, finish, lane_vector, new_outcome, pack_lanes
from .radau_state import (
    Attempt,
    Lanes,
    OneLane,
    Settings,
    new_attempt,
    new_lanes,
    new_one_lane,
)
from .radau_steps import (
    build_lanes,
    error_lanes,
    error_rhs_lanes,
    f0_masked,
    guess_lanes,
    jacobian_lanes,
    node_states,
    residual_lanes,
    stages_rhs,
    to_w,
    update_lanes,
    wnorm_lanes,
)
from .rates import cos_nutation_any_lanes, rates_lanes
from .simd import DRIVER_PHASE, LANES, NO_REFCOUNT, REFCOUNT
from .solves import lu_solve_lanes, lu_solve_pair_lanes

__all__ = ["integrate_radau_lanes"]

_N = N_STATE
_V = N_STATE * LANES  # one vector of every lane
_M = N_STATE * N_STATE * LANES  # one matrix of every lane
# Newton outcome of a lane in the current attempt
_RUNNING, _CONVERGED, _FAILED, _IDLE = 0, 1, 2, 3


@njit(cache=True, nogil=True, fastmath=False, error_model="numpy", **REFCOUNT)
def integrate_radau_lanes(
    y0,
    t0,
    p,
    scale,
    t_max,
    h0,
    h_max,
    max_steps,
    hand_back,
    order,
    rtol,
    atol,
    event_tol,
    n_lanes,
    vw,
):
    """Radau IIA from (t0, y0) of many points until theta = theta_cr or t_max, in lanes.

    Parameters
    ----------
    y0 : ndarray, shape (n, 8)
        Start states (DOP853's last accepted states).
    t0 : ndarray, shape (n,)
        Start times [s].
    p : ndarray, shape (n, N_PARAM)
        Packed parameters; every row must have the same ``P_KERNEL``.
    scale : ndarray, shape (n, 8)
        Error-weight scales.
    t_max, h0, h_max : ndarray, shape (n,)
        End time, initial step and largest step [s].
    max_steps : ndarray of int, shape (n,)
        Accepted-step limit per point.
    hand_back : ndarray of bool, shape (n,)
        Stop a point with ``NONSTIFF`` once sliding has resumed (as ``Controls.hand_back``
        in :func:`obturator.core.integrators.radau.integrate`).
    order : ndarray of int, shape (n,)
        The order in which points enter the lanes.
    rtol, atol : float
        Tolerances (transformed as in :mod:`obturator.core.integrators.radau`).
    event_tol : float
        Bracket width of the event time [s].
    n_lanes : int
        Lanes advanced together, 1 to :data:`LANES`.
    vw : int
        :data:`LANES`, passed at run time: the trip count of the vector loops (see
        :mod:`.lu`: with the constant LLVM unrolls them into scalar code).

    Returns
    -------
    tuple
        (status int8 (n,), t_event (n,), t_end (n,), y_end (n, 8), nfev (n,), n_steps (n,),
        n_rejected (n,)), statuses as :func:`obturator.core.integrators.radau.integrate`
        (``NONSTIFF`` with the state where sliding had resumed in y_end / t_end).
    """
    if vw != LANES:
        raise ValueError("vw must be LANES")
    n_pts = y0.shape[0]
    n_par = p.shape[1]
    no_floor = np.zeros(y0.shape[0])
    pts = Points(y0, t0, p, scale, t_max, h0, h_max, max_steps, hand_back, no_floor, order)
    out = new_outcome(n_pts)
    rtol, atol, fnewt = radau5_tolerances(rtol, atol)  # as radau.integrate
    generic = n_pts > 0 and p[0, P_KERNEL] == KERNEL_GENERIC
    tol = Settings(rtol, atol, fnewt, event_tol, vw, generic)
    nl = max(1, min(n_lanes, LANES, n_pts))
    _run(pts, new_lanes(n_par), new_attempt(), new_one_lane(n_par), out, nl, tol)
    cnt = out.counts
    return out.status, out.t_event, out.t_end, out.y_end, cnt[0], cnt[1], cnt[2]


@njit(cache=True, fastmath=False, error_model="numpy", **NO_REFCOUNT)
def _run(pts: Points, ln: Lanes, at: Attempt, one: OneLane, out: Outcome, nl, tol) -> None:
    """The loop of :func:`integrate_radau_lanes`: refill and pack the lanes, then one
    attempted step of every lane in the phases of the module docstring, then each lane's
    decision, until every point has ended."""
    n_pts = pts.y0.shape[0]
    nxt = 0
    while True:
        nxt = _refill(pts, ln, one, out, nl, nxt)
        if nxt >= n_pts:
            nl = pack_lanes(ln, nl, _move_lane)
            if nl == 0:
                break
        kernel = (tol.generic, nl, one.rates)
        _prepare(ln, at, nl, kernel, tol.vw)
        _factor(ln, at, out, nl, tol.vw)
        _newton(ln, at, nl, kernel, tol)
        _newton_failures(ln, at, out, nl)
        _estimate(ln, at, nl, kernel, tol)
        for j in range(nl):
            at.acc[j] = _decide(ln, at, one, out, j, tol)
        for j in range(nl, LANES):
            at.acc[j] = False
        f0_masked(ln.y, ln.p, ln.f0, at.fw, at.acc, ln.cnt, kernel, tol.vw)


@njit(**DRIVER_PHASE)
def _refill(pts: Points, ln: Lanes, one: OneLane, out: Outcome, nl, nxt):
    """Load points into free lanes, then the checks at the top of the scalar loop (t_max,
    step limit) in every lane; returns the next entry of ``pts.order`` to load."""
    n_pts = pts.y0.shape[0]
    for j in range(nl):
        while True:
            if not ln.live[j]:
                if nxt >= n_pts:
                    break
                _load(pts, ln, one, j, pts.order[nxt])
                ln.live[j] = True
                nxt += 1
            if not ln.t[j] < ln.t_max[j]:
                ln.live[j] = _end(ln, out, j, Status.T_MAX)
            elif ln.cnt[1, j] >= ln.max_steps[j]:
                ln.live[j] = _end(ln, out, j, Status.STEP_LIMIT)
            else:
                break
    return nxt


@njit(**DRIVER_PHASE)
def _load(pts: Points, ln: Lanes, one: OneLane, j, q) -> None:
    """Load point q into lane j, as :func:`obturator.core.integrators.radau.integrate`
    starts a run."""
    ys, ps = one.y, one.p
    ln.idx[j] = q
    for i in range(ps.shape[0]):
        ln.p[i * LANES + j] = pts.p[q, i]
        ps[i] = pts.p[q, i]
    theta_cr = ps[P_THETA_CR]
    w_ref = 1.0
    for i in range(_N):
        w_ref = max(w_ref, pts.scale[q, i])
    for i in range(_N):
        ln.y[i * LANES + j] = pts.y0[q, i]
        ln.scale[i * LANES + j] = pts.scale[q, i]
        ys[i] = pts.y0[q, i]
        quaternion = ps[P_FORM] == FORM_QUATERNION
        ln.cap[i * LANES + j] = increment_cap(pts.scale[q, i], ps[P_WIDTH], w_ref, quaternion)
    t0 = pts.t0[q]
    ln.t[j] = t0
    ln.t_max[j] = pts.t_max[q]
    ln.h_max[j] = pts.h_max[q]
    ln.max_steps[j] = pts.max_steps[q]
    ln.h[j] = min(pts.h0[q], pts.h_max[q], pts.t_max[q] - t0)
    ln.h_acc[j] = 1.0
    ln.g_old[j] = nutation_angle_of_state(ys, ps) - theta_cr
    ln.t_stick[j] = t0
    ln.hand_back[j] = pts.hand_back[q]
    ln.cos_cr[j] = math.cos(theta_cr)
    for c in range(3):
        ln.cnt[c, j] = 0
    ln.new_jac[j] = True
    ln.fresh[j] = False
    ln.poly[j] = False
    ln.first[j] = True
    ln.rejected[j] = False
    ln.faccon[j] = 1.0
    ln.h_gus[j] = 0.0
    ln.err_gus[j] = 1.0
    ln.h_lim[j] = math.inf


@njit(**DRIVER_PHASE)
def _move_lane(ln: Lanes, a, b) -> None:
    """Copy everything lane a carries from step to step into lane b; lane a is then free."""
    for x in (ln.p, ln.y, ln.f0, ln.scale, ln.cap, ln.z_acc, ln.jac):  # vectors, matrices
        copy_lane(x, a, b)
    for x in (ln.t, ln.h, ln.h_acc, ln.t_max, ln.h_max, ln.h_lim, ln.h_gus, ln.err_gus):
        copy_lane(x, a, b)
    for x in (ln.faccon, ln.g_old, ln.t_stick, ln.cos_cr):
        copy_lane(x, a, b)
    copy_lane(ln.max_steps, a, b)
    copy_lane(ln.idx, a, b)
    for x in (ln.new_jac, ln.fresh, ln.poly, ln.first, ln.hand_back, ln.rejected, ln.live):
        copy_lane(x, a, b)
    for c in range(3):
        ln.cnt[c, b] = ln.cnt[c, a]
    ln.live[a] = False


@njit(**DRIVER_PHASE)
def _prepare(ln: Lanes, at: Attempt, nl, kernel, vw) -> None:
    """Before an attempt: harmless numbers in the idle lanes, f(y) of the lanes just
    filled, the Jacobian where stale (phase 1), the step cut to end at t_max."""
    for j in range(nl, LANES):
        ln.h[j] = 1.0
        ln.h_acc[j] = 1.0
        ln.new_jac[j] = False
    # f(y) of lanes just filled (after a step it is computed with the accepted state)
    for j in range(nl):
        at.acc[j] = ln.first[j] and ln.cnt[0, j] == 0
    f0_masked(ln.y, ln.p, ln.f0, at.fw, at.acc, ln.cnt, kernel, vw)
    any_jac = False
    for j in range(nl):
        any_jac = any_jac or ln.new_jac[j]
    if any_jac:
        y, f0, new_jac = ln.y, ln.f0, ln.new_jac
        work, fw, cap = at.work, at.fw, ln.cap
        jacobian_lanes(y, f0, ln.p, ln.scale, ln.jac, new_jac, work, fw, cap, at.vmax, kernel, vw)
        for j in range(nl):
            if ln.new_jac[j]:
                ln.cnt[0, j] += _N
                ln.new_jac[j] = False
                ln.fresh[j] = True
    for j in range(nl):
        if ln.t[j] + 1.01 * ln.h[j] >= ln.t_max[j]:
            ln.h[j] = ln.t_max[j] - ln.t[j]


@njit(**DRIVER_PHASE)
def _factor(ln: Lanes, at: Attempt, out: Outcome, nl, vw) -> None:
    """Phase 2: the real and complex LU of every lane; a singular lane halves its step
    (and fails where the step underflows) and sits out the attempt."""
    build_lanes(ln.jac, ln.h, at.lu_r, at.lu_cr, at.lu_ci, vw)
    for j in range(vw):
        at.ok[j] = True
    lu_factor_lanes(at.lu_r, at.piv_r, at.swap_r, at.ok, at.vmax, vw)
    lu_factor_complex_lanes(at.lu_cr, at.lu_ci, at.piv_c, at.swap_c, at.ok, at.vmax, vw)
    for j in range(nl):
        at.state[j] = _RUNNING
        if not at.ok[j]:
            ln.cnt[2, j] += 1
            ln.h[j] *= NEWTON_CUT
            at.state[j] = _IDLE
            if underflow(ln.h[j], ln.t[j]):
                ln.live[j] = _end(ln, out, j, Status.FAILED)
    for j in range(nl, LANES):
        at.state[j] = _IDLE


@njit(**DRIVER_PHASE)
def _newton(ln: Lanes, at: Attempt, nl, kernel, tol: Settings) -> None:
    """Phase 3: the simplified Newton iterations of every running lane, from the
    extrapolated collocation polynomial, until each has converged or failed."""
    vw = tol.vw
    for i in range(_N):
        for j in range(vw):
            u = i * LANES + j
            at.scal[u] = 1.0 / (tol.atol * ln.scale[u] + tol.rtol * abs(ln.y[u]))
    guess_lanes(at.nw, ln.z_acc, ln.h, ln.h_acc, ln.poly, vw)
    to_w(at.nw, vw)
    for j in range(nl):
        if at.state[j] == _RUNNING:
            ln.faccon[j] = max(ln.faccon[j], _UROUND) ** FACCON_POWER
        at.theta[j] = _THET
        at.dyn_old[j] = 1.0
        at.thq_old[j] = 1.0
        at.newt[j] = 0
    while _running(at, nl):
        for j in range(vw):
            at.want[j] = at.state[j] == _RUNNING
        stages_rhs(ln.y, at.z, ln.p, at.f, at.work, at.want, kernel, vw)
        residual_lanes(at.nw, ln.h, at.fin, vw)
        real = (at.lu_r, at.piv_r, at.swap_r, at.work)
        lu_solve_pair_lanes(*real, at.lu_cr, at.lu_ci, at.piv_c, at.swap_c, at.cbr, at.cbi, vw)
        wnorm_lanes(at.nw, at.dyno, vw)
        for j in range(vw):
            at.run[j] = False
        for j in range(nl):
            if at.state[j] == _RUNNING:
                _contraction(ln, at, j, tol.fnewt)
        update_lanes(at.nw, at.run, vw)
        for j in range(nl):
            if at.run[j] and ln.faccon[j] * at.dyno[j] <= tol.fnewt:
                at.state[j] = _CONVERGED


@njit(**DRIVER_PHASE)
def _running(at: Attempt, nl) -> bool:
    """Whether any lane still iterates; lanes out of iterations fail (step halved)."""
    running = False
    for j in range(nl):
        if at.state[j] == _RUNNING:
            if at.newt[j] >= _NIT:
                at.state[j] = _FAILED
                at.h_fac[j] = NEWTON_CUT
            else:
                running = True
    return running


@njit(**DRIVER_PHASE)
def _contraction(ln: Lanes, at: Attempt, j, fnewt) -> None:
    """Lane j's Newton convergence test after an iteration (radau_control)."""
    at.newt[j] += 1
    ln.cnt[0, j] += 3
    if not at.fin[j]:
        at.state[j] = _FAILED
        at.h_fac[j] = NEWTON_CUT
        return
    dyno = at.dyno[j]
    failed, at.theta[j], at.thq_old[j], ln.faccon[j], at.h_fac[j] = newton_contraction(
        at.newt[j], dyno, at.dyn_old[j], at.thq_old[j], at.theta[j], ln.faccon[j], fnewt
    )
    if failed:
        at.state[j] = _FAILED
        return
    at.dyn_old[j] = max(dyno, _UROUND)
    at.run[j] = True


@njit(**DRIVER_PHASE)
def _newton_failures(ln: Lanes, at: Attempt, out: Outcome, nl) -> None:
    """Lanes whose Newton iteration failed: a shorter step, a new Jacobian unless it is
    fresh, failure where the step underflows."""
    for j in range(nl):
        if at.state[j] == _FAILED:
            ln.h_lim[j] = min(ln.h_lim[j], ln.h[j] * _LIM_SHRINK)
            ln.cnt[2, j] += 1
            ln.rejected[j] = True
            ln.h[j] *= at.h_fac[j]
            if not ln.fresh[j]:
                ln.new_jac[j] = True
            if underflow(ln.h[j], ln.t[j]):
                ln.live[j] = _end(ln, out, j, Status.FAILED)


@njit(**DRIVER_PHASE)
def _estimate(ln: Lanes, at: Attempt, nl, kernel, tol: Settings) -> None:
    """Phase 4: the embedded error estimate (filtered once more where the scalar code
    does), and the largest cos(theta) over the nodes c1, c2 and the step end (the
    opening pre-test)."""
    vw = tol.vw
    error_rhs_lanes(ln.y, at.z, ln.f0, ln.h, at.ynew, at.err_v, at.work, vw)
    lu_solve_lanes(at.lu_r, at.piv_r, at.swap_r, at.work, vw)
    error_lanes(ln.y, at.ynew, at.work, tol.rtol, tol.atol, ln.scale, at.err, vw)
    any_filter = False
    for j in range(vw):
        once_more = at.state[j] == _CONVERGED and (ln.first[j] or ln.rejected[j])
        at.acc[j] = j < nl and once_more and at.err[j] >= 1.0
        any_filter = any_filter or at.acc[j]
    if any_filter:  # the estimate is unreliable for very stiff components: filter once more
        for u in range(_N * vw):
            at.cbr[u] = ln.y[u] + at.work[u]
        rates_lanes(at.cbr, ln.p, at.fw, 0, kernel, at.acc)
        for u in range(_N * vw):
            at.cbi[u] = at.fw[u] + at.err_v[u] - ln.f0[u]
        lu_solve_lanes(at.lu_r, at.piv_r, at.swap_r, at.cbi, vw)
        error_lanes(ln.y, at.ynew, at.cbi, tol.rtol, tol.atol, ln.scale, at.dyno, vw)
        for j in range(nl):
            if at.acc[j]:
                ln.cnt[0, j] += 1
                at.err[j] = at.dyno[j]
    cos_nutation_any_lanes(at.ynew, ln.p, at.cos_n)
    for k in range(2):
        node_states(ln.y, at.z, k, at.work, vw)
        cos_nutation_any_lanes(at.work, ln.p, at.cos_k)
        for j in range(vw):
            at.cos_n[j] = max(at.cos_n[j], at.cos_k[j])


@njit(**DRIVER_PHASE)
def _decide(ln: Lanes, at: Attempt, one: OneLane, out: Outcome, j, tol: Settings) -> bool:
    """Lane j's decision on a converged attempt, as radau.integrate takes it: reject, or
    accept (opening test and location, hand-back test, next step size). Returns whether
    the step was accepted and the point goes on (its f(y) is then wanted)."""
    if at.state[j] != _CONVERGED or not ln.live[j]:
        return False
    err = at.err[j]
    if not (err == err):
        err = 1e10
    h = ln.h[j]
    quot, quot_std = step_quotient(err, at.newt[j], h, ln.first[j], ln.h_gus[j], ln.err_gus[j])
    if err >= 1.0:
        ln.cnt[2, j] += 1
        ln.rejected[j] = True
        ln.h[j] = h * FIRST_CUT if ln.first[j] else h / quot_std
        if not ln.fresh[j]:
            ln.new_jac[j] = True
        if underflow(ln.h[j], ln.t[j]):
            ln.live[j] = _end(ln, out, j, Status.FAILED)
        return False
    h_new = h / quot
    ln.h_gus[j] = h
    ln.err_gus[j] = max(ERR_GUS_MIN, err)
    # opening: the nodes and the step end are well above theta_cr unless one of their
    # cos(theta) comes near cos(theta_cr); only then the scalar test
    if at.cos_n[j] >= ln.cos_cr[j] - 1e-9 or not (at.cos_n[j] == at.cos_n[j]):
        if _opening(ln, at, one, out, j, tol):
            return False
    else:
        ln.g_old[j] = math.inf
    for u in range(3 * _N):
        ln.z_acc[u * LANES + j] = at.z[u * LANES + j]
    ln.h_acc[j] = h
    ln.poly[j] = True
    ln.t[j] = ln.t[j] + h
    for i in range(_N):
        ln.y[i * LANES + j] = at.ynew[i * LANES + j]
    ln.cnt[1, j] += 1
    if not (ln.y[j] == ln.y[j]):
        ln.live[j] = _end(ln, out, j, Status.FAILED)
        return False
    if ln.hand_back[j] and _sliding_resumed(ln, one, j):
        ln.cnt[0, j] += 1  # the scalar code has evaluated f at the new state
        ln.live[j] = _end(ln, out, j, NONSTIFF_SIGNAL)
        return False
    ln.h[j], ln.h_lim[j], slow = next_step(
        h, h_new, ln.h_lim[j], ln.h_max[j], ln.rejected[j], at.theta[j]
    )
    ln.new_jac[j] = ln.new_jac[j] or slow
    ln.first[j] = False
    ln.rejected[j] = False
    ln.fresh[j] = False
    return True


@njit(**DRIVER_PHASE)
def _opening(ln: Lanes, at: Attempt, one: OneLane, out: Outcome, j, tol: Settings) -> bool:
    """The exact opening test of lane j's converged step and, where theta crosses
    theta_cr inside it, its location (radau.locate_opening_at on the lane's data); whether
    the point opened (it has then ended). Sets ``g_old`` for the next step otherwise."""
    ps = one.p
    for i in range(ps.shape[0]):
        ps[i] = ln.p[i * LANES + j]
    lane_vector(ln.y, j, 0, one.y)
    lane_vector(at.ynew, j, 0, one.ynew)
    for k in range(3):
        lane_vector(at.z, j, k, one.z[k])
    theta_cr = ps[P_THETA_CR]
    if ln.g_old[j] == math.inf:  # the exact g at the step start
        ln.g_old[j] = nutation_angle_of_state(one.y, ps) - theta_cr
    g_new = nutation_angle_of_state(one.ynew, ps) - theta_cr
    if ln.g_old[j] > 0.0:
        lane_vector(at.scal, j, 0, one.scal)
        for i in range(_N):
            for c in range(_N):
                one.jac[i, c] = ln.jac[(i * _N + c) * LANES + j]
        step = (ln.t[j], one.y, ln.h[j], one.z, one.ynew, ln.g_old[j], g_new)
        found, t_ev, nf = locate_opening_at(
            step, ps, one.scal, one.jac, tol.fnewt, tol.event_tol, one.event
        )
        ln.cnt[0, j] += nf
        if found:
            ln.live[j] = finish(out, j, Status.OPENED, t_ev, ln.y, ln.t, ln.idx, ln.cnt)
            return True
    ln.g_old[j] = g_new
    return False


@njit(**DRIVER_PHASE)
def _sliding_resumed(ln: Lanes, one: OneLane, j) -> bool:
    """The hand-back test at lane j's accepted state (switching.sliding_resumed)."""
    lane_vector(ln.y, j, 0, one.y)
    for i in range(one.p.shape[0]):
        one.p[i] = ln.p[i * LANES + j]
    slip, spin = slip_and_spin(one.y, one.p)
    back, ln.t_stick[j] = sliding_resumed(ln.t[j], ln.t_stick[j], slip, spin, one.p[P_WIDTH])
    return back


@njit(**DRIVER_PHASE)
def _end(ln: Lanes, out: Outcome, j, status) -> bool:
    """End lane j's point with `status` at its current state; False."""
    return finish(out, j, status, math.nan, ln.y, ln.t, ln.idx, ln.cnt)
