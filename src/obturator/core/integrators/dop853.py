"""Compiled explicit integrator: Dormand & Prince's 8(5,3) Runge-Kutta pair (DOP853).

Outside sticking phases the
equations of motion are not stiff (the friction Jacobian is ~ mu N R_s / (A
|omega_r|), small once the ball slips at several rad/s), so an explicit
high-order pair needs far fewer right-hand-side evaluations than the implicit
methods and no Jacobian. In sticking phases it is hopeless, and it says so
(status ``STIFF``, with its last accepted state) so that ``auto`` can continue with
Radau IIA from there.

* Method: the eighth-order pair of Hairer, Norsett & Wanner, *Solving
  Ordinary Differential Equations I*, 2nd ed., Sec. II.10 (code DOP853), with
  its combined 5th/3rd-order error estimate
  ``err = h |e5|^2 / sqrt(|e5|^2 + 0.01 |e3|^2)`` and step control
  ``h_new = h min(10, max(0.2, 0.9 err^(-1/8)))`` (no growth right after a
  rejection). The coefficients are published data; the decimal values here
  were taken from SciPy's ``scipy/integrate/_ivp/dop853_coefficients.py``
  (which transcribes Hairer's ``dop853.f``).
* Error weights as in the other integrators, ``atol * scale[i] + rtol *
  max(|y_i|, |ynew_i|)``, but with (rtol, atol) multiplied by
  :data:`TOL_FACTOR` = 0.01 (rtol floored at 1e-14), so that t_cr errors are
  ~1e-9 relative at rtol 1e-8, as with Radau (which transforms its rtol too).
* Opening event theta = theta_cr (downward crossing) is tested at step ends and
  located by re-stepping from the step start with a shorter step (Illinois
  false position), so the event state is as accurate as an accepted step
  (eighth order), to a bracket of ``event_tol``.
* t_eval output re-steps from the start of the step that contains each output
  time (11 right-hand sides per point), so output values carry the accuracy
  of an accepted step (no interpolation error); it is not used for t_cr.
* Stiffness: the run stops with status ``STIFF`` when Hairer's test (dop853.f)
  finds h*lambda = h |f(y_new) - f(y_12)| / |y_new - y_12| beyond the stability
  boundary 6.1 on 15 accepted steps in a row (detects a sticking phase within a few
  dozen steps), when the number of accepted plus rejected steps exceeds
  ``STEPS_PER_PERIOD`` per spin period of simulated time plus ``STEP_ALLOWANCE``
  (the thresholds of :mod:`.switching`, shared with every driver), when the step
  size collapses, or when the state turns non-finite. The state it returns is the
  last accepted one.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..dynamics import nutation_angle_of_state, rhs
from ..fma import fma
from ..jit_flags import NO_REFCOUNT, REFCOUNT
from ..layout import N_STATE, P_THETA_CR
from .common import (
    append_row,
    bracket_closed,
    crossed,
    illinois_trial,
    illinois_update,
    record_row,
    start,
    underflow,
)
from .contract import RawSolution, Status
from .dop853_coefficients import E3 as _E3
from .dop853_coefficients import E5 as _E5
from .dop853_coefficients import A as _A
from .dop853_coefficients import B as _B
from .dop853_coefficients import C as _C
from .switching import (
    STEP_ALLOWANCE,
    STEPS_PER_PERIOD,
    STIFF_HLAMBDA,
    STIFF_SIGNAL,
    STIFF_STEPS,
    over_step_budget,
    stiffness_count,
)

__all__ = [
    "STEPS_PER_PERIOD",
    "STEP_ALLOWANCE",
    "STIFF_HLAMBDA",
    "STIFF_STEPS",
    "TOL_FACTOR",
    "integrate",
]

#: The step error is controlled to this fraction of the requested (rtol, atol).
TOL_FACTOR = 0.01


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
def _stages(t, y, h, p, k, ynew, work) -> None:
    """Stages k[1..11] (k[0] = f(t, y) given) and the 8th-order solution ynew."""
    n = N_STATE
    for s in range(1, 12):
        for i in range(n):
            acc = 0.0
            for j in range(s):
                acc = fma(_A[s, j], k[j, i], acc)
            work[i] = fma(h, acc, y[i])
        rhs(t + _C[s] * h, work, p, k[s])
    for i in range(n):
        acc = 0.0
        for j in range(12):
            acc = fma(_B[j], k[j, i], acc)
        ynew[i] = fma(h, acc, y[i])


@njit(cache=True, error_model="numpy", **NO_REFCOUNT, fastmath=False)
def step_factor(err) -> float:
    """0.9 err^(-1/8), DOP853's step-size factor before its bounds (inf at err = 0).

    Written with square roots instead of pow so that the lanes' loop over lanes
    vectorises (pow does not without a vector math library); both paths use this.
    NumPy error model: err = 0 gives inf (the caller's bound makes it 10), and the
    lanes call it for idle lanes too.
    """
    return 0.9 / math.sqrt(math.sqrt(math.sqrt(err)))


@njit(cache=True, error_model="numpy", **NO_REFCOUNT, fastmath=False)
def stiffness_product(h, num, den) -> float:
    """Hairer's h |lambda| estimate h sqrt(num / den), or -1 when den = 0."""
    return h * math.sqrt(num / den) if den > 0.0 else -1.0


@njit(cache=True, error_model="numpy", **NO_REFCOUNT, fastmath=False)
def error_weight(atol, scale, rtol, y, ynew) -> float:
    """atol * scale + rtol * max(|y|, |ynew|), the same operations as the lane code's
    (:mod:`.lanes`), so both round alike."""
    return atol * scale + rtol * max(abs(y), abs(ynew))


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="python")
def _error_norm(k, h, y, ynew, rtol, atol, scale) -> float:
    """DOP853's combined estimate h |e5|^2 / sqrt((|e5|^2 + 0.01 |e3|^2) n)."""
    n = N_STATE
    s5 = 0.0
    s3 = 0.0
    for i in range(n):
        sc = error_weight(atol, scale[i], rtol, y[i], ynew[i])
        e5 = 0.0
        e3 = 0.0
        for j in range(12):
            e5 = fma(_E5[j], k[j, i], e5)
            e3 = fma(_E3[j], k[j, i], e3)
        e5 /= sc
        e3 /= sc
        s5 = fma(e5, e5, s5)
        s3 = fma(e3, e3, s3)
    if s5 == 0.0 and s3 == 0.0:
        return 0.0
    return abs(h) * s5 / math.sqrt((s5 + 0.01 * s3) * n)


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def locate_event(t, y, h, p, k, work, ytry, y_event, g_old, g_new, event_tol):
    """Opening time inside the accepted step (t, t + h] (g_old > 0 >= g_new).

    Illinois false position on g(s) = theta(step(y, s h)) - theta_cr, re-stepping
    from (t, y) (k[0] = f(t, y) is unchanged by the trial steps), to a bracket of
    `event_tol`; `y_event` (holding the step's end state) receives the state of the
    last trial at or past theta_cr. Returns (t_event, right-hand sides spent).
    Shared with the batched lanes (:mod:`.lanes`).
    """
    theta_cr = p[P_THETA_CR]
    s_lo, s_hi = 0.0, 1.0
    g_lo, g_hi = g_old, g_new
    side = 0
    nfev = 0
    for _ in range(200):
        if bracket_closed(s_lo, s_hi, h, event_tol):
            break
        s = illinois_trial(s_lo, g_lo, s_hi, g_hi)
        _stages(t, y, s * h, p, k, ytry, work)
        nfev += 11
        g = nutation_angle_of_state(ytry, p) - theta_cr
        s_lo, g_lo, s_hi, g_hi, side = illinois_update(s, g, s_lo, g_lo, s_hi, g_hi, side)
        if not g > 0.0:  # same branch as illinois_update (NaN included)
            for i in range(N_STATE):
                y_event[i] = ytry[i]
    return t + s_hi * h, nfev


