"""Event-driven stick-slip integration of the friction laws, with no width.

The nonsmooth pieces have one home each (the split of Siconos and of Acary and
Brogliato): the admissible set of friction moments in
:mod:`obturator.core.friction_sets`, the modes (slip speed, admissibility, breakaway)
in :mod:`.stick_slip_modes`, this event-driven strategy, which composes them with the
step phases of :mod:`.radau` and stretches of :mod:`.dop853`, and the time-stepping
(Moreau-Jean) strategy in :mod:`.moreau_jean`.

Formulation: the *switch model* of Leine and Nijmeijer (*Dynamics and Bifurcations
of Non-Smooth Mechanical Systems*, Springer 2004, ch. 2 and 9), with the exact set of
admissible moments in place of Leine's stick band (Glocker, *Set-Valued Force Laws*,
Springer 2001; Acary and Brogliato, *Numerical Methods for Nonsmooth Dynamical
Systems*, Springer 2008, ch. 7: event-driven schemes). The ball is in one of two
modes (``docs/stick_slip.md`` derives them from thesis Eqs. 35-36, 56-64, Appendix A,
and for the Coulomb patch law from its dissipation function, section 9 there):

* **stick**, omega_r = 0: the ball turns rigidly with the socket, so its attitude is a
  rotation about Z and nothing is integrated; the reaction is G_req =
  omega_p^2 (C - A) z_Z (Z x z) (:func:`obturator.core.friction_sets.required_reaction`)
  and the mode holds while G_req lies in the admissible set F. The exit (G_req on the
  boundary of F) is a closed-form rotation angle
  (:func:`~obturator.core.friction_sets.breakaway_angle`), exact to rounding.
* **slip**, omega_r != 0: thesis Eqs. 62-64 with the true-direction law at full
  magnitude (``P_WIDTH = 0``: no regularisation). Slip right after breakaway and before
  sticking is stiff in the slip *direction* (relaxation rate ~ M / (A |omega_r|),
  unbounded as omega_r -> 0: the rig's creep about X is a sliding motion on this slow
  manifold), so an explicit method would need unboundedly many steps there: it is
  integrated by fifth-order Radau IIA: the loop calls the step phases of :mod:`.radau`
  (:func:`~.radau.factored`, :func:`~.radau.attempt`, :func:`~.radau.accepted_outputs`,
  :func:`~.radau.advance`, :func:`~.radau.plan_next`, and :func:`~.radau.jump` after
  every mode change) at ``auto``'s third of the tolerances.
  Above |omega_r| = :data:`~.switching.FAST_SLIP` (M / A) h_max the direction is
  resolved by the largest step and the slip runs in DOP853 stretches (:mod:`.dop853`,
  the tolerances as given), each short enough that |omega_r| cannot fall below half
  that level at twice its present rate of change; DOP853's stiffness test (the signal
  ``STIFF``, :mod:`.switching`) hands back to Radau IIA otherwise.

Transitions:

* slip -> stick: stick is the only continuation once |omega_r| reaches 0 with G_req
  inside F. When G_req is inside F and |omega_r| decreases, the step is cut to
  :data:`HOME_IN` of the predicted time to zero slip (Newton's method on |omega_r|(t)),
  and stick starts once |omega_r| <= :data:`STICK_SLIP` omega_p: omega_r is then set to
  0. Projecting from |omega_r| = r changes the attitude by O(r^2 / a) (a the
  deceleration), far below the step error.
* stick -> slip: at the breakaway angle; the slip starts with omega_r =
  :data:`KICK` omega_p along the ray in which the saturated friction gives way
  (-G_req / |G_req| for the thesis law; Radau IIA needs a defined direction at its
  first node).

* reversal: a slip that has exceeded :data:`STICK_SLIP` omega_p and falls back to it
  with G_req outside F passes through zero slip (the rig's creep about X under the
  Coulomb patch law, twice a revolution): it is set to zero there as for stick and
  kicked out at once along the departure ray
  (:func:`~obturator.core.friction_sets.exit_slip_direction`); Radau IIA cannot step
  across that kink.
* grazing exit: a kicked slip that cannot take off (|omega_r| below the kick with
  G_req still outside F, Radau IIA's steps collapsed) is held rigidly through the rest of
  the window (:func:`_through_window`); its creep is below the kick's scale.

The friction moment at zero slip is never evaluated in slip, and the stick reaction
is never integrated, so there is no width (the thesis law's slip phases run the
specialised kernel at zero width, :func:`~obturator.core.specialised.specialise`);
Radau IIA's Jacobian differences the law at zero width with increments scaled to the
slip speed (:mod:`.stick_slip_jacobian`).
A step with no collocation polynomial to extrapolate (after a kick) starts Newton from
the rigid turn with the socket. Requires the quaternion formulation,
the thesis friction law (rig or flight) or the Coulomb patch law with a patch (a > 0),
constant mu_s, and a constant or free spin.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ...errors import InputError
from ..dynamics import nutation_angle_of_state, rhs
from ..friction_sets import (
    breakaway_angle,
    hold_stick,
    turn_by,
    turn_rigidly,
)
from ..jit_flags import NO_REFCOUNT, REFCOUNT
from ..layout import (
    FAMILY_ALGEBRAIC,
    FORM_QUATERNION,
    KERNEL_THESIS,
    N_STATE,
    P_FAMILY,
    P_FORM,
    P_KERNEL,
    P_SPIN_MODE,
    P_THETA_CR,
    P_WIDTH,
    SPIN_THESIS_ENERGY,
)
from ..specialised import specialise
from . import AUTO_RADAU_TOL_FACTOR
from . import stick_slip_map as return_map
from .common import append_row, record_row, start, underflow
from .contract import Controls, Problem, RawSolution, Status
from .dop853 import integrate as dop853_integrate
from .radau import (
    N_REJ,
    N_STEPS,
    NFEV,
    RadauState,
    RadauWork,
    accepted_outputs,
    advance,
    attempt,
    factored,
    jump,
    new_state,
    plan_next,
    took_jacobian,
    work_with,
)
from .radau_coefficients import C1, C2
from .radau_control import radau5_tolerances
from .radau_step import guess_stages
from .stick_slip_jacobian import slip_jacobian
from .stick_slip_modes import (
    EVENT_DRIVEN,
    HAND_OFF_KAPPA,
    HAND_OFF_SLIP,
    HOLD_THROUGH,
    HOME_IN,
    KICK,
    REKICK,
    RELEASE_KICK,
    STICK_SLIP,
    TAKE_OFF,
    EventDrivenSettings,
    check_set_valued_law,
    slip_speed_unit,
)
from .stick_slip_modes import break_away as _break_away
from .stick_slip_modes import slip as _slip
from .stick_slip_modes import slip_rate as _slip_rate
from .stick_slip_modes import stick_admissible as _stick_admissible
from .stick_slip_modes import stick_ratio as _stick_ratio
from .stick_slip_modes import through_window as _through_window
from .switching import CHUNK, FAST_SLIP, NONSTIFF_SIGNAL

__all__ = [
    "EVENT_DRIVEN",
    "EventDrivenSettings",
    "STICK_SLIP",
    "KICK",
    "HOME_IN",
    "FAST_SLIP",
    "TAKE_OFF",
    "RELEASE_KICK",
    "REKICK",
    "HOLD_THROUGH",
    "at_zero_width",
    "integrate",
    "run_cycles",
    "zero_width",
]


def integrate(
    problem: Problem,
    controls: Controls,
    stick_slip: float = STICK_SLIP,
    kick: float = KICK,
    shared: return_map.CycleMap | None = None,
) -> RawSolution:
    """Integrate with exact stick and slip modes from t0 to the opening or t_max.

    Keeps the contract of :mod:`.contract`; the regularisation width and family in
    ``problem.p`` are ignored (the law is used at zero width). `stick_slip` and
    `kick` override :data:`STICK_SLIP` and :data:`KICK` (convergence studies);
    `shared` is this case's return map from
    :func:`.stick_slip_family.shared_maps` (a sweep's cases).

    Raises
    ------
    InputError
        For a case outside the solver's scope (Euler-angle formulation, the thesis's
        energy spin mode, no friction, a slip-speed law, Coulomb point contacts).
    """
    problem = at_zero_width(problem)
    if return_map.applies(problem, controls):
        return return_map.integrate(problem, controls, run_cycles(stick_slip, kick), shared)
    return run_cycles(stick_slip, kick)(problem, controls, math.inf)


def at_zero_width(problem: Problem) -> Problem:
    """`problem` at zero width, after the checks of the solver's scope (raises as
    :func:`integrate` does)."""
    p = np.array(problem.p, dtype=float)
    if p[P_FORM] != FORM_QUATERNION:
        raise InputError("formulation", "the set-valued solver integrates 'quaternion' only")
    if p[P_SPIN_MODE] == SPIN_THESIS_ENERGY:
        raise InputError("spin_mode", "the set-valued solver takes 'constant' or 'free'")
    check_set_valued_law(p, "the set-valued solver")
    return problem._replace(p=zero_width(p))


def zero_width(p: np.ndarray) -> np.ndarray:
    """`p` (in place) with no regularisation width, for the mode loop: the law at full
    magnitude, on the specialised kernel where it applies (the thesis law)."""
    p[P_WIDTH] = 0.0
    p[P_FAMILY] = FAMILY_ALGEBRAIC
    return specialise(p, zero_width=True)


def run_cycles(stick_slip: float = STICK_SLIP, kick: float = KICK):
    """``run(problem, controls, cycle_end) -> RawSolution``: the mode loop on a problem
    whose parameters :func:`integrate` has checked and set to zero width, stopping at
    the first breakaway at or after `cycle_end` [s] (``math.inf``: never)."""

    def run(problem: Problem, controls: Controls, cycle_end: float) -> RawSolution:
        return _integrate(problem, controls, stick_slip, kick, cycle_end)

    return run


# the loop's phases are inlined at numba's IR level, as are those of .radau: a callee
# that is not is linked into its caller as a copy that a process loading the caller from
# the cache runs, optimised again there, while a compiling process binds the callee's
# own code (the two may round differently: benchmarks/cache_binding.py)
_PHASE = dict(cache=True, fastmath=False, error_model="python", inline="always")


@njit(**_PHASE, **NO_REFCOUNT)
def _release(st: RadauState, y, p, t: float, f0, ytry) -> float:
    """A run that starts in slip: where it starts at (or near) zero slip with G_req
    outside F (released), kicked at :data:`RELEASE_KICK`; f0 = f(t, y). Returns t [s]."""
    spin = abs(y[7]) if y[7] != 0.0 else 1.0
    r_release = RELEASE_KICK * spin
    if _slip(y)[3] < r_release:
        tau = _break_away(y, p, r_release, ytry)
        t += tau
        if tau > 0.0:
            st.h[0] = min(st.h[0], TAKE_OFF * tau)
    rhs(t, y, p, f0)
    st.cnt[NFEV] += 1
    return t


@njit(**_PHASE, **REFCOUNT)
def _stick(y, p, t, t_max, record, out, ytry):
    """The stick mode: the rigid turn with the socket to the breakaway angle (or t_max),
    with its outputs; `out` is (t_eval, i_eval, ts, ys, n_out). Returns (t, exit angle
    (< 0: a re-kick inside a window), i_eval, ts, ys, n_out)."""
    t_eval, i_eval, ts, ys, n_out = out
    wp = y[7]
    hold_stick(y, wp)
    exit_angle = breakaway_angle(y, p, wp)
    angle = max(exit_angle, 0.0)
    t_b = min(t + angle / abs(wp), t_max) if wp != 0.0 else t_max
    while i_eval < t_eval.shape[0] and t_eval[i_eval] <= t_b:
        turn_rigidly(y, wp * (t_eval[i_eval] - t), ytry)
        ts[n_out] = t_eval[i_eval]
        ys[n_out, :] = ytry
        n_out += 1
        i_eval += 1
    turn_rigidly(y, wp * (t_b - t), ytry)
    y[:] = ytry
    if record and t_eval.shape[0] == 0:
        ts, ys, n_out = append_row(ts, ys, n_out, t_b, y)
    return t_b, exit_angle, i_eval, ts, ys, n_out


@njit(**_PHASE, **NO_REFCOUNT)
def _kick(st: RadauState, y, p, t, t_max, h0, h_max, r_kick, f0, ytry) -> float:
    """Stick -> slip at the breakaway: the kick (:func:`.stick_slip_modes.break_away`) and
    a jump of the Radau IIA state, its first step the slip's age tau (it about doubles:
    a longer first step let Newton land on a decaying branch of the non-smooth law).
    Returns t [s]."""
    tau = _break_away(y, p, r_kick, ytry)
    t += tau
    rhs(t, y, p, f0)
    st.cnt[NFEV] += 1
    h_first = TAKE_OFF * tau if tau > 0.0 else h0
    jump(st, min(h0, h_first), h_max, t_max - t)
    st.rejected[0] = False
    st.faccon[0] = 1.0
    return t


@njit(**_PHASE, **NO_REFCOUNT)
def _predict(st: RadauState, ws: RadauWork, y) -> None:
    """Newton's start: the last step's polynomial, or after a jump (a kick) the rigid turn
    with the socket, so that Newton corrects only the slip; from z = 0 its linearised
    rotation errs by ~ (omega_p h)^2 omega_p in omega_r, the kicked slip's size for a
    step of the slip's age, and the iteration failed down to h ~ age / 100."""
    z = ws.stage[0]
    if st.have_poly[0]:
        guess_stages(z, ws.event.zacc, st.h[0], st.h_acc[0], True)
        return
    h, fwork = st.h[0], ws.fwork
    for k in range(3):
        ck = C1 if k == 0 else (C2 if k == 1 else 1.0)
        turn_rigidly(y, y[7] * ck * h, fwork)
        for i in range(N_STATE):
            z[k, i] = fwork[i] - y[i]


