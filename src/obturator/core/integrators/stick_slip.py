"""Event-driven stick-slip integration of the friction laws, with no width.

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
  integrated by fifth-order Radau IIA (the steps, Newton iteration, error estimate and
  opening-event location of :mod:`.radau`, at ``auto``'s third of the tolerances).
  Above |omega_r| = :data:`FAST_SLIP` (M / A) h_max the direction is resolved by the
  largest step and the slip runs in DOP853 stretches (:mod:`.dop853`, the tolerances
  as given), each short enough that |omega_r| cannot fall below half that level at
  twice its present rate of change; DOP853's stiffness test (status ``STIFF``) hands
  back to Radau IIA otherwise.

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
* hand-off: with ``controls.hand_back`` (a study's points, t_cr only) a slip past
  :data:`~.stick_slip_modes.HAND_OFF_KAPPA` and :data:`~.stick_slip_modes.HAND_OFF_SLIP`,
  where the ball no longer sticks, stops the run (``NONSTIFF``) for :mod:`.stick_slip_lanes`.

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
from .common import append_row, record_row, rms_norm, start, underflow
from .contract import Controls, Problem, RawSolution, Status
from .dop853 import integrate as dop853_integrate
from .linalg import lu_solve
from .radau import (
    _UROUND,
    EventWork,
    _colloc_weights,
    _dense,
    _factor,
    _newton,
    locate_opening_at,
)
from .radau_coefficients import C1, C2, E1, E2, E3
from .radau_control import _LIM_SHRINK, next_step, step_quotient
from .stick_slip_jacobian import slip_jacobian
from .stick_slip_modes import (
    HAND_OFF_KAPPA,
    HAND_OFF_SLIP,
    HOLD_THROUGH,
    REKICK,
    check_set_valued_law,
    slip_speed_unit,
    stick_ratio,
)
from .stick_slip_modes import break_away as _break_away
from .stick_slip_modes import slip as _slip
from .stick_slip_modes import slip_rate as _slip_rate
from .stick_slip_modes import stick_admissible as _stick_admissible
from .stick_slip_modes import through_window as _through_window

__all__ = [
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

#: Slip speed, in units of |omega_p|, at which a decaying slip with G_req inside F
#: becomes stick.
STICK_SLIP = 1e-6
#: Slip speed, in units of |omega_p|, given at breakaway (along -G_req / |G_req|).
#: 1e-9 let Radau IIA hover at the kick's level for ~100 steps in the wide windows
#: near theta = 49 deg (40 rad/s), and rounding alone then decided whether a window
#: slipped in full (t_cr moved by a whole cycle, 1.9e-3, between two equivalent
#: starts); at 1e-8 and 1e-7 it took off in every window tried.
KICK = 1e-8
#: The kick at release (zero slip, G_req outside F: flight, the rig at some azimuths),
#: where G_req is well outside F and the slip takes off at once: 1e-9 as before (at 1e-8
#: the flight t_cr moved by up to 4e-8 at rtol 1e-9, by 3e-7 at rtol 1e-8, Mach 3).
RELEASE_KICK = 1e-9
#: Fraction of the predicted time to zero slip taken as the step when homing in. The
#: slip, and with it the stiffness of its direction, changes about 1 / (1 - HOME_IN)
#: fold across such a step: at 0.98 the simplified Newton iteration failed on most of
#: them (40 rad/s: 566 rejected steps against 375 at 0.5; right-hand sides -4 %).
HOME_IN = 0.5
#: Slip speed above which slip is integrated by DOP853, in units of (M / A) h_max: the
#: slip direction relaxes at ~ M / (A |omega_r|), so there h_max resolves it.
FAST_SLIP = 4.0
#: First Radau IIA step after a breakaway, in units of the kicked slip's age (the time
#: from the exit of F to the kick).
TAKE_OFF = 1.0
#: Fraction of |omega_r| / |omega_r'| that one DOP853 stretch may last.
_CHUNK = 0.5


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


@njit(cache=True, inline="always", **NO_REFCOUNT)
def _fresh_radau(h: float, h_max: float, t_left: float) -> tuple:
    """Radau IIA state after a mode change or a DOP853 stretch: (h, h_lu, need_jac,
    have_poly, first, h_lim), no collocation polynomial or Jacobian carried over."""
    return min(h, h_max, t_left), math.nan, True, False, True, math.inf


@njit(cache=True, nogil=True, fastmath={"contract"}, error_model="python", **REFCOUNT)
def _integrate(problem, controls, stick_slip, kick, cycle_end):
    """The mode loop: closed-form stick phases, Radau IIA slip phases (see module).

    Stops (status ``T_MAX``, ``t_end < t_max``) at the first breakaway at or after
    `cycle_end` [s], before its kick: one cycle of the return map (:mod:`.stick_slip_map`).
    """
    p, scale = problem.p, problem.scale
    t_max, rtol, atol, h0, h_max, max_steps, t_eval, record, terminal, event_tol, _ = controls
    hand_off = controls.hand_back and p[P_KERNEL] == KERNEL_THESIS  # to stick_slip_lanes
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
    zacc = np.zeros((3, n))
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
    stage_ev = (zev, wev, f)
    ev = EventWork(zacc, stage_ev, lu, scratch, ytry, y_event)
    n_eval = t_eval.shape[0]
    use_eval = n_eval > 0
    i_eval = 0
    nfev = 0
    njev = 0
    n_steps = 0
    n_rej = 0
    status = Status.T_MAX
    t_event = math.nan
    rtol0, atol0 = rtol, atol  # DOP853 stretches take the tolerances as given
    unit = slip_speed_unit(p, h_max)
    r_fast, r_hand = unit * FAST_SLIP, unit * HAND_OFF_SLIP
    # Radau IIA at auto's fraction of the tolerances (near-stick t_cr amplifies its
    # local errors), transformed as RADAU5 does (as in .radau)
    rtol *= AUTO_RADAU_TOL_FACTOR
    atol *= AUTO_RADAU_TOL_FACTOR
    quot_tol = atol / rtol
    rtol = 0.1 * rtol ** (2.0 / 3.0)
    atol = rtol * quot_tol
    fnewt = max(10.0 * _UROUND / rtol, min(0.03, math.sqrt(rtol)))
    spin = abs(y[7]) if y[7] != 0.0 else 1.0
    r_stick = stick_slip * spin
    r_kick = kick * spin
    r0 = _slip(y)[3]
    sticking = r0 <= r_stick and _stick_admissible(y, p)
    # slip-phase state of the Radau IIA steps
    h = min(h0, h_max, t_max - t)
    h_lu = math.nan
    need_jac = True
    jac_fresh = False
    have_poly = False
    h_acc = 0.0
    first = True
    rejected = False
    faccon = 1.0
    h_gus = 0.0
    err_gus = 1.0
    h_lim = math.inf
    theta = 0.0
    armed = True  # re-stick allowed (after a breakaway: once G_req has left F)
    took_off = True  # a reversal allowed (after a kick: once |omega_r| has passed r_stick)
    if not sticking:
        r_release = RELEASE_KICK * spin
        if r0 < r_release:  # released at (or near) zero slip with G_req outside F
            tau = _break_away(y, p, r_release, ytry)
            t += tau
            if tau > 0.0:
                h = min(h, TAKE_OFF * tau)
        rhs(t, y, p, f0)
        nfev += 1
    g_old = nutation_angle_of_state(y, p) - theta_cr
    while t < t_max:
        if sticking:
            wp = y[7]
            hold_stick(y, wp)
            exit_angle = breakaway_angle(y, p, wp)  # < 0: a re-kick inside a window
            angle = max(exit_angle, 0.0)
            t_b = min(t + angle / abs(wp), t_max) if wp != 0.0 else t_max
            if use_eval:
                while i_eval < n_eval and t_eval[i_eval] <= t_b:
                    turn_rigidly(y, wp * (t_eval[i_eval] - t), ytry)
                    ts[n_out] = t_eval[i_eval]
                    ys[n_out, :] = ytry
                    n_out += 1
                    i_eval += 1
            turn_rigidly(y, wp * (t_b - t), ytry)
            y[:] = ytry
            t = t_b
            if record and not use_eval:
                ts, ys, n_out = append_row(ts, ys, n_out, t, y)
            if t >= t_max or (t >= cycle_end and exit_angle >= 0.0):
                break
            tau = _break_away(y, p, r_kick, ytry)
            t += tau
            sticking = False
            armed = False
            took_off = False
            rhs(t, y, p, f0)
            nfev += 1
            # first step: the slip's age tau (it about doubles): a longer first step
            # let Newton land on a decaying branch of the non-smooth law (seen at
            # 40 rad/s, one window in ~500 lost by rounding alone)
            h_first = TAKE_OFF * tau if tau > 0.0 else h0
            h, h_lu, need_jac, have_poly, first, h_lim = _fresh_radau(
                min(h0, h_first), h_max, t_max - t
            )
            rejected = False
            faccon = 1.0
            g_old = nutation_angle_of_state(y, p) - theta_cr
            continue
        if n_steps >= max_steps:
            status = Status.STEP_LIMIT
            break
        if need_jac:
            # forward differences far below the slip speed (the law's scale near stick)
            slip_jacobian(t, y, f0, p, scale, jac, work, fwork, r_kick)
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
        for i in range(n):
            scal[i] = 1.0 / (atol * scale[i] + rtol * abs(y[i]))
        if have_poly:
            for k in range(3):
                ck = C1 if k == 0 else (C2 if k == 1 else 1.0)
                l1, l2, l3 = _colloc_weights(1.0 + ck * h / h_acc)
                for i in range(n):
                    z[k, i] = l1 * zacc[0, i] + l2 * zacc[1, i] + l3 * zacc[2, i] - zacc[2, i]
        else:
            # no polynomial yet (after a kick): predict the rigid turn with the socket,
            # so that Newton corrects only the slip; from z = 0 its linearised rotation
            # errs by ~ (omega_p h)^2 omega_p in omega_r, the kicked slip's size for a
            # step of the slip's age, and the iteration failed down to h ~ age / 100
            for k in range(3):
                ck = C1 if k == 0 else (C2 if k == 1 else 1.0)
                turn_rigidly(y, y[7] * ck * h, fwork)
                for i in range(n):
                    z[k, i] = fwork[i] - y[i]
        ok, newt, theta, faccon, hfac = _newton(t, y, h, p, scal, stage, lu, scratch, faccon, fnewt)
        nfev += 3 * newt
        if not ok:
            h_lim = min(h_lim, h * _LIM_SHRINK)
            n_rej += 1
            rejected = True
            h *= hfac
            if not jac_fresh:
                need_jac = True
            if underflow(h, t):
                t_w, i_eval, n_out = _through_window(
                    y, p, t, t_max, r_kick, ytry, ts, ys, n_out, t_eval, i_eval
                )
                if t_w < 0.0:
                    status = Status.FAILED
                    break
                t = t_w
                sticking = True
                continue
            continue
        for i in range(n):
            ynew[i] = y[i] + z[2, i]
            err_v[i] = f0[i] + (E1 * z[0, i] + E2 * z[1, i] + E3 * z[2, i]) / h
        for i in range(n):
            work[i] = err_v[i]
        lu_solve(lu_r, piv_r, work)
        err = rms_norm(work, y, ynew, rtol, atol, scale)
        if err >= 1.0 and (first or rejected):
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
                t_w, i_eval, n_out = _through_window(
                    y, p, t, t_max, r_kick, ytry, ts, ys, n_out, t_eval, i_eval
                )
                if t_w < 0.0:
                    status = Status.FAILED
                    break
                t = t_w
                sticking = True
                continue
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
                h_lu = math.nan
                t_event = t_ev
                if terminal:
                    status = Status.OPENED
                    t_stop = t_event
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
        n_steps += 1
        if not (y[0] == y[0]):
            status = Status.FAILED
            break
        inside = _stick_admissible(y, p)
        armed = armed or not inside
        admissible = inside and armed
        rhs(t, y, p, f0)
        nfev += 1
        wx, wy, wz, r = _slip(y)
        took_off = took_off or r > r_stick
        reversal = took_off and not inside and r <= r_stick
        rate = _slip_rate(y, f0) if admissible or reversal else 0.0
        if (admissible or reversal) and r <= r_stick and rate < 0.0:
            # zero slip at t + tau, tau = r / |r'|; the attitude gets the slip's turn
            # omega_r tau / 2 and the spin's omega_p tau (error O(r tau^2 |u'|)). With
            # G_req inside F that is stick; outside, a reversal through zero slip (the
            # rig's creep about X under the Coulomb patch law, twice a revolution): the
            # stick branch finds G_req outside F and kicks the slip out at once
            tau = -r / rate
            turn_by(y, 0.5 * tau * wx, 0.5 * tau * wy, 0.5 * tau * wz)
            turn_rigidly(y, y[7] * tau, ytry)
            y[:] = ytry
            t += tau
            sticking = True  # hold_stick zeroes omega_r at the top of the loop
            if record and not use_eval:
                ts, ys, n_out = append_row(ts, ys, n_out, t, y)
            continue
        if record and not use_eval:
            ts, ys, n_out = append_row(ts, ys, n_out, t, y)
        h, h_lim, slow = next_step(h, h_new, h_lim, h_max, rejected, theta)
        need_jac = need_jac or slow
        if rate < 0.0 and -HOME_IN * r / rate < h:  # home in: Newton on |omega_r|(t)
            h = -HOME_IN * r / rate
        first = False
        rejected = False
        jac_fresh = False
        if hand_off and r >= r_hand and stick_ratio(y, p) >= HAND_OFF_KAPPA:
            status = Status.NONSTIFF
            break
        # fast slip: DOP853 stretches, each too short for |omega_r| to fall to r_fast / 2
        # at twice its present rate of change, floored at |omega_r| omega_p / (4 pi) (a
        # slip that turns with the ball changes at ~ omega_p |omega_r|); DOP853's own
        # stiffness test stops one should the slip still approach zero
        stretched = False
        done = False
        while r >= r_fast and t < t_max:
            rate_floor = r * spin / (4.0 * math.pi)
            t_chunk = t + _CHUNK * (r - 0.5 * r_fast) / max(abs(_slip_rate(y, f0)), rate_floor)
            if t_chunk - t < 2.0 * h_max:
                break
            t_chunk = min(t_chunk, t_max)
            j = i_eval
            while j < n_eval and t_eval[j] <= t_chunk:
                j += 1
            stretch = Controls(
                t_chunk, rtol0, atol0, min(h, h_max), h_max, max_steps - n_steps,
                t_eval[i_eval:j], record and not use_eval, terminal, event_tol, False,
            )  # fmt: skip
            out = dop853_integrate(Problem(y.copy(), p, scale, t), stretch)
            stretched = True
            nfev += out.nfev
            n_steps += out.n_steps
            n_rej += out.n_rejected
            k0 = 0 if use_eval else 1  # a recorded stretch starts with this state
            for k in range(k0, out.t.shape[0]):
                if use_eval:
                    ts[n_out] = out.t[k]
                    ys[n_out, :] = out.y[k]
                    n_out += 1
                    i_eval += 1
                elif record:
                    ts, ys, n_out = append_row(ts, ys, n_out, out.t[k], out.y[k])
            if out.t_event == out.t_event and t_event != t_event:
                t_event = out.t_event
                y_event[:] = out.y_event
            if out.status == Status.OPENED:
                status = Status.OPENED
                done = True
            elif not (out.y_end[0] == out.y_end[0]) or out.status == Status.STEP_LIMIT:
                status = out.status
                done = True
            t = out.t_end
            y[:] = out.y_end
            if done or out.status != Status.T_MAX:  # STIFF: back to Radau IIA
                break
            rhs(t, y, p, f0)
            nfev += 1
            r = _slip(y)[3]
        if done:
            break
        if stretched:
            rhs(t, y, p, f0)
            nfev += 1
            h, h_lu, need_jac, have_poly, first, h_lim = _fresh_radau(h, h_max, t_max - t)
            g_old = nutation_angle_of_state(y, p) - theta_cr
    return RawSolution(
        status, t_event, y_event, ts[:n_out], ys[:n_out], nfev, njev, n_steps, n_rej, t, y
    )