# the counters of Dop853State.cnt (as the rows of the lanes' cnt)
NFEV, N_STEPS, N_REJ, N_STIFF, N_CALM = 0, 1, 2, 3, 4

# The phases below are inlined at numba's IR level into the driver, as those of .radau
# (a cached caller would otherwise run its own copy of each: benchmarks/cache_binding.py).


class Dop853State(NamedTuple):
    """What a DOP853 run carries from step to step, updated by the phases below (the
    one-trajectory counterpart of the lanes' state, :mod:`.lanes.dop853`)."""

    h: np.ndarray  #: (1,) the step to try [s]
    rejected: np.ndarray  #: bool (1,): the last step was rejected (no growth after it)
    #: bool (1,): the run just started (or jumped): k[0] was evaluated, not carried over
    #: from the last step's end (first same as last); cleared by the next accepted step
    made_jump: np.ndarray
    cnt: np.ndarray  #: int64 (5,): NFEV, N_STEPS, N_REJ, N_STIFF, N_CALM
    k: np.ndarray  #: (12, N_STATE) stages; k[0] = f(t, y)
    f1: np.ndarray  #: f(t + h, ynew): the next step's k[0]
    ynew: np.ndarray  #: the step's end
    ytry: np.ndarray  #: a trial state (event location, output)
    work: np.ndarray  #: stage argument; after a step y12, the stiffness test's