@njit(**_PHASE, **NO_REFCOUNT)
def _slip_after_step(st: RadauState, y, p, t, f0, armed, took_off, r_stick):
    """The slip mode at an accepted step's end (f0 = f(t, y) evaluated here): whether it
    ends at zero slip, with G_req inside F (stick; `armed` once G_req has left F since the
    breakaway) or outside (a reversal; `took_off` once |omega_r| has passed r_stick
    since the kick). Returns (armed, took_off, to_zero, (wx, wy, wz, r), rate)."""
    inside = _stick_admissible(y, p)
    armed = armed or not inside
    admissible = inside and armed
    rhs(t, y, p, f0)
    st.cnt[NFEV] += 1
    w = _slip(y)
    r = w[3]
    took_off = took_off or r > r_stick
    reversal = took_off and not inside and r <= r_stick
    rate = _slip_rate(y, f0) if admissible or reversal else 0.0
    to_zero = (admissible or reversal) and r <= r_stick and rate < 0.0
    return armed, took_off, to_zero, w, rate


@njit(**_PHASE, **NO_REFCOUNT)
def _to_zero_slip(y, t, w, rate, ytry) -> float:
    """Slip -> stick (or a reversal through zero slip): zero slip at t + tau, tau = r / |r'|;
    the attitude gets the slip's turn omega_r tau / 2 and the spin's omega_p tau (error
    O(r tau^2 |u'|)); the stick mode then zeroes omega_r (with G_req outside F it kicks
    the slip out at once: the rig's creep about X under the Coulomb patch law). Returns t."""
    wx, wy, wz, r = w
    tau = -r / rate
    turn_by(y, 0.5 * tau * wx, 0.5 * tau * wy, 0.5 * tau * wz)
    turn_rigidly(y, y[7] * tau, ytry)
    for i in range(N_STATE):
        y[i] = ytry[i]
    return t + tau


