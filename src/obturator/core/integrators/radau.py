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
  No compiled function allows fast-math (:mod:`obturator.core.jit_flags`).
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
from ..layout import N_STATE, P_THETA_CR, P_WIDTH
from .common import append_row, jacobian, record_row, start, underflow
from .contract import RawSolution, Status
from .radau_control import (
    _LIM_SHRINK,
    ERR_GUS_MIN,
    FIRST_CUT,
    NEWTON_CUT,
    next_step,
    radau5_tolerances,
    step_quotient,
)
from .radau_step import (
    EventWork,
    RadauWork,
    _factor,
    _newton,
    dense_rows,
    error_estimate,
    guess_stages,
    locate_opening_at,
    new_work,
)
from .switching import NONSTIFF_SIGNAL, sliding_resumed

__all__ = [
    "EventWork",
    "RadauState",
    "accepted_outputs",
    "advance",
    "attempt",
    "factored",
    "integrate",
    "jump",
    "locate_opening_at",
    "new_state",
    "new_work",
    "plan_next",
    "took_jacobian",
]

# the counters of RadauState.cnt
NFEV, NJEV, N_STEPS, N_REJ = 0, 1, 2, 3

# The phases below are inlined at numba's IR level into each driver (this module's and
# .stick_slip's): a callee that is not is linked into its caller as a copy, which a
# process loading the caller from the cache runs while a compiling process binds the
# callee's own code, and the two may round differently (benchmarks/cache_binding.py).


class RadauState(NamedTuple):
    """What a Radau IIA run carries from step to step, updated by the phases below (the
    one-trajectory counterpart of :class:`.lanes.radau_state.Lanes`): one-element arrays."""

    h: np.ndarray  #: the step to try [s]
    h_lu: np.ndarray  #: the step the LU factors belong to [s] (NaN: none)
    h_acc: np.ndarray  #: the last accepted step [s] (the stage predictor's)
    h_new: np.ndarray  #: the controller's proposal after the step just accepted [s]
    h_gus: np.ndarray  #: Gustafsson's previous accepted step [s]
    err_gus: np.ndarray  #: Gustafsson's previous error
    h_lim: np.ndarray  #: the step cap after Newton failures [s]
    faccon: np.ndarray  #: Newton's contraction estimate carried over
    theta: np.ndarray  #: the last Newton contraction rate
    need_jac: np.ndarray  #: bool: the Jacobian is stale
    jac_fresh: np.ndarray  #: bool: the Jacobian was taken at this step's start
    have_poly: np.ndarray  #: bool: the event work's zacc holds a collocation polynomial
    first: np.ndarray  #: bool: the first step since the start or a jump
    rejected: np.ndarray  #: bool: the last step was rejected
    #: bool: the run just jumped (start, mode change, a stretch of another method): no
    #: polynomial or step history to extrapolate (diffrax's ``made_jump``)
    made_jump: np.ndarray
    cnt: np.ndarray  #: int64 (4,): NFEV, NJEV, N_STEPS, N_REJ