@njit(cache=True, fastmath=False, error_model="numpy", **REFCOUNT)
def new_state(t, y, p, h) -> Dop853State:
    """The state at a run's start (t, y), first step `h` [s]; k[0] = f(t, y)."""
    n = N_STATE
    st = Dop853State(
        np.full(1, h), np.zeros(1, dtype=np.bool_), np.ones(1, dtype=np.bool_),
        np.zeros(5, dtype=np.int64), np.empty((12, n)), np.empty(n), np.empty(n),
        np.empty(n), np.empty(n),
    )  # fmt: skip
    rhs(t, y, p, st.k[0])
    st.cnt[NFEV] += 1
    return st


@njit(cache=True, fastmath=False, error_model="numpy", **NO_REFCOUNT, inline="always")
def attempt(st: Dop853State, t, y, p, rtol, atol, scale) -> float:
    """One step of length ``st.h`` from (t, y): the stages, the 8th-order end
    ``st.ynew`` and DOP853's error estimate (1e10 for NaN). Rejected (> 1): ``st.h`` the
    shorter step to retry; the driver checks it for underflow. Returns the error."""
    h = st.h[0]
    _stages(t, y, h, p, st.k, st.ynew, st.work)
    st.cnt[NFEV] += 11
    err = _error_norm(st.k, h, y, st.ynew, rtol, atol, scale)
    if not (err == err):
        err = 1e10
    if err > 1.0:
        st.cnt[N_REJ] += 1
        st.rejected[0] = True
        st.h[0] = h * max(0.2, step_factor(err))
    return err


@njit(cache=True, fastmath=False, error_model="numpy", **NO_REFCOUNT, inline="always")
def stiff_at_end(st: Dop853State, t, p) -> bool:
    """f at the accepted step's end (``st.f1``) and Hairer's stiffness test (dop853.f):
    h |f(ynew) - f(y12)| / |ynew - y12| estimates h*lambda, y12 = ``st.work`` the last
    stage's argument; :func:`.switching.stiffness_count` decides (the step size held by
    stability, not accuracy)."""
    h = st.h[0]
    f1, k, ynew, work = st.f1, st.k, st.ynew, st.work
    rhs(t + h, ynew, p, f1)
    st.cnt[NFEV] += 1
    num = 0.0
    den = 0.0
    for i in range(N_STATE):
        num += (f1[i] - k[11, i]) ** 2
        den += (ynew[i] - work[i]) ** 2
    hl = stiffness_product(h, num, den)
    n_stiff, n_calm, stiff = stiffness_count(hl, st.cnt[N_STIFF], st.cnt[N_CALM])
    st.cnt[N_STIFF] = n_stiff
    st.cnt[N_CALM] = n_calm
    return stiff


