"""The points of the front door that run one at a time.

:func:`~obturator.solve.many.integrate_packed` runs some packed points one by one
instead of in lanes: those ``auto`` gives to the set-valued solver (and every point
under ``method="set-valued"``), and right-hand-side kernels with too few points for the
lanes to pay. :func:`run_one_by_one` runs such a set of points as
:func:`~obturator.solve.opening_time` would, one integrator call each, except that

set-valued points that differ in spin alone share their cycles' return maps
(:mod:`obturator.core.integrators.stick_slip_family`; ``OBTURATOR_SHARED_MAPS=0``: each
builds its own).
"""

from __future__ import annotations

import math
import os
from typing import TYPE_CHECKING

import numpy as np

from ..core.integrators import Controls, Problem, RawSolution, integrate
from ..core.integrators.stick_slip import integrate as integrate_set_valued
from ..core.integrators.stick_slip_family import shared_maps
from ..core.layout import N_STATE
from ..errors import InputError
from ..status import Status
from .dispatch import core_method, dispatched_controls
from .options import SolverOptions
from .setup import integration_controls

if TYPE_CHECKING:
    from ..core.integrators.stick_slip_map import CycleMap
    from .many import PackedPoints

__all__ = ["env_switch", "failed_status", "run_one_by_one"]


def env_switch(name: str) -> bool:
    """An on/off environment variable: unset or ``1`` is on, ``0`` off.

    Raises
    ------
    InputError
        Any other value (a typo must not silently select a path).
    """
    value = os.environ.get(name, "1")
    if value not in ("0", "1"):
        raise InputError(name, f"{value!r}; allowed: 0 (off), 1 (on)")
    return value == "1"


def failed_status(exc: RuntimeError) -> Status:
    """``STEP_LIMIT`` where an integrator raised at its step limit, else ``FAILED``."""
    return Status.STEP_LIMIT if getattr(exc, "status", None) == Status.STEP_LIMIT else Status.FAILED


def run_one_by_one(
    packed: PackedPoints,
    idx: np.ndarray,
    options: SolverOptions,
    chosen: str,
    to_t_max: bool,
    n_lanes: int,
) -> tuple[list[RawSolution], int]:
    """The points `idx` of `packed`, each through the integrator `chosen`
    (``"set-valued"`` or ``"regularised"``; see the module), with `to_t_max` to
    ``t_max`` with an output there (:func:`~obturator.solve.advance`), else to the
    opening. Returns their runs and the right-hand sides spent on shared maps."""
    setups = [_point_setup(packed, int(k), options, chosen, to_t_max) for k in idx]
    problems, controls = [s[0] for s in setups], [s[1] for s in setups]
    maps: list[CycleMap | None] = [None] * len(idx)
    nfev = 0
    if chosen == "set-valued" and env_switch("OBTURATOR_SHARED_MAPS"):
        maps, counts = shared_maps(problems, controls)
        nfev = int(counts[0])
    runs = [_point(*setup, chosen, m) for setup, m in zip(setups, maps, strict=True)]
    return runs, nfev


def _point_setup(
    packed: PackedPoints,
    k: int,
    options: SolverOptions,
    chosen: str,
    to_t_max: bool,
) -> tuple[Problem, Controls]:
    """Point `k`'s problem and controls for the integrator `chosen`, as
    :func:`~obturator.solve.opening_time` builds them (with `to_t_max`, as
    :func:`~obturator.solve.advance`'s one-by-one path: an output at t_max)."""
    problem = Problem(packed.y0[k], packed.p[k], packed.scale[k])
    t_max = float(packed.t_max[k])
    controls = integration_controls(
        options, t_max, float(packed.h0[k]), float(packed.h_max[k]),
        t_eval=np.array([t_max]) if to_t_max else None,
    )  # fmt: skip
    return problem, dispatched_controls(options.method, chosen, controls)


def _point(
    problem: Problem, controls: Controls, chosen: str, cycle_map: CycleMap | None = None
) -> RawSolution:
    """One point through the integrator `chosen` (``"set-valued"``, with the shared
    return map `cycle_map` where given, or ``"regularised"``); an integrator that
    raises counts as failed, as in the one-by-one path."""
    try:
        if cycle_map is not None:
            return integrate_set_valued(problem, controls, shared=cycle_map)
        return integrate(core_method(chosen), problem, controls)
    except RuntimeError as exc:
        nan = np.full(N_STATE, math.nan)
        return RawSolution(
            failed_status(exc), math.nan, nan, np.empty(0), np.empty((0, N_STATE)),
            0, 0, 0, 0, 0.0, nan,
        )  # fmt: skip
