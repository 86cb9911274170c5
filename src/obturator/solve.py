"""Solving the equations of motion: the only place integrators live.

:func:`simulate` integrates one :class:`Case` to the opening event
theta = theta_cr (thesis: theta_cr = beta_s) and returns a
:class:`NutationResult`; :func:`opening_time` returns t_cr alone (no time
series stored), which is what sweeps and fits call.

Numerics: at release the ball co-rotates, omega_r = 0, and the sliding-friction
direction is 0/0; near sticking the friction torque is extremely stiff. Only
the magnitude of the friction torque is regularised (width delta [rad/s], one
of three families; see :func:`obturator.dynamics.applied_torque`); the thesis's
moment arm always uses the true slip direction. Integration is compiled: an
explicit Dormand-Prince 8(5,3) pair by default, which hands the run to a
fifth-order Radau IIA method when it detects stiffness (Radau's Newton
iterations cope with the strongly nonlinear stiffness of near-stick phases),
and back once the ball slides again; Radau alone or an L-stable Rosenbrock pair
can be chosen; the opening event is located by re-stepping to 1e-12 s.
:func:`convergence_check` reruns a case with tighter tolerances, a narrower width
and another regularisation family.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from .core.dynamics import observables
from .core.integrators import Controls, Problem, RawSolution, integrate
from .core.layout import (
    FAMILY_CODES,
    FORM_CODES,
    N_PARAM,
    N_STATE,
    P_A,
    P_C,
    P_FAMILY,
    P_FORM,
    P_IP,
    P_KE0,
    P_SPEED,
    P_SPIN_MODE,
    P_THETA_CR,
    P_VISC,
    P_WIDTH,
    SPIN_CODES,
)
from .core.specialised import specialise
from .errors import InputError, SolverError, check_range
from .model.case import Case
from .result import NutationResult
from .status import MESSAGES, Status
from .vocab import (
    FORMULATIONS,
    FRICTION_FAMILIES,
    METHODS,
    Formulation,
    FrictionFamily,
    Method,
    check_choice,
)

__all__ = [
    "SolverOptions",
    "simulate",
    "opening_time",
    "convergence_check",
    "ConvergenceCheck",
    "alternative_family",
    "pack_parameters",
    "error_scale",
    "OPENING_TIME_ACCURACY",
    "MAX_STEP_PERIODS",
    "MAX_STEP_PERIODS_SHARP",
    "max_step_periods",
    "tolerances_for_opening_time",
    "integration_controls",
    "integration_setup",
]


@dataclass(frozen=True)
class SolverOptions:
    """Integrator settings.

    Parameters
    ----------
    rtol : float
        Relative tolerance, in [1e-12, 0.1) (smaller values cannot be honoured
        in double precision by the integrators' error norms).
    atol : float
        Absolute tolerance on the quaternion components and on rates measured
        in units of the initial spin omega_p0 (so it is scale-free).
    friction_width : float
        Regularisation width of the Coulomb magnitude, relative to the initial
        spin: delta = friction_width * omega_p0 [rad/s]. Default 1e-7: t_cr
        converges about linearly in delta, and at low spin (long near-stick
        phases, e.g. 40-100 rad/s on the rig) 1e-6 still leaves ~1e-3
        relative; 1e-7 leaves <= 2e-4 there (tests/test_convergence.py). Keep
        ``atol`` well below the width (both are in units of omega_p0): the
        integrator must resolve slip speeds of order delta.
    friction_family : {"algebraic", "tanh", "linear"}
        Shape of the regularised magnitude s(|omega_r|/delta):
        x/sqrt(1+x^2) (default), tanh(x) or min(x, 1). Only the magnitude is
        regularised; the thesis's moment arm always uses the true slip
        direction. :func:`convergence_check` reruns with another family.
    formulation : {"quaternion", "euler"}
        Singularity-free quaternion form (default) or the thesis's Euler angles.
    max_steps : int
        Step limit (status 2 when reached).
    event_tol : float
        Bracket width at which the opening time is accepted [s].
    max_step : float or None
        Largest step [s]; default :func:`max_step_periods` of a spin period (a
        twentieth on the rig, a tenth in flight).
    method : {"auto", "radau", "rosenbrock", "set-valued"}
        Compiled integrator. ``"auto"`` (default): the explicit eighth-order
        Dormand-Prince pair DOP853 (no Jacobian; the problem is not stiff
        outside sticking), handing the run over to Radau IIA (at a third of the
        tolerances) from its last accepted state when DOP853 detects stiffness
        (Hairer's h*lambda test, or more than 200 steps per spin period plus 1000,
        or a step size collapse), and back to DOP853 from Radau's last accepted
        step once the slip speed has stayed above 1e4 regularisation widths for half
        a revolution (the stick-slip phase is over; at most
        :data:`~obturator.core.integrators.AUTO_HAND_BACKS` times); counters add up.
        t_cr errors at rtol 1e-8: median
        ~5e-9, worst 3.0e-7 relative at 100-1000 rad/s, up to 1.6e-3 in the long
        near-stick runs below 100 rad/s (:data:`OPENING_TIME_ACCURACY`; rtol 3e-9 keeps
        them below 5e-6, rtol 1e-10 below 1.5e-7). ``"radau"``:
        the fifth-order Radau IIA collocation method (Newton iterations follow the nonlinear
        stiffness of sticking, 8-15x faster than Rosenbrock on the thesis cases
        and ~1e2-1e4x fewer steps in long sticking phases). ``"rosenbrock"``:
        the L-stable Rosenbrock pair of Shampine (ode23s). Radau transforms rtol as RADAU5 does
        (0.1 rtol^(2/3)); t_cr errors stay below ~3e-7 relative at rtol 1e-8.
        ``"set-valued"``: the thesis law with no width (``friction_width`` and
        ``friction_family`` unused): exact stick and event-driven transitions
        (:mod:`obturator.core.integrators.stick_slip`, ``docs/stick_slip.md``); quaternion
        form, thesis friction, constant or free spin. :func:`convergence_check` then
        compares with the regularised path (``"auto"``) at the narrower width, both
        families.
    """

    rtol: float = 1e-8
    atol: float = 1e-10
    friction_width: float = 1e-7
    friction_family: FrictionFamily = "algebraic"
    formulation: Formulation = "quaternion"
    max_steps: int = 20_000_000
    event_tol: float = 1e-12
    max_step: float | None = None
    method: Method = "auto"

    def __post_init__(self) -> None:
        # DOP853 works at 0.01 rtol, floored at 1e-14: a smaller rtol would be clamped.
        check_range("rtol", self.rtol, 1e-12, 0.1, hi_open=True)
        check_range("atol", self.atol, 0.0, 1.0, lo_open=True)
        check_range("friction_width", self.friction_width, 0.0, 1.0, lo_open=True)
        check_choice("friction_family", self.friction_family, FRICTION_FAMILIES)
        check_choice("formulation", self.formulation, FORMULATIONS)
        if int(self.max_steps) < 1:
            raise InputError("max_steps", f"{self.max_steps} is outside the allowed range >= 1")
        check_range("event_tol", self.event_tol, 0.0, 1e-3, lo_open=True, unit="s")
        check_choice("method", self.method, METHODS)
        if self.max_step is not None:
            check_range("max_step", self.max_step, 0.0, math.inf, lo_open=True, unit="s")

    @classmethod
    def for_opening_time_accuracy(cls, tcr_rtol: float, **kw: Any) -> SolverOptions:
        """Options whose t_cr is accurate to `tcr_rtol` (relative) on the measured cases.

        The tolerances come from :data:`OPENING_TIME_ACCURACY`, the loosest whose
        measured worst t_cr error, times a safety factor of 3, is within
        `tcr_rtol` over the rig at 40-1000 rad/s; the long near-stick runs below
        100 rad/s set it (above 100 rad/s the default rtol 1e-8 is within 3.0e-7).
        Looser requests get rtol 1e-8 too (the default): at rtol 3e-8 the
        10,000-point rig sweep over 100-700 rad/s already has a worst error of 6.6e-5
        (near stick, 11 points beyond 1e-6) for 4 % less time.

        Parameters
        ----------
        tcr_rtol : float
            Requested relative accuracy of t_cr, >= 4.5e-7 [-].
        **kw
            Other :class:`SolverOptions` fields (not ``rtol``/``atol``).
        """
        rtol = tolerances_for_opening_time(tcr_rtol)
        return cls(rtol=rtol, atol=rtol * 1e-2, **kw)

    def tighter(self, factor: float = 10.0) -> SolverOptions:
        """Both tolerances divided by `factor` (for convergence studies)."""
        return replace(self, rtol=self.rtol / factor, atol=self.atol / factor)


#: (t_cr accuracy, rtol): rtol (atol = rtol/100) whose worst relative t_cr error,
#: times 3, is within that accuracy. Measured against Radau IIA at rtol 1e-12 (at
#: 1e-11 it is itself up to 1e-7 off near stick) on the rig at mu_s 0.5473 (default
#: width and family), every point of two sweeps through the sweep path and through the
#: one-trajectory path (``python -m benchmarks.dense_accuracy``, which reports both):
#: 10,000 points over 100-700 rad/s and 241 over 40-100 rad/s (the long near-stick
#: runs, t_cr 0.6-43 s); plus 13 fixed spins and 100 random ones over 40-1000 rad/s and
#: the flight case at Mach 1.5-4, mu_s 0.35 and 0.5473. Worst errors of either path
#: (40-100 rad/s; 100-1000 rad/s): rtol 1e-8: 1.6e-3 (the one-trajectory path at 42.5
#: rad/s, t_cr 31.6 s; the sweep path's worst 1.6e-4); 3.0e-7. 3e-9: 4.8e-6; 1.5e-7.
#: 1e-9: 3.5e-6; 6.3e-8. 1e-10: 1.5e-7; 5.0e-8 (the reference's own floor is ~2e-8).
#: Flight errors are <= 4e-10. The low band sets every entry. Each is the worst of
#: several measurements that differ only in rounding (the right-hand side before and
#: after its rewrite with one square root, the compiled code before and after ``auto``
#: learned to go back to DOP853, the sweep's vectorised Radau IIA and the scalar one):
#: near stick, stick-slip over hundreds of revolutions amplifies rounding, so at rtol
#: 1e-8 single points scatter by 1e-4..1e-3 from one such variant to the next, at
#: 1e-10 by less than 1e-7. (Until release 0.3 the table was taken from the sweep path
#: alone, and its rtol 1e-8 entry, 4.8e-4, did not hold for the one-trajectory path.)
OPENING_TIME_ACCURACY: tuple[tuple[float, float], ...] = (
    (4.9e-3, 1e-8),
    (1.5e-5, 3e-9),
    (1.1e-5, 1e-9),
    (4.5e-7, 1e-10),
)


#: Largest default step, in spin periods: a tenth, and :data:`MAX_STEP_PERIODS_SHARP`
#: where the friction torque's moment arm vanishes in some slip direction (the rig's
#: single bottom contact; :func:`max_step_periods`).
MAX_STEP_PERIODS = 0.1
#: With a tenth on the rig, DOP853 now and then took a step of that length across the
#: sharp minimum of the moment arm (Eq. 61: sqrt(1 - u_X^2), small while omega_r
#: points near the gravity axis X, twice per revolution) with an error estimate that
#: missed it: isolated t_cr outliers of up to 8e-7 at rtol 1e-8 (0.3 % of a
#: 10,000-point rig sweep over 100-700 rad/s, the state error jumping 300x in one step)
#: where neighbouring spins were within ~3e-9. A twentieth cut the worst to 3e-7
#: (1.2e-7 -> 1.7e-8 at rtol 1e-9) for ~10 % more DOP853 work. In flight (no such
#: minimum) it only doubled the steps.
MAX_STEP_PERIODS_SHARP = 0.05


def max_step_periods(case: Case) -> float:
    """Largest default step of `case`, in spin periods (see :data:`MAX_STEP_PERIODS`)."""
    friction = case.torque.friction
    sharp = friction is not None and friction.arm_vanishes
    return MAX_STEP_PERIODS_SHARP if sharp else MAX_STEP_PERIODS


def tolerances_for_opening_time(tcr_rtol: float) -> float:
    """rtol for a requested relative t_cr accuracy (see :data:`OPENING_TIME_ACCURACY`).

    Raises
    ------
    InputError
        `tcr_rtol` outside [4.5e-7, 0.1].
    """
    check_range("tcr_rtol", tcr_rtol, OPENING_TIME_ACCURACY[-1][0], 0.1)
    for accuracy, rtol in OPENING_TIME_ACCURACY:
        if tcr_rtol >= accuracy:
            return rtol
    raise AssertionError("unreachable")  # pragma: no cover


def pack_parameters(case: Case, options: SolverOptions, y0: np.ndarray | None = None) -> np.ndarray:
    """Flat float parameter vector for the compiled right-hand side."""
    ball = case.ball
    a, c = ball.transverse_inertia, ball.axial_inertia
    if y0 is None:
        y0 = case.initial_state(options.formulation)
    p = np.zeros(N_PARAM)
    p[P_A], p[P_C], p[P_IP] = a, c, case.projectile_inertia
    p[P_SPIN_MODE] = SPIN_CODES[case.spin_mode]
    p[P_FORM] = FORM_CODES[options.formulation]
    p[P_WIDTH] = options.friction_width * case.spin_rate
    p[P_THETA_CR] = case.opening_angle
    p[P_VISC:P_FAMILY] = case.torque.pack()
    p[P_SPEED : P_SPEED + 3] = case.torque.speed_law.pack()
    p[P_FAMILY] = FAMILY_CODES[options.friction_family]
    # total kinetic energy, read by the thesis's energy form only (Appendix A, C(4));
    # elsewhere it stays 0, so that packing calls no compiled code (a process that has
    # not loaded numba packs points in ~30 us, obturator.sweeps.ahead)
    if case.spin_mode == "thesis-energy":
        obs = observables(y0[None, :], p)
        p[P_KE0] = obs[0, 5] + 0.5 * case.projectile_inertia * case.spin_rate**2
    return specialise(p)


def error_scale(case: Case, formulation: str) -> np.ndarray:
    """Component scales of the error weights: 1 for angles, omega_p0 for rates."""
    w = case.spin_rate
    if formulation == "euler":
        return np.array([1.0, w, 1.0, w, 1.0, w, w, 1.0])
    return np.array([1.0, 1.0, 1.0, 1.0, w, w, w, w])


def integration_controls(
    options: SolverOptions,
    t_max: float,
    h0: float,
    h_max: float,
    *,
    t_eval: np.ndarray | None = None,
    record: bool = False,
    terminal: bool = True,
) -> Controls:
    """The :class:`Controls` of `options` for a run to `t_max` [s] with initial step `h0`
    and largest step `h_max` [s] (as :func:`integration_setup` derives them from a case;
    the batched lanes rebuild them from their packed arrays)."""
    return Controls(
        t_max=t_max,
        rtol=options.rtol,
        atol=options.atol,
        h0=h0,
        h_max=h_max,
        max_steps=int(options.max_steps),
        t_eval=np.empty(0) if t_eval is None else t_eval,
        record=record,
        terminal=terminal,
        event_tol=options.event_tol,
    )


def integration_setup(
    case: Case,
    options: SolverOptions,
    y0: np.ndarray | None = None,
    *,
    record: bool = False,
    t_eval: np.ndarray | None = None,
    terminal: bool = True,
) -> tuple[Problem, Controls]:
    """What the compiled integrators take for one case: the packed problem and controls.

    The initial step is 1e-4 spin periods and the largest ``options.max_step`` or
    :func:`max_step_periods` of a period. Shared by the one-trajectory path and the batched lanes
    (:mod:`obturator.sweeps.batch`), so both start from the same numbers.

    Raises
    ------
    InputError
        `y0` not of shape (8,), or `t_eval` not non-negative and increasing.
    """
    if y0 is None:
        y0 = case.initial_state(options.formulation)
    y0 = np.asarray(y0, dtype=float)
    if y0.shape != (N_STATE,):
        raise InputError("y0", f"expected shape ({N_STATE},), got {y0.shape}")
    period = 2.0 * math.pi / case.spin_rate
    te = np.empty(0) if t_eval is None else np.asarray(t_eval, dtype=float)
    if te.size and (np.any(np.diff(te) < 0) or te[0] < 0):
        raise InputError("t_eval", "times must be non-negative and increasing")
    controls = integration_controls(
        options,
        float(case.t_max),
        1e-4 * period,
        options.max_step if options.max_step is not None else max_step_periods(case) * period,
        t_eval=te,
        record=record,
        terminal=terminal,
    )
    p = pack_parameters(case, options, y0)
    return Problem(y0, p, error_scale(case, options.formulation)), controls


def _run(
    case: Case,
    options: SolverOptions,
    y0: np.ndarray | None,
    record: bool,
    t_eval: np.ndarray | None,
    terminal: bool,
) -> tuple[np.ndarray, RawSolution]:
    """Pack the case, call the compiled integrator; return the parameters and its solution."""
    problem, controls = integration_setup(
        case, options, y0, record=record, t_eval=t_eval, terminal=terminal
    )
    return problem.p, integrate(options.method, problem, controls)


def simulate(
    case: Case,
    options: SolverOptions | None = None,
    *,
    y0: np.ndarray | None = None,
    t_eval: np.ndarray | None = None,
    terminal: bool = True,
) -> NutationResult:
    """Integrate one case and return its time history and opening time t_cr.

    Parameters
    ----------
    case : Case
    options : SolverOptions, optional
    y0 : ndarray, optional
        Initial state (see :func:`initial_state`); default: co-rotating release.
    t_eval : array_like, optional
        Output times [s] (dense output); default: every accepted step.
    terminal : bool
        Stop at the opening event (default) or continue to ``case.t_max``.

    Returns
    -------
    NutationResult
    """
    options = options or SolverOptions()
    p, out = _run(case, options, y0, True, t_eval, terminal)
    obs = observables(out.y, p) if len(out.t) else np.empty((0, 11))
    return NutationResult(
        t=out.t,
        theta=obs[:, 0],
        psi=np.unwrap(obs[:, 1]),
        phi=np.unwrap(obs[:, 2]),
        omega_r=obs[:, 3],
        torque=obs[:, 4],
        kinetic_energy=obs[:, 5],
        spin_rate=obs[:, 6],
        axial_momentum=obs[:, 7],
        power=obs[:, 8],
        opening_time=float(out.t_event),
        status=Status(out.status),
        message=MESSAGES[Status(out.status)],
        nfev=int(out.nfev),
        njev=int(out.njev),
        n_steps=int(out.n_steps),
        n_rejected=int(out.n_rejected),
        case=case,
        options=options,
        state=out.y,
    )


def opening_time(case: Case, options: SolverOptions | None = None) -> float:
    """Opening time t_cr [s] of a case (NaN if it does not open by ``case.t_max``).

    Stores no time series; this is the call sweeps and fits make.

    Raises
    ------
    SolverError
        If the integrator fails or reaches its step limit (a RuntimeError).
    """
    options = options or SolverOptions()
    _, out = _run(case, options, None, False, None, True)
    status = Status(out.status)
    if not status.success:
        raise SolverError(f"{case.name or 'case'}: {MESSAGES[status]}", status=status)
    return float(out.t_event)


def alternative_family(family: str) -> str:
    """The family a convergence check compares with: "linear" for the smooth
    families (the most different shape: it reaches full friction at a finite
    slip), "algebraic" for "linear"."""
    return "algebraic" if family == "linear" else "linear"


@dataclass(frozen=True)
class ConvergenceCheck:
    """t_cr re-computed with tighter tolerances, a narrower width and another family.

    A width study alone cannot reveal a regularisation that converges to the
    wrong limit (each family looks converged as its own width shrinks); a
    second family with a different shape can. t_cr counts as converged only
    when all three reruns agree with it.

    Attributes
    ----------
    opening_time : float
        t_cr with the given options [s] (NaN if it did not open).
    tighter_tolerance : float
        t_cr with rtol and atol divided by `factor` [s].
    narrower_width : float
        t_cr with ``friction_width`` divided by `factor` [s] (tolerances
        divided by `factor` too, so slip speeds of order delta stay resolved).
    other_family : float
        t_cr with ``friction_family`` replaced by `family` [s].
    family : str
        The family of that rerun.
    factor : float
        Refinement factor (10 by default).
    threshold : float
        Largest relative change accepted as converged.
    """

    opening_time: float
    tighter_tolerance: float
    narrower_width: float
    other_family: float
    family: str
    factor: float
    threshold: float

    @staticmethod
    def _rel(a: float, b: float) -> float:
        if math.isnan(a) and math.isnan(b):
            return 0.0  # both "did not open by t_max"
        if math.isnan(a) or math.isnan(b):
            return math.inf
        return abs(b - a) / abs(a)

    @property
    def tolerance_change(self) -> float:
        """|t_tight - t| / t [-] (0 when neither run opened, inf when only one did)."""
        return self._rel(self.opening_time, self.tighter_tolerance)

    @property
    def width_change(self) -> float:
        """|t_narrow - t| / t [-]."""
        return self._rel(self.opening_time, self.narrower_width)

    @property
    def family_change(self) -> float:
        """|t_family - t| / t [-]."""
        return self._rel(self.opening_time, self.other_family)

    @property
    def converged(self) -> bool:
        """All three changes below the threshold."""
        return max(self.tolerance_change, self.width_change, self.family_change) < self.threshold

    def to_dict(self) -> dict[str, object]:
        """JSON-ready summary (None for NaN/inf)."""

        def clean(x: float) -> float | None:
            return x if math.isfinite(x) else None

        return {
            "converged": self.converged,
            "tolerance_rel_change": clean(self.tolerance_change),
            "width_rel_change": clean(self.width_change),
            "family_rel_change": clean(self.family_change),
            "t_cr_tighter_tolerance_s": clean(self.tighter_tolerance),
            "t_cr_narrower_width_s": clean(self.narrower_width),
            "t_cr_other_family_s": clean(self.other_family),
            "other_family": self.family,
            "factor": self.factor,
            "threshold": self.threshold,
        }


def convergence_check(
    case: Case,
    options: SolverOptions | None = None,
    *,
    factor: float = 10.0,
    threshold: float = 1e-3,
    opening_time_s: float | None = None,
    family: str | None = None,
) -> ConvergenceCheck:
    """Recompute t_cr with tighter tolerances, a narrower width and another family.

    Parameters
    ----------
    case : Case
    options : SolverOptions, optional
        The options whose result is being checked.
    factor : float
        Refinement factor for (rtol, atol) and for ``friction_width``.
    threshold : float
        Relative change below which t_cr counts as converged.
    opening_time_s : float, optional
        t_cr already computed with `options` [s] (saves one run).
    family : str, optional
        Regularisation family of the third rerun; default
        :func:`alternative_family` of ``options.friction_family``.
    """
    options = options or SolverOptions()
    family = alternative_family(options.friction_family) if family is None else family
    check_choice("family", family, FRICTION_FAMILIES)
    t0 = opening_time(case, options) if opening_time_s is None else float(opening_time_s)
    t1 = opening_time(case, options.tighter(factor))
    narrow = replace(options.tighter(factor), friction_width=options.friction_width / factor)
    other = replace(options, friction_family=family)
    if options.method == "set-valued":  # no width: the regularised path is the check
        narrow = replace(narrow, method="auto")
        other = replace(narrow, friction_family=family)
    t2 = opening_time(case, narrow)
    t3 = opening_time(case, other)
    return ConvergenceCheck(t0, t1, t2, t3, family, factor, threshold)