@njit(cache=True, fastmath=False, error_model="numpy", **NO_REFCOUNT, inline="always")
def accepted_outputs(st: Dop853State, t, y, p, g_old, t_event, y_event, terminal, event_tol, out):
    """The opening inside the accepted step (:func:`locate_event`, the first downward
    crossing) and the output on t_eval up to its end or a terminal event (re-stepping
    from (t, y): as accurate as a step). `out` is (t_eval, i_eval, ts, ys, n_out).
    Returns (t_event, opened (terminal event found), g_new, i_eval, n_out)."""
    t_eval, i_eval, ts, ys, n_out = out
    h = st.h[0]
    k, ynew, ytry, work = st.k, st.ynew, st.ytry, st.work
    t_stop = t + h
    opened = False
    g_new = nutation_angle_of_state(ynew, p) - p[P_THETA_CR]
    if crossed(g_old, g_new, t_event):
        for i in range(N_STATE):
            y_event[i] = ynew[i]
        t_event, nf = locate_event(t, y, h, p, k, work, ytry, y_event, g_old, g_new, event_tol)
        st.cnt[NFEV] += nf
        if terminal:
            opened = True
            t_stop = t_event
    while i_eval < t_eval.shape[0] and t_eval[i_eval] <= t_stop:
        _stages(t, y, t_eval[i_eval] - t, p, k, ytry, work)
        st.cnt[NFEV] += 11
        ts[n_out] = t_eval[i_eval]
        for i in range(N_STATE):
            ys[n_out, i] = ytry[i]
        n_out += 1
        i_eval += 1
    return t_event, opened, g_new, i_eval, n_out


@njit(cache=True, fastmath=False, error_model="numpy", **NO_REFCOUNT, inline="always")
def advance(st: Dop853State, t, y) -> float:
    """Move to the accepted step's end (`y` in place, k[0] = f there: first same as
    last). Returns the new time [s]."""
    for i in range(N_STATE):
        y[i] = st.ynew[i]
        st.k[0, i] = st.f1[i]
    st.cnt[N_STEPS] += 1
    st.made_jump[0] = False
    return t + st.h[0]


@njit(cache=True, fastmath=False, error_model="numpy", **NO_REFCOUNT, inline="always")
def plan_next(st: Dop853State, err, h_max) -> None:
    """The next step after an accepted one: h min(10, max(0.2, 0.9 err^(-1/8))), no growth
    right after a rejection, at most `h_max`."""
    fac = min(10.0, max(0.2, step_factor(err)))  # err = 0: inf -> 10
    if st.rejected[0]:
        fac = min(fac, 1.0)
    st.rejected[0] = False
    st.h[0] = min(st.h[0] * fac, h_max)


#: What :func:`_step` asks of :func:`integrate`'s loop: step again (rejected), end the
#: run as stiff (the hand-over signal), end it at the opening, go on.
_RETRY, _STIFF, _OPENED, _STEPPED = 0, 1, 2, 3


