"""One point of a study: its t_cr and :class:`~obturator.status.Status`, and chunks of points.

Every grid point or Monte Carlo sample is one independent call of
:func:`obturator.solve.opening_time` through :func:`evaluate_point`, the same
deterministic function wherever it runs (in this process, a process pool or
a Dask worker), so local, pooled and distributed results are identical bit for
bit. :func:`run_chunk` is module level so that workers can import it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from ..model.cases import rig_case
from ..solve import SolverOptions, convergence_check, opening_time
from ..status import Status
from .spec import SweepSpec

if TYPE_CHECKING:  # batch imports this module
    from .batch import PackedPoints

__all__ = [
    "POINT_STATUSES",
    "evaluate_point",
    "is_warm",
    "point_status",
    "run_chunk",
    "warm",
]

#: The statuses a study point can have (the ``status`` variable's flag values).
POINT_STATUSES: tuple[Status, ...] = (
    Status.INVALID_INPUT,
    Status.FAILED,
    Status.T_MAX,
    Status.OPENED,
    Status.STEP_LIMIT,
    Status.UNCONVERGED,
)


def point_status(status: Status, t: float) -> tuple[float, int]:
    """(t_cr, status) of a point from an integration's status and t_event [s].

    ``FAILED`` or ``STEP_LIMIT`` when the integration failed (t_cr NaN), ``T_MAX``
    when it did not open, else ``OPENED``. Shared by the per-point path and the
    lanes (:mod:`obturator.sweeps.batch`).
    """
    if not status.success:
        return math.nan, Status.STEP_LIMIT if status == Status.STEP_LIMIT else Status.FAILED
    return (t, Status.OPENED) if math.isfinite(t) else (math.nan, Status.T_MAX)


def evaluate_point(spec: SweepSpec, values: Mapping[str, float]) -> tuple[float, int]:
    """t_cr [s] and status at one point (never raises for a bad point).

    ``INVALID_INPUT`` when the point is not a valid case, ``FAILED`` or
    ``STEP_LIMIT`` when the integrator fails, ``T_MAX`` when the bore does not
    open by t_max, ``UNCONVERGED`` when it opens but fails the convergence
    check (only with ``spec.check_convergence``), else ``OPENED``.
    """
    try:
        case = spec.build_case(values)
    except InputError:
        return math.nan, Status.INVALID_INPUT
    try:
        t = opening_time(case, spec.options)
        if spec.check_convergence and math.isfinite(t):
            if not convergence_check(case, spec.options, opening_time_s=t).converged:
                return t, Status.UNCONVERGED
    except RuntimeError as exc:  # SolverError, or anything else the integrator raised
        limit = getattr(exc, "status", None) == Status.STEP_LIMIT
        return point_status(Status.STEP_LIMIT if limit else Status.FAILED, math.nan)
    return point_status(Status.OPENED, t)


def run_chunk(
    spec: SweepSpec, names: tuple[str, ...], rows: np.ndarray, packed: PackedPoints | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Evaluate the points of one chunk (rows of values in ``names`` order).

    In lanes (:mod:`obturator.sweeps.batch`) where the options allow, else one
    :func:`evaluate_point` per row; the results are the same. `packed`: the rows'
    :class:`~obturator.sweeps.batch.PackedPoints` where already built
    (:mod:`obturator.sweeps.ahead`). Module level so that process pools and dask
    workers can import it.
    """
    from .batch import batchable, run_rows

    if batchable(spec.options, spec.check_convergence):
        return run_rows(spec, names, rows, packed)
    t = np.empty(len(rows))
    s = np.empty(len(rows), dtype=np.int8)
    for k, row in enumerate(rows):
        t[k], s[k] = evaluate_point(spec, dict(zip(names, row.tolist(), strict=True)))
    return t, s


def warm(options: SolverOptions, radau_lanes: bool = False) -> None:
    """Load (or compile) the integrators once: a short rig run with these options that
    turns stiff (150 rad/s, 10 ms), so ``auto`` loads DOP853 and Radau IIA, and the
    same run in lanes (:mod:`obturator.sweeps.batch`), and with `radau_lanes` the Radau
    IIA lanes (~0.4 s to load; chunks too small to use them skip it)."""
    from ..warmup import load_radau_lanes
    from .batch import batchable, opening_times

    if is_warm(options, radau_lanes):
        return
    case = rig_case(150.0, 0.5, t_max=1e-2)
    try:
        opening_time(case, options)
        if batchable(options):
            opening_times([case], options)
            if radau_lanes:
                load_radau_lanes()
    except RuntimeError:  # pragma: no cover - warm-up only
        pass
    _WARM.add((options, radau_lanes))


#: (options, radau_lanes) of the :func:`warm` calls done in this process (forked
#: workers inherit it with the loaded code).
_WARM: set[tuple[SolverOptions, bool]] = set()


def is_warm(options: SolverOptions, radau_lanes: bool = False) -> bool:
    """True when :func:`warm` has loaded the integrators for `options` in this process."""
    return (options, radau_lanes) in _WARM