@njit(cache=True, fastmath=False, error_model="numpy", **REFCOUNT)
def new_state(h: float) -> RadauState:
    """The state at a run's start, first step `h` [s] (a jump: see :func:`jump`)."""
    b = np.zeros(1, dtype=np.bool_)
    st = RadauState(
        np.full(1, h), np.full(1, math.nan), np.zeros(1), np.zeros(1), np.zeros(1),
        np.ones(1), np.full(1, math.inf), np.ones(1), np.zeros(1), b.copy(), b.copy(),
        b.copy(), b.copy(), b.copy(), b.copy(), np.zeros(4, dtype=np.int64),
    )  # fmt: skip
    jump(st, h, math.inf, math.inf)
    return st


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy", inline="always")
def jump(st: RadauState, h: float, h_max: float, t_left: float) -> None:
    """After a discontinuity (the start, a mode change, a stretch of another method): the
    next step min(h, h_max, t_left) [s] with a new Jacobian and LU, no polynomial to
    extrapolate and no Newton-failure cap; counters, Newton's and Gustafsson's history kept."""
    st.h[0] = min(h, h_max, t_left)
    st.h_lu[0] = math.nan
    st.need_jac[0] = True
    st.have_poly[0] = False
    st.first[0] = True
    st.h_lim[0] = math.inf
    st.made_jump[0] = True


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy", inline="always")
def took_jacobian(st: RadauState) -> None:
    """After the driver evaluated the Jacobian (N_STATE right-hand sides): fresh, LU stale."""
    st.cnt[NFEV] += N_STATE
    st.cnt[NJEV] += 1
    st.need_jac[0] = False
    st.jac_fresh[0] = True
    st.h_lu[0] = math.nan


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy", inline="always")
def factored(st: RadauState, t: float, t_max: float, ws: RadauWork) -> bool:
    """The step cut to end at `t_max` where it nearly does, and the LU of its Newton
    matrices (kept while h is); False where the LU failed: then the step is cut
    (rejected) and the driver checks it for underflow."""
    h = st.h[0]
    if t + 1.01 * h >= t_max:
        h = t_max - t
        st.h[0] = h
    if h != st.h_lu[0]:
        if not _factor(h, ws.jac, ws.lu):
            st.cnt[N_REJ] += 1
            st.h[0] = h * NEWTON_CUT
            st.h_lu[0] = math.nan
            return False
        st.h_lu[0] = h
    return True


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy", inline="always")
def predict(st: RadauState, ws: RadauWork) -> None:
    """Newton's start in ``ws.stage[0]``: the last step's polynomial extrapolated, or zero
    after a jump (a driver with a better guess writes its own)."""
    guess_stages(ws.stage[0], ws.event.zacc, st.h[0], st.h_acc[0], st.have_poly[0])


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy", inline="always")
def attempt(st: RadauState, ws: RadauWork, t, y, p, scale, rtol, atol, fnewt) -> bool:
    """One step of length ``st.h`` from (t, y): Newton from the guess in ``ws.stage[0]``,
    the error estimate and the step-size quotient (RADAU5's rules, tolerances already
    transformed). Accepted: True, ``ws.ynew`` the step's end and ``st.h_new`` the
    controller's proposal. Rejected: False, ``st.h`` the shorter step to retry (capped
    after a Newton failure); the driver checks it for underflow."""
    n = N_STATE
    h = st.h[0]
    scal = ws.scal
    for i in range(n):  # reciprocal error weights: the Newton norm multiplies
        scal[i] = 1.0 / (atol * scale[i] + rtol * abs(y[i]))
    ok, newt, theta, faccon, hfac = _newton(
        t, y, h, p, scal, ws.stage, ws.lu, ws.scratch, st.faccon[0], fnewt
    )
    st.cnt[NFEV] += 3 * newt
    st.theta[0] = theta
    st.faccon[0] = faccon
    first = st.first[0]
    if ok:
        err, nf = error_estimate(t, y, h, p, scale, rtol, atol, first or st.rejected[0], ws)
        st.cnt[NFEV] += nf
        quot, quot_std = step_quotient(err, newt, h, first, st.h_gus[0], st.err_gus[0])
        h_retry = h * FIRST_CUT if first else h / quot_std
    else:  # Newton failed: a shorter step, capped below this one
        err, quot = math.inf, 1.0
        st.h_lim[0] = min(st.h_lim[0], h * _LIM_SHRINK)
        h_retry = h * hfac
    if err >= 1.0:  # rejected: a Jacobian at this point if it was stale
        st.cnt[N_REJ] += 1
        st.rejected[0] = True
        st.h[0] = h_retry
        if not st.jac_fresh[0]:
            st.need_jac[0] = True
        return False
    st.h_new[0] = h / quot
    st.h_gus[0] = h
    st.err_gus[0] = max(ERR_GUS_MIN, err)
    return True


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy", inline="always")
def accepted_outputs(st, ws, t, y, p, g_old, t_event, terminal, event_tol, fnewt, out):
    """The opening inside the accepted step (looked for while `g_old` > 0 and none found
    yet; located as :func:`locate_opening_at` does) and its dense output up to the step's
    end or a terminal event. `out` is (t_eval, i_eval, ts, ys, n_out). Returns
    (t_event, opened (terminal event found), g_new, i_eval, n_out)."""
    t_eval, i_eval, ts, ys, n_out = out
    h = st.h[0]
    z = ws.stage[0]
    t_stop = t + h
    g_new = nutation_angle_of_state(ws.ynew, p) - p[P_THETA_CR]
    opened = False
    if g_old > 0.0 and t_event != t_event:
        step = (t, y, h, z, ws.ynew, g_old, g_new)
        found, t_ev, nf = locate_opening_at(step, p, ws.scal, ws.jac, fnewt, event_tol, ws.event)
        st.cnt[NFEV] += nf
        if found:
            st.h_lu[0] = math.nan  # the LU now belongs to a trial step
            t_event = t_ev
            if terminal:
                opened = True
                t_stop = t_event
    if t_eval.shape[0] > 0:
        i_eval, n_out = dense_rows(t, y, h, z, t_stop, t_eval, i_eval, ts, ys, n_out, ws.event.ytry)
    return t_event, opened, g_new, i_eval, n_out


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy", inline="always")
def advance(st: RadauState, ws: RadauWork, t: float, y) -> float:
    """Move to the accepted step's end (`y` in place); its polynomial is kept for the next
    guess. Returns the new time [s]."""
    z, zacc, ynew = ws.stage[0], ws.event.zacc, ws.ynew
    for k in range(3):
        for i in range(N_STATE):
            zacc[k, i] = z[k, i]
    h = st.h[0]
    st.h_acc[0] = h
    st.have_poly[0] = True
    st.made_jump[0] = False
    for i in range(N_STATE):
        y[i] = ynew[i]
    st.cnt[N_STEPS] += 1
    return t + h


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy", inline="always")
def plan_next(st: RadauState, h_max: float) -> None:
    """The next step after an accepted one (:func:`.radau_control.next_step`)."""
    h, h_lim, slow = next_step(
        st.h[0], st.h_new[0], st.h_lim[0], h_max, st.rejected[0], st.theta[0]
    )
    st.h[0] = h
    st.h_lim[0] = h_lim
    st.need_jac[0] = st.need_jac[0] or slow
    st.first[0] = False
    st.rejected[0] = False
    st.jac_fresh[0] = False