# a function of its own, compiled without reference counting (it allocates nothing):
# inlined into the counted loop, every phase's access to the state's arrays was wrapped
# in reference counts (obturator.core.jit_flags); same operations, same order
@njit(cache=True, fastmath=False, error_model="python", **NO_REFCOUNT)
def _step(st: Dop853State, t, y, p, scale, controls, g_old, t_event, y_event, out):
    """One step of :func:`integrate`: cut to end at t_max, the trial, the stiffness
    test, outputs at `t_eval` inside it and the move to its end. `controls` is (t_max,
    rtol, atol, terminal, event_tol) (the transformed tolerances), `out` (t_eval, i_eval,
    ts, ys, n_out). Returns (code, err, t, t_event, g_old, i_eval, n_out) with the codes
    above and the step's error estimate `err` (for :func:`plan_next`)."""
    t_max, rtol, atol, terminal, event_tol = controls
    t_eval, i_eval, ts, ys, n_out = out
    if t + 1.01 * st.h[0] >= t_max:
        st.h[0] = t_max - t
    err = attempt(st, t, y, p, rtol, atol, scale)
    if err > 1.0:
        return _STIFF if underflow(st.h[0], t) else _RETRY, err, t, t_event, g_old, i_eval, n_out
    if stiff_at_end(st, t, p):
        return _STIFF, err, t, t_event, g_old, i_eval, n_out
    t_event, opened, g_new, i_eval, n_out = accepted_outputs(
        st, t, y, p, g_old, t_event, y_event, terminal, event_tol,
        (t_eval, i_eval, ts, ys, n_out),
    )  # fmt: skip
    if opened:
        return _OPENED, err, t, t_event, g_old, i_eval, n_out
    t = advance(st, t, y)
    return _STEPPED, err, t, t_event, g_new, i_eval, n_out


# nogil: the CLI watcher thread can stop a long run
@njit(cache=True, nogil=True, fastmath=False, error_model="python", **REFCOUNT)
def integrate(problem, controls):
    """Integrate from t = t0 until theta = theta_cr (event) or t_max; see :mod:`.contract`.

    Status ``STIFF`` when the problem looks stiff; njev is always 0.
    """
    p, scale = problem.p, problem.scale
    t_max, rtol, atol, h0, h_max, max_steps, t_eval, record, terminal, event_tol, _, _ = controls
    t, y, ts, ys, n_out, y_event = start(problem, controls)
    use_eval = t_eval.shape[0] > 0
    i_eval = 0
    status = Status.T_MAX
    t_event = math.nan
    # spin period of the release state: the largest component scale is omega_p0
    w0 = 0.0
    for i in range(N_STATE):
        w0 = max(w0, scale[i])
    # Tolerance transformation: the local error per step is controlled to
    # TOL_FACTOR * (rtol, atol). At the requested tolerances the accumulated
    # phase error gave t_cr errors up to ~1e-6 (rig, 700 rad/s, rtol 1e-8) and
    # a t_cr(mu_s) ripple that spoils finite-difference fits; a hundredth gives
    # ~1e-9 for ~1.5x the right-hand sides, like Radau's at equal rtol.
    tol_f = max(TOL_FACTOR, 1e-14 / rtol)
    rtol = tol_f * rtol
    atol = tol_f * atol
    steps_per_time = STEPS_PER_PERIOD * w0 / (2.0 * math.pi)
    t0 = t
    st = new_state(t, y, p, min(h0, h_max, t_max - t))
    c = st.cnt
    g_old = nutation_angle_of_state(y, p) - p[P_THETA_CR]
    while t < t_max:
        if c[N_STEPS] >= max_steps:
            status = Status.STEP_LIMIT
            break
        if over_step_budget(c[N_STEPS] + c[N_REJ], steps_per_time, t, t0):
            status = STIFF_SIGNAL
            break
        code, err, t, t_event, g_old, i_eval, n_out = _step(
            st, t, y, p, scale, (t_max, rtol, atol, terminal, event_tol), g_old, t_event,
            y_event, (t_eval, i_eval, ts, ys, n_out),
        )  # fmt: skip
        if code == _RETRY:
            continue
        if code == _STIFF:
            status = STIFF_SIGNAL
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
            status = STIFF_SIGNAL
            break
        plan_next(st, err, h_max)
    return RawSolution(
        status, t_event, y_event, ts[:n_out], ys[:n_out], c[NFEV], 0, c[N_STEPS], c[N_REJ], t, y
    )
