"""The set-valued points of the front door, run one at a time.

:func:`~obturator.solve.many.integrate_packed` runs the points whose route is the
set-valued solver (:mod:`obturator.solve.plan`) one by one, as
:func:`~obturator.solve.opening_time` runs a case alone; with ``options.shared_maps``
each reads the return map of its spin's fixed band
(:func:`obturator.core.integrators.stick_slip_family.band_map`), a function of the point
alone, so the same t_cr alone or in any batch.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..core.integrators import Controls, Problem, RawSolution
from ..core.integrators.stick_slip import integrate as integrate_set_valued
from ..core.integrators.stick_slip_family import band_map
from ..core.integrators.stick_slip_lanes import finish_in_lanes
from ..status import Status
from .dispatch import dispatched_controls
from .options import SolverOptions
from .setup import integration_controls

if TYPE_CHECKING:
    from .many import PackedPoints

__all__ = ["failed_status", "run_one_by_one", "run_set_valued"]


def failed_status(exc: RuntimeError) -> Status:
    """``STEP_LIMIT`` where an integrator raised at its step limit, else ``FAILED``."""
    return Status.STEP_LIMIT if getattr(exc, "status", None) == Status.STEP_LIMIT else Status.FAILED


def run_one_by_one(
    packed: PackedPoints,
    idx: np.ndarray,
    options: SolverOptions,
    to_t_max: bool,
    n_lanes: int,
) -> tuple[list[RawSolution], int]:
    """The points `idx` of `packed` through the set-valued solver, each as
    :func:`~obturator.solve.opening_time` runs it (with `to_t_max` to ``t_max`` with an
    output there, :func:`~obturator.solve.advance`), their last slips together in
    `n_lanes` DOP853 lanes under ``options.slip_lanes`` (not with `to_t_max`). Returns
    their runs and the right-hand sides spent on the band grids of shared maps built
    here."""
    counts = np.zeros(4, dtype=np.int64)
    hand_off = options.slip_lanes and not to_t_max
    problems, controls, runs = [], [], []
    for k in idx:
        problem = Problem(packed.y0[k], packed.p[k], packed.scale[k])
        t_max = float(packed.t_max[k])
        ctl = integration_controls(
            options, t_max, float(packed.h0[k]), float(packed.h_max[k]),
            t_eval=np.array([t_max]) if to_t_max else None,
        )  # fmt: skip
        ctl = dispatched_controls(options.method, "set-valued", ctl)
        ctl = ctl._replace(last_slip_to_lanes=hand_off)
        problems.append(problem)
        controls.append(ctl)
        runs.append(run_set_valued(problem, ctl, options, counts))
    if hand_off:
        runs = finish_in_lanes(problems, controls, runs, n_lanes)
    return runs, int(counts[0])


def run_set_valued(
    problem: Problem, controls: Controls, options: SolverOptions, counts: np.ndarray | None = None
) -> RawSolution:
    """One point through the set-valued solver at `controls` (those ``options.method``
    gives it: :func:`~obturator.solve.dispatch.dispatched_controls`), with its band's
    shared return map under ``options.shared_maps`` (built without the hand-off of
    ``controls.last_slip_to_lanes``: a band's nodes are whole cycles); an integrator
    that raises counts as failed. `counts` gains the band grid's work where one is
    built."""
    try:
        shared = None
        if options.shared_maps:
            shared = band_map(problem, controls._replace(last_slip_to_lanes=False), counts)
        if shared is not None:
            return integrate_set_valued(problem, controls, shared=shared)
        return integrate_set_valued(problem, controls)
    except RuntimeError as exc:
        status = failed_status(exc)
        nan = np.full(problem.y0.shape[0], np.nan)
        return RawSolution(
            status, np.nan, nan, np.empty(0), np.empty((0, problem.y0.shape[0])), 0, 0, 0, 0,
            0.0, nan,
        )  # fmt: skip