@njit(cache=True, fastmath=False, error_model="numpy", **REFCOUNT)
def work_with(y_event) -> RadauWork:
    """:func:`new_work` whose event state is the run's `y_event` (from :func:`.common.start`)."""
    ws = new_work()
    e = ws.event
    ev = EventWork(e.zacc, e.stage, e.lu, e.scratch, e.ytry, y_event)
    return RadauWork(
        ws.f0, ws.ynew, ws.fwork, ws.scal, ws.err_v, ws.jac, ws.stage, ws.lu, ws.scratch, ev
    )


#: What :func:`_step` asks of :func:`integrate`'s loop: step again (a new Jacobian,
#: factors or a shorter step), end the run as failed, end it at the opening, go on.
_RETRY, _FAILED, _OPENED, _STEPPED = 0, 1, 2, 3


# a function of its own, compiled without reference counting (it allocates nothing):
# inlined into the counted loop, every phase's access to the state's arrays was wrapped
# in reference counts (obturator.core.jit_flags); same operations, same order
@njit(cache=True, fastmath=False, error_model="python", **NO_REFCOUNT)
def _step(st: RadauState, ws: RadauWork, t, y, p, scale, controls, g_old, t_event, out):
    """One step of :func:`integrate`: its Jacobian where due, factors, Newton, outputs at
    `t_eval` inside it, the move to its end and f there. `controls` is (t_max, rtol, atol,
    fnewt, terminal, event_tol) (RADAU5's tolerances), `out` (t_eval, i_eval, ts, ys,
    n_out). Returns (code, t, t_event, g_old, i_eval, n_out) with the codes above."""
    t_max, rtol, atol, fnewt, terminal, event_tol = controls
    t_eval, i_eval, ts, ys, n_out = out
    if st.need_jac[0]:
        jacobian(t, y, ws.f0, p, scale, ws.jac, ws.scratch[0], ws.fwork)
        took_jacobian(st)
    if not factored(st, t, t_max, ws):
        return _FAILED if underflow(st.h[0], t) else _RETRY, t, t_event, g_old, i_eval, n_out
    predict(st, ws)
    if not attempt(st, ws, t, y, p, scale, rtol, atol, fnewt):
        return _FAILED if underflow(st.h[0], t) else _RETRY, t, t_event, g_old, i_eval, n_out
    t_event, opened, g_new, i_eval, n_out = accepted_outputs(
        st, ws, t, y, p, g_old, t_event, terminal, event_tol, fnewt, (t_eval, i_eval, ts, ys, n_out)
    )
    if opened:
        return _OPENED, t, t_event, g_old, i_eval, n_out
    t = advance(st, ws, t, y)
    rhs(t, y, p, ws.f0)
    st.cnt[NFEV] += 1
    return _STEPPED, t, t_event, g_new, i_eval, n_out