@njit(**_PHASE, **NO_REFCOUNT)
def _stretch_end(y, f0, t, r, r_fast, spin) -> float:
    """End [s] of the next DOP853 stretch of a fast slip |omega_r| = `r` (see
    :func:`_fast_slip`); f0 = f(t, y)."""
    rate_floor = r * spin / (4.0 * math.pi)
    return t + CHUNK * (r - 0.5 * r_fast) / max(abs(_slip_rate(y, f0)), rate_floor)


@njit(**_PHASE, **REFCOUNT)
def _fast_slip(st: RadauState, y, p, scale, f0, t, r, speeds, controls, out, ends):
    """Fast slip: DOP853 stretches (:func:`.dop853.integrate`, the tolerances as given in
    `controls`), each too short for |omega_r| (`r`) to fall to r_fast / 2 at twice its
    present rate of change, floored at |omega_r| omega_p / (4 pi) (a slip that turns with
    the ball changes at ~ omega_p |omega_r|); DOP853's stiffness test stops one should the
    slip still approach zero. `speeds` is (r_fast, omega_p at the start) [rad/s]; `out`
    is (t_eval, i_eval, ts, ys, n_out); `ends` is
    (status, t_event, y_event). Returns (t, ran (a stretch ran), ended (the run ends:
    opened, step limit, non-finite state), status, t_event, i_eval, ts, ys, n_out)."""
    t_max, rtol, atol, _, h_max, max_steps, t_eval, record, terminal, event_tol, _, _ = controls
    t_eval, i_eval, ts, ys, n_out = out
    status, t_event, y_event = ends
    use_eval = t_eval.shape[0] > 0
    r_fast, spin = speeds
    ran = False
    while r >= r_fast and t < t_max:
        t_chunk = _stretch_end(y, f0, t, r, r_fast, spin)
        if t_chunk - t < 2.0 * h_max:
            break
        t_chunk = min(t_chunk, t_max)
        j = i_eval
        while j < t_eval.shape[0] and t_eval[j] <= t_chunk:
            j += 1
        stretch = Controls(
            t_chunk, rtol, atol, min(st.h[0], h_max), h_max, max_steps - st.cnt[N_STEPS],
            t_eval[i_eval:j], record and not use_eval, terminal, event_tol, False, False,
        )  # fmt: skip
        run = dop853_integrate(Problem(y.copy(), p, scale, t), stretch)
        ran = True
        st.cnt[NFEV] += run.nfev
        st.cnt[N_STEPS] += run.n_steps
        st.cnt[N_REJ] += run.n_rejected
        for k in range(0 if use_eval else 1, run.t.shape[0]):  # a recorded stretch
            if use_eval:  # starts with this state
                ts[n_out] = run.t[k]
                ys[n_out, :] = run.y[k]
                n_out += 1
                i_eval += 1
            elif record:
                ts, ys, n_out = append_row(ts, ys, n_out, run.t[k], run.y[k])
        if run.t_event == run.t_event and t_event != t_event:
            t_event = run.t_event
            y_event[:] = run.y_event
        ended = run.status == Status.OPENED or run.status == Status.STEP_LIMIT
        ended = ended or not (run.y_end[0] == run.y_end[0])
        if ended:
            status = run.status
        t = run.t_end
        y[:] = run.y_end
        if ended or run.status != Status.T_MAX:  # STIFF: back to Radau IIA
            return t, ran, ended, status, t_event, i_eval, ts, ys, n_out
        rhs(t, y, p, f0)
        st.cnt[NFEV] += 1
        r = _slip(y)[3]
    return t, ran, False, status, t_event, i_eval, ts, ys, n_out


