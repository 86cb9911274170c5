"""Solving the equations of motion: the only package above :mod:`obturator.core` that
drives the integrators.

One case, one trajectory (:mod:`~obturator.solve.one`): :func:`simulate` (time history,
:class:`~obturator.result.NutationResult`) and :func:`opening_time` (t_cr alone).
Many cases (:mod:`~obturator.solve.many`): :func:`opening_times`, the front door every
study (sweeps, Monte Carlo, calibration, validation, the thesis figures, the envelope)
takes; SIMD lanes where the options allow, else one by one, same answers;
:func:`advance`, the same from given states to each case's t_max (one segment of a
piecewise-constant load for many points).
Settings (:mod:`~obturator.solve.options`): :class:`SolverOptions` and the measured
accuracy table. Convergence (:mod:`~obturator.solve.convergence`):
:func:`convergence_check` reruns with tighter tolerances, a narrower width and
another regularisation family. Past first light (:mod:`~obturator.solve.start`):
:func:`start_times` runs on to the start of the internal flow, theta_start.
:mod:`~obturator.solve.setup` packs a case for the
compiled integrators (shared by both paths).
"""

from .convergence import (
    ConvergenceCheck,
    alternative_family,
    convergence_check,
    convergence_checks,
    refined_options,
)
from .many import (
    POINT_STATUSES,
    Advanced,
    PackedPoints,
    advance,
    batchable,
    integrate_packed,
    opening_times,
    pack_points,
    point_status,
)
from .one import opening_time, simulate
from .options import (
    AUTO_OPENING_TIME_ACCURACY,
    MAX_STEP_PERIODS,
    MAX_STEP_PERIODS_SHARP,
    OPENING_TIME_ACCURACY,
    SolverOptions,
    max_step_periods,
    opening_time_accuracy,
    tolerances_for_opening_time,
)
from .setup import error_scale, integration_controls, integration_setup, pack_parameters
from .start import StartTimes, start_times

__all__ = [
    "MAX_STEP_PERIODS",
    "MAX_STEP_PERIODS_SHARP",
    "AUTO_OPENING_TIME_ACCURACY",
    "OPENING_TIME_ACCURACY",
    "POINT_STATUSES",
    "Advanced",
    "ConvergenceCheck",
    "PackedPoints",
    "SolverOptions",
    "StartTimes",
    "advance",
    "alternative_family",
    "batchable",
    "convergence_check",
    "convergence_checks",
    "error_scale",
    "integrate_packed",
    "integration_controls",
    "integration_setup",
    "max_step_periods",
    "opening_time",
    "opening_times",
    "pack_parameters",
    "pack_points",
    "refined_options",
    "point_status",
    "simulate",
    "start_times",
    "opening_time_accuracy",
    "tolerances_for_opening_time",
]