@njit(cache=True, nogil=True, fastmath=False, error_model="python", **REFCOUNT)
def integrate(problem, controls):
    """Integrate from t = t0 until theta = theta_cr (event) or t_max; see :mod:`.contract`."""
    p, scale = problem.p, problem.scale
    (
        t_max,
        rtol,
        atol,
        h0,
        h_max,
        max_steps,
        t_eval,
        record,
        terminal,
        event_tol,
        stop_when_sliding,
        _,
    ) = controls
    t, y, ts, ys, n_out, y_event = start(problem, controls)
    ws = work_with(y_event)
    use_eval = t_eval.shape[0] > 0
    i_eval = 0
    status = Status.T_MAX
    t_event = math.nan
    rtol, atol, fnewt = radau5_tolerances(rtol, atol)
    st = new_state(min(h0, h_max, t_max - t))
    rhs(t, y, p, ws.f0)
    st.cnt[NFEV] += 1
    g_old = nutation_angle_of_state(y, p) - p[P_THETA_CR]
    t_stick = t  # last time the slip speed was below saturation (stop_when_sliding)
    while t < t_max:
        if st.cnt[N_STEPS] >= max_steps:
            status = Status.STEP_LIMIT
            break
        code, t, t_event, g_old, i_eval, n_out = _step(
            st, ws, t, y, p, scale, (t_max, rtol, atol, fnewt, terminal, event_tol),
            g_old, t_event, (t_eval, i_eval, ts, ys, n_out),
        )  # fmt: skip
        if code == _RETRY:
            continue
        if code == _FAILED:
            status = Status.FAILED
            break
        if code == _OPENED:
            status = Status.OPENED
            ts, ys, n_out = record_row(ts, ys, n_out, t_event, y_event, record, use_eval)
            y[:] = y_event
            t = t_event
            break
        if record and not use_eval:  # a call per step costs reference counts
            ts, ys, n_out = append_row(ts, ys, n_out, t, y)
        if not (y[0] == y[0]):
            status = Status.FAILED
            break
        if stop_when_sliding:
            slip, spin = slip_and_spin(y, p)
            back, t_stick = sliding_resumed(t, t_stick, slip, spin, p[P_WIDTH])
            if back:
                status = NONSTIFF_SIGNAL
                break
        plan_next(st, h_max)
    c = st.cnt
    return RawSolution(
        status, t_event, y_event, ts[:n_out], ys[:n_out], c[NFEV], c[NJEV], c[N_STEPS], c[N_REJ],
        t, y,
    )  # fmt: skip