#: What :func:`_slip_step` asks of the loop: step again (a new Jacobian, factors or a
#: shorter step), end the run as failed, hold the ball through the window, end it at the
#: opening, go on slipping, or stick (zero slip reached); and what :func:`_slip_steps`
#: returns besides: the step limit reached, the last slip to hand to the DOP853 lanes.
_RETRY, _FAILED, _WINDOW, _OPENED, _SLIPPING, _TO_ZERO, _STEP_LIMIT, _HAND_OFF = range(8)


@njit(**_PHASE, **NO_REFCOUNT)
def _slip_step(st: RadauState, ws: RadauWork, t, y, p, scale, controls, modes, speeds, out):
    """One Radau IIA step of the slip mode, from its Jacobian to the mode test at its end.

    `controls` is (t_max, rtol, atol, fnewt, terminal, event_tol) (Radau IIA's
    tolerances), `modes` (g_old, t_event, armed, took_off), `speeds` (r_kick, r_stick)
    [rad/s], `out` (t_eval, i_eval, ts, ys, n_out), outputs at `t_eval` only (the loop
    appends recorded steps). Returns (code, t, t_event, g_old, i_eval, n_out, armed,
    took_off, (wx, wy, wz, |omega_r|), d|omega_r|/dt) with the codes above: ``_TO_ZERO``
    with y already at zero slip (:func:`_to_zero_slip`).
    """
    t_max, rtol_r, atol_r, fnewt, terminal, event_tol = controls
    g_old, t_event, armed, took_off = modes
    r_kick, r_stick = speeds
    t_eval, i_eval, ts, ys, n_out = out
    f0, ytry = ws.f0, ws.event.ytry
    w = (0.0, 0.0, 0.0, 0.0)
    if st.need_jac[0]:  # forward differences far below the slip speed (stick's scale)
        slip_jacobian(t, y, f0, p, scale, ws.jac, ws.scratch[0], ws.fwork, r_kick)
        took_jacobian(st)
    if not factored(st, t, t_max, ws):
        code = _FAILED if underflow(st.h[0], t) else _RETRY
        return code, t, t_event, g_old, i_eval, n_out, armed, took_off, w, 0.0
    _predict(st, ws, y)
    if not attempt(st, ws, t, y, p, scale, rtol_r, atol_r, fnewt):
        code = _WINDOW if underflow(st.h[0], t) else _RETRY
        return code, t, t_event, g_old, i_eval, n_out, armed, took_off, w, 0.0
    t_event, opened, g_new, i_eval, n_out = accepted_outputs(
        st, ws, t, y, p, g_old, t_event, terminal, event_tol, fnewt,
        (t_eval, i_eval, ts, ys, n_out),
    )  # fmt: skip
    if opened:
        return _OPENED, t, t_event, g_old, i_eval, n_out, armed, took_off, w, 0.0
    t = advance(st, ws, t, y)
    if not (y[0] == y[0]):
        return _FAILED, t, t_event, g_new, i_eval, n_out, armed, took_off, w, 0.0
    armed, took_off, to_zero, w, rate = _slip_after_step(st, y, p, t, f0, armed, took_off, r_stick)
    code = _SLIPPING
    if to_zero:
        t, code = _to_zero_slip(y, t, w, rate, ytry), _TO_ZERO
    return code, t, t_event, g_new, i_eval, n_out, armed, took_off, w, rate


