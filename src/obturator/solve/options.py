"""Solver options: tolerances, regularisation, method, and what they buy in t_cr accuracy.

:class:`SolverOptions` is the one frozen set of integrator settings every path takes
(one trajectory, the lanes, the convergence check); :data:`OPENING_TIME_ACCURACY` is the
measured table from which :meth:`SolverOptions.for_opening_time_accuracy` picks
tolerances; :meth:`SolverOptions.from_settings` maps the merged settings of a config
file and flags (canonical field names) to options.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from typing import Any

from ..errors import InputError, check_range
from ..model.case import Case
from ..vocab import (
    FORMULATIONS,
    FRICTION_FAMILIES,
    METHODS,
    Formulation,
    FrictionFamily,
    Method,
    check_choice,
)
from .limits import check_regularised_limits

__all__ = [
    "MAX_STEP_PERIODS",
    "MAX_STEP_PERIODS_SHARP",
    "AUTO_OPENING_TIME_ACCURACY",
    "OPENING_TIME_ACCURACY",
    "SolverOptions",
    "max_step_periods",
    "tolerances_for_opening_time",
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
        relative; 1e-7 leaves ~2e-4 at 40, 50, 65, 78 rad/s
        (tests/solve/test_convergence.py) but up to 3.2e-3 at other spins below
        100 rad/s (65.93 rad/s; 1.5e-4 at 100-210, <= 2e-7 above: 2,000 rig points
        against the width-free limit, ``python -m benchmarks.dense_accuracy --limit``). Keep
        ``atol`` well below the width (both are in units of omega_p0): the
        integrator must resolve slip speeds of order delta. The methods
        ``"regularised"``, ``"radau"`` and ``"rosenbrock"`` need ``friction_width >=
        rtol`` on a case with friction, refused where options meet the case
        (:func:`~obturator.solve.limits.check_width_resolved`).
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
    method : {"auto", "regularised", "radau", "rosenbrock", "set-valued", "moreau-jean"}
        Compiled integrator. ``"auto"`` (default): chosen per case
        (:mod:`obturator.solve.dispatch`): ``"set-valued"`` where that solver takes the
        case (the thesis law, the Coulomb patch law; quaternion form, constant mu_s,
        constant or free spin) and its spin is below
        :data:`~obturator.solve.dispatch.SET_VALUED_BELOW`, where it is both faster and
        more accurate (no width); ``"regularised"`` for every other case (slip-speed
        laws, the thesis's energy spin mode, Euler angles, higher spins). The same choice
        in the one-trajectory path and in the lanes. ``friction_width`` and
        ``friction_family`` apply to the cases run regularised only.
        ``"regularised"``: the regularised law with the explicit eighth-order
        Dormand-Prince pair DOP853 (no Jacobian; the problem is not stiff
        outside sticking), handing the run over to Radau IIA (at a third of the
        tolerances) from its last accepted state when DOP853 detects stiffness
        (Hairer's h*lambda test, or more than 200 steps per spin period plus 1000,
        or a step size collapse), and back to DOP853 from Radau's last accepted
        step once the slip speed has stayed above 1e4 regularisation widths for half
        a revolution (the stick-slip phase is over; at most
        :data:`~obturator.core.integrators.AUTO_HAND_BACKS` times); counters add up.
        Its t_cr accuracy per rtol is :data:`OPENING_TIME_ACCURACY`. ``"radau"``:
        the fifth-order Radau IIA collocation method (Newton iterations follow the nonlinear
        stiffness of sticking, far fewer steps than Rosenbrock in long sticking phases).
        ``"rosenbrock"``: the L-stable Rosenbrock pair of Shampine (ode23s). Radau transforms
        rtol as RADAU5 does (0.1 rtol^(2/3)).
        ``"set-valued"``: the friction law with no width (``friction_width`` and
        ``friction_family`` unused): exact stick and event-driven transitions
        (:mod:`obturator.core.integrators.stick_slip`, ``docs/stick_slip.md``); quaternion
        form, constant mu_s, constant or free spin. :func:`convergence_check` then
        compares with the regularised path (``"regularised"``) at the narrower width, both
        families. The thesis law, or the Coulomb patch law with a patch (a > 0).
        ``"moreau-jean"``: the same law by first-order event-capturing time-stepping
        (:mod:`obturator.core.integrators.moreau_jean`) with the fixed step
        ``fixed_step``: an independent cross-check of ``"set-valued"`` (no modes, no
        events), first order in the step (``docs/stick_slip.md``); constant spin, t_cr only (no time
        history: :func:`~obturator.solve.simulate` with it is refused).
    fixed_step : float or None
        Step of ``method="moreau-jean"`` [s], > 0; default None: 1e-4 of a spin period
        (the initial step of the adaptive methods). Only with that method.
    lanes : bool
        Speed strategy of :func:`~obturator.solve.opening_times`: the regularised points
        of a batch advance together in DOP853 SIMD lanes (default True). Each lane runs
        the scalar DOP853's arithmetic, so t_cr, status and counters are those of the
        point alone, bit for bit; False runs every point one by one (cross-checks,
        benchmarks).
    radau_lanes : bool
        Speed strategy of the regularised law in :func:`~obturator.solve.opening_times`
        (default True): a point whose DOP853 stretch turns stiff continues in Radau IIA
        SIMD lanes (:func:`obturator.core.integrators.lanes.integrate_radau_lanes`), alone
        or in any batch alike (their vectorised LU rounds differently from the scalar
        Radau IIA's, so the choice is a route, :mod:`obturator.solve.plan`); False: the
        scalar Radau IIA. A time history (:func:`~obturator.solve.simulate`) always takes
        the scalar one.
    shared_maps : bool
        Speed strategy of the set-valued solver (default False): its cycles' return map
        is interpolated in the spin as well as in the nutation, from a grid of node
        cycles over a fixed band of spins (:mod:`obturator.core.integrators.stick_slip_family`),
        which every case whose parameters differ in the spin alone reuses. The band, its
        nodes and so the map are functions of the case alone (never of the other cases of
        a batch), so a case gives the same t_cr alone or in any batch; it differs from the
        case's own one-spin map (``False``) within the maps' tolerance. It pays where many
        cases share a band (spin sweeps: ``obturator sweep`` turns it on); one case alone
        pays for its band's whole grid.
    slip_lanes : bool
        Speed strategy of the set-valued solver in :func:`~obturator.solve.opening_times`
        (default True): a point's last slip (the ball no longer sticks) continues in the
        DOP853 SIMD lanes with the other points' last slips
        (:mod:`obturator.core.integrators.stick_slip_lanes`), alone or in any batch alike
        (each lane runs the scalar arithmetic on its own point); it differs from the
        mode loop's own stretches (``False``) within the tolerances, so the choice is a
        route (:mod:`obturator.solve.plan`). A time history always runs in the mode loop.
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
    fixed_step: float | None = None
    lanes: bool = True
    radau_lanes: bool = True
    shared_maps: bool = False
    slip_lanes: bool = True

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
        for name in ("lanes", "radau_lanes", "shared_maps", "slip_lanes"):
            if not isinstance(getattr(self, name), bool):
                raise InputError(name, f"{getattr(self, name)!r}; allowed: true, false")
        if self.fixed_step is not None:
            if self.method != "moreau-jean":
                raise InputError("fixed_step", "applies to method 'moreau-jean' only")
            check_range("fixed_step", self.fixed_step, 0.0, 1.0, lo_open=True, unit="s")
        check_regularised_limits(self)

    @classmethod
    def for_opening_time_accuracy(cls, tcr_rtol: float, **kw: Any) -> SolverOptions:
        """Options whose t_cr is accurate to `tcr_rtol` (relative) on the measured cases.

        The tolerances come from the method's measured table
        (:func:`opening_time_accuracy`), the loosest whose worst t_cr error over the rig
        at 40-1000 rad/s, times a safety factor of 3, is within `tcr_rtol`. For the
        default ``"auto"`` (:data:`AUTO_OPENING_TIME_ACCURACY`) that is rtol 1e-8 down to
        5.7e-7; for the others (:data:`OPENING_TIME_ACCURACY`) the regularised path's
        long near-stick runs below 100 rad/s set it. Looser requests get rtol 1e-8 too
        (the default): looser tolerances leave near-stick outliers for little gain.

        Parameters
        ----------
        tcr_rtol : float
            Requested relative accuracy of t_cr [-]: >= 1.6e-8 for ``"auto"``, >= 4.5e-7
            for the other methods.
        **kw
            Other :class:`SolverOptions` fields (not ``rtol``/``atol``).
        """
        rtol = tolerances_for_opening_time(tcr_rtol, kw.get("method", "auto"))
        return cls(rtol=rtol, atol=rtol * 1e-2, **kw)

    def digest_extra(self) -> dict[str, Any]:
        """What a study digest names besides the fields (:func:`obturator.runs.digest.canonical`):
        under ``"auto"`` the thresholds of its per-case choice
        (:func:`obturator.solve.dispatch.dispatch_identity`)."""
        from .dispatch import dispatch_identity

        return dispatch_identity(self)

    def tighter(self, factor: float = 10.0) -> SolverOptions:
        """Both tolerances divided by `factor` (for convergence studies)."""
        return replace(self, rtol=self.rtol / factor, atol=self.atol / factor)

    @classmethod
    def from_settings(cls, settings: Mapping[str, Any]) -> SolverOptions:
        """Options from merged settings (canonical field names; defaults for the rest).

        Keys other than the option fields are ignored (the settings of a case ride
        along). A relative tolerance without an absolute one sets atol = rtol / 100.
        """
        kw = {f.name: settings[f.name] for f in fields(cls) if f.name in settings}
        if "rtol" in kw and "atol" not in kw:
            kw["atol"] = kw["rtol"] * 1e-2
        return cls(**kw)


#: (t_cr accuracy, rtol): rtol (atol = rtol/100) whose worst relative t_cr error,
#: times 3, is within that accuracy, over the rig at 40-1000 rad/s and the flight case,
#: both paths (``python -m benchmarks.dense_accuracy``; tables and history in
#: ``docs/benchmarks.md``). The low band sets every entry. Each is the worst of
#: several measurements that differ only in rounding (the right-hand side before and
#: after its rewrite with one square root, the compiled code before and after ``auto``
#: learned to go back to DOP853, the sweep's vectorised Radau IIA and the scalar one):
#: near stick, stick-slip over hundreds of revolutions amplifies rounding, so at rtol
#: 1e-8 single points scatter by 1e-4..1e-3 from one such variant to the next, at
#: 1e-10 by less than 1e-7. (Until release 0.3 the table was taken from the sweep path
#: alone, and its rtol 1e-8 entry, 4.8e-4, did not hold for the one-trajectory path.)
#: These are errors of the integration at the default width; the width's own error
#: against the width-free limit comes on top below 210 rad/s: up to 3.2e-3, whatever the
#: rtol (Radau IIA at rtol 1e-12 at that width is as far off;
#: ``python -m benchmarks.dense_accuracy --limit``, ``docs/stick_slip.md``).
OPENING_TIME_ACCURACY: tuple[tuple[float, float], ...] = (
    (4.9e-3, 1e-8),
    (1.5e-5, 3e-9),
    (1.1e-5, 1e-9),
    (4.5e-7, 1e-10),
)
#: (t_cr accuracy, rtol) of the default method ``"auto"`` (the set-valued solver below
#: the stick-ratio threshold, at a third of the tolerances; the regularised path above,
#: :mod:`obturator.solve.dispatch`): 3 x the worst relative error against the width-free
#: limit (the set-valued solver at rtol 1e-12) over the rig points of ``python -m
#: benchmarks.dense_accuracy --limit`` (40-1000 rad/s) at each rtol. The width error is
#: included here, unlike :data:`OPENING_TIME_ACCURACY` (the regularised path's own
#: integration error, which every other method uses as its conservative bound).
AUTO_OPENING_TIME_ACCURACY: tuple[tuple[float, float], ...] = (
    (5.7e-7, 1e-8),
    (4.0e-7, 3e-9),
    (1.5e-7, 1e-9),
    (1.6e-8, 1e-10),
)


def opening_time_accuracy(method: str = "auto") -> tuple[tuple[float, float], ...]:
    """The measured (t_cr accuracy, rtol) table that `method` picks its tolerances from:
    :data:`AUTO_OPENING_TIME_ACCURACY` for ``"auto"``, else :data:`OPENING_TIME_ACCURACY`."""
    return AUTO_OPENING_TIME_ACCURACY if method == "auto" else OPENING_TIME_ACCURACY


#: Largest default step, in spin periods: a tenth, and :data:`MAX_STEP_PERIODS_SHARP`
#: where the friction torque's moment arm vanishes in some slip direction (the rig's
#: single bottom contact; :func:`max_step_periods`).
MAX_STEP_PERIODS = 0.1
#: With a tenth on the rig, DOP853 now and then stepped across the sharp minimum of the
#: moment arm (Eq. 61: sqrt(1 - u_X^2), small while omega_r points near the gravity axis
#: X, twice per revolution) with an error estimate that missed it, leaving isolated t_cr
#: outliers (``docs/benchmarks.md``). In flight (no such
#: minimum) it only doubled the steps.
MAX_STEP_PERIODS_SHARP = 0.05


def max_step_periods(case: Case) -> float:
    """Largest default step of `case`, in spin periods (see :data:`MAX_STEP_PERIODS`)."""
    friction = case.torque.friction
    sharp = friction is not None and friction.arm_vanishes
    return MAX_STEP_PERIODS_SHARP if sharp else MAX_STEP_PERIODS


def tolerances_for_opening_time(tcr_rtol: float, method: str = "auto") -> float:
    """rtol for a requested relative t_cr accuracy with `method`
    (:func:`opening_time_accuracy`: the default ``"auto"`` its own table, every other
    method the regularised path's).

    Raises
    ------
    InputError
        `tcr_rtol` outside [1.6e-8, 0.1] (``"auto"``) or [4.5e-7, 0.1] (other methods).
    """
    table = opening_time_accuracy(method)
    check_range("tcr_rtol", tcr_rtol, table[-1][0], 0.1)
    for accuracy, rtol in table:
        if tcr_rtol >= accuracy:
            return rtol
    raise AssertionError("unreachable")  # pragma: no cover