# a function of its own, compiled without reference counting (it allocates nothing):
# inlined into the counted loop, every phase's access to the Radau IIA state's arrays was
# wrapped in reference counts (obturator.core.jit_flags), and called once per step from
# it, each call counted the references of every array it passed; here a slip's steps
# run in one call. Same operations in the same order as one step per call.
@njit(cache=True, fastmath=False, error_model="python", **NO_REFCOUNT)
def _slip_steps(st: RadauState, ws: RadauWork, t, y, p, scale, controls, modes, speeds, out, run):
    """Radau IIA steps of the slip mode until the loop has something to do: a code other
    than ``_SLIPPING`` or ``_RETRY`` of :func:`_slip_step`, the step limit
    (``_STEP_LIMIT``), the last slip's hand-off (``_HAND_OFF``), a DOP853 stretch due
    (``_SLIPPING``: :func:`_fast_slip` runs one) or `t_max`; after each accepted step in
    slip, the next step planned and homed in on zero slip.

    `controls`, `modes`, `speeds` and `out` as :func:`_slip_step`; `run` is (max_steps,
    h_max, one_step (return after every accepted step: the loop records it), hand_off,
    r_hand, r_fast, spin). Returns what :func:`_slip_step` does.
    """
    t_max = controls[0]
    max_steps, h_max, one_step, hand_off, r_hand, r_fast, spin = run
    while True:
        if st.cnt[N_STEPS] >= max_steps:
            w = (0.0, 0.0, 0.0, 0.0)
            return _STEP_LIMIT, t, modes[1], modes[0], out[1], out[4], modes[2], modes[3], w, 0.0
        code, t, t_event, g_old, i_eval, n_out, armed, took_off, w, rate = _slip_step(
            st, ws, t, y, p, scale, controls, modes, speeds, out
        )
        modes = (g_old, t_event, armed, took_off)
        out = (out[0], i_eval, out[2], out[3], n_out)
        if code == _RETRY:
            continue
        if code != _SLIPPING:
            return code, t, t_event, g_old, i_eval, n_out, armed, took_off, w, rate
        plan_next(st, h_max)
        if rate < 0.0 and -HOME_IN * w[3] / rate < st.h[0]:  # home in: Newton on |omega_r|(t)
            st.h[0] = -HOME_IN * w[3] / rate
        if hand_off and w[3] >= r_hand and _stick_ratio(y, p) >= HAND_OFF_KAPPA:
            return _HAND_OFF, t, t_event, g_old, i_eval, n_out, armed, took_off, w, rate
        stretch = w[3] >= r_fast and t < t_max
        if (
            one_step
            or not t < t_max
            or (stretch and not _stretch_end(y, ws.f0, t, w[3], r_fast, spin) - t < 2.0 * h_max)
        ):
            return code, t, t_event, g_old, i_eval, n_out, armed, took_off, w, rate


@njit(cache=True, nogil=True, fastmath=False, error_model="python", **REFCOUNT)
def _integrate(problem, controls, stick_slip, kick, cycle_end):
    """The mode loop: closed-form stick phases, Radau IIA slip phases (see module).

    Stops (status ``T_MAX``, ``t_end < t_max``) at the first breakaway at or after
    `cycle_end` [s], before its kick: one cycle of the return map (:mod:`.stick_slip_map`).
    """
    p, scale = problem.p, problem.scale
    t_max, rtol, atol, h0, h_max, max_steps, t_eval, record, terminal, event_tol, _, _ = controls
    t, y, ts, ys, n_out, y_event = start(problem, controls)
    ws = work_with(y_event)
    f0, ytry = ws.f0, ws.event.ytry
    use_eval = t_eval.shape[0] > 0
    i_eval = 0
    status = Status.T_MAX
    t_event = math.nan
    unit = slip_speed_unit(p, h_max)
    r_fast, r_hand = unit * FAST_SLIP, unit * HAND_OFF_SLIP
    hand_off = controls.last_slip_to_lanes and p[P_KERNEL] == KERNEL_THESIS
    # Radau IIA at auto's fraction of the tolerances (near-stick t_cr amplifies its
    # local errors), transformed as RADAU5 does; DOP853 stretches take them as given
    f = AUTO_RADAU_TOL_FACTOR
    rtol_r, atol_r, fnewt = radau5_tolerances(rtol * f, atol * f)
    spin = abs(y[7]) if y[7] != 0.0 else 1.0
    r_stick, r_kick = stick_slip * spin, kick * spin
    sticking = _slip(y)[3] <= r_stick and _stick_admissible(y, p)
    st = new_state(min(h0, h_max, t_max - t))
    armed = True  # re-stick allowed (after a breakaway: once G_req has left F)
    took_off = True  # a reversal allowed (after a kick: once |omega_r| has passed r_stick)
    if not sticking:
        t = _release(st, y, p, t, f0, ytry)
    g_old = nutation_angle_of_state(y, p) - p[P_THETA_CR]
    while t < t_max:
        if sticking:
            t, exit_angle, i_eval, ts, ys, n_out = _stick(
                y, p, t, t_max, record, (t_eval, i_eval, ts, ys, n_out), ytry
            )
            if t >= t_max or (t >= cycle_end and exit_angle >= 0.0):
                break
            t = _kick(st, y, p, t, t_max, h0, h_max, r_kick, f0, ytry)
            sticking, armed, took_off = False, False, False
            g_old = nutation_angle_of_state(y, p) - p[P_THETA_CR]
            continue
        code, t, t_event, g_old, i_eval, n_out, armed, took_off, w, rate = _slip_steps(
            st, ws, t, y, p, scale, (t_max, rtol_r, atol_r, fnewt, terminal, event_tol),
            (g_old, t_event, armed, took_off), (r_kick, r_stick), (t_eval, i_eval, ts, ys, n_out),
            (max_steps, h_max, record and not use_eval, hand_off, r_hand, r_fast, spin),
        )  # fmt: skip
        if code == _STEP_LIMIT:
            status = Status.STEP_LIMIT
            break
        if code == _FAILED:
            status = Status.FAILED
            break
        if code == _WINDOW:  # a kicked slip that cannot take off
            t_w, i_eval, n_out = _through_window(
                y, p, t, t_max, r_kick, ytry, ts, ys, n_out, t_eval, i_eval
            )
            if t_w < 0.0:
                status = Status.FAILED
                break
            t, sticking = t_w, True
            continue
        if code == _OPENED:
            status = Status.OPENED
            ts, ys, n_out = record_row(ts, ys, n_out, t_event, y_event, record, use_eval)
            y[:] = y_event
            t = t_event
            break
        sticking = code == _TO_ZERO
        if record and not use_eval:
            ts, ys, n_out = append_row(ts, ys, n_out, t, y)
        if sticking:
            continue
        if code == _HAND_OFF:
            status = NONSTIFF_SIGNAL  # the last slip, for the DOP853 lanes
            break
        t, ran, ended, status, t_event, i_eval, ts, ys, n_out = _fast_slip(
            st, y, p, scale, f0, t, w[3], (r_fast, spin), controls, (t_eval, i_eval, ts, ys, n_out),
            (status, t_event, y_event),
        )  # fmt: skip
        if ended:
            break
        if ran:
            rhs(t, y, p, f0)
            st.cnt[NFEV] += 1
            jump(st, st.h[0], h_max, t_max - t)
            g_old = nutation_angle_of_state(y, p) - p[P_THETA_CR]
    c = st.cnt
    return RawSolution(
        status, t_event, y_event, ts[:n_out], ys[:n_out], c[0], c[1], c[2], c[3], t, y
    )
