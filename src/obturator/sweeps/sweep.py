"""The sweep study: :func:`run_points` (the points of a study on a runner) and the sweep API.

:func:`run_sweep` evaluates the full Cartesian grid of a
:class:`~obturator.sweeps.spec.SweepSpec` and returns an :class:`xarray.Dataset`
with ``t_cr`` [s] (NaN where the bore did not open) and an integer ``status``
(:class:`~obturator.status.Status`); :func:`execute_sweep` also reports how it
ran (:class:`SweepRun`). The points run on a :class:`~obturator.runs.Runner` (local
processes or Dask, chunks, progress); with ``store=PATH`` finished chunks survive an
interruption or a full disk (:mod:`obturator.runs.store`).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache, cached_property, partial
from typing import TYPE_CHECKING, Any

import numpy as np

from .._docs import field_docs
from ..errors import InputError
from ..runs import Runner
from ..runs.chunks import TASK_CHUNK
from ..solve import batchable
from ..status import Status
from .export import check_distinct_outputs, grid_table, write_outputs
from .job import LANE_CHUNK, PointResults, sweep_job
from .points import validity_note
from .spec import SweepSpec
from .table import StudyTable

if TYPE_CHECKING:  # pragma: no cover
    import xarray

__all__ = ["Outcome", "SweepRun", "run_points", "execute_sweep", "run_sweep", "sweep_summary"]


@dataclass(frozen=True)
class Outcome:
    """Results of :func:`run_points` and how they were computed."""

    t_cr: np.ndarray
    status: np.ndarray
    route: np.ndarray
    n_resumed: int
    n_computed: int
    workers: int
    backend: str
    elapsed_s: float
    #: What of the points lies outside the Appendix B runs
    #: (:func:`~.points.validity_note`), or None.
    outside_validated_data: str | None = None


def run_points(
    spec: SweepSpec,
    names: tuple[str, ...],
    rows_of: Callable[[np.ndarray], np.ndarray],
    n_points: int,
    digest: str,
    runner: Runner,
    *,
    label: str,
    unit: str = "points",
    extra_outputs: tuple[str, ...] = (),
) -> Outcome:
    """Compute t_cr and the status of `n_points` points with `runner`, resuming from and
    writing to its resume store when it has one (:mod:`obturator.runs.store`), and
    check them against the validated data (:func:`~.points.validity_note`; serial work,
    done while pool or Dask workers compute)."""
    runner.open(digest, extra_outputs)
    results = PointResults(n_points)
    max_chunk = LANE_CHUNK if batchable(spec.options) else TASK_CHUNK
    note = cache(partial(validity_note, spec, names, rows_of, n_points, unit))  # once
    job = sweep_job(spec, names, rows_of, meanwhile=note)
    info = runner.run(job, results, n_points, label=label, unit=unit, max_chunk=max_chunk)
    results.check_complete()
    return Outcome(
        results.t_cr,
        results.status,
        results.route,
        info.n_resumed,
        info.n_computed,
        info.workers,
        info.backend,
        info.elapsed_s,
        note(),
    )


@field_docs
@dataclass(frozen=True)
class SweepRun:
    """Outcome of :func:`execute_sweep`."""

    #: The results as arrays (:class:`~.table.StudyTable`; :attr:`dataset` as a Dataset).
    table: StudyTable
    #: Points integrated in this call.
    n_computed: int
    #: Points taken from the resume store instead of being integrated again.
    n_resumed: int
    #: Local processes used (1: in this process; 0: a dask cluster).
    workers: int
    #: Where the points ran: ``"local"`` or ``"dask.distributed"``.
    backend: str
    #: Wall time of the computation [s] (without writing files).
    elapsed_s: float

    @cached_property
    def dataset(self) -> xarray.Dataset:
        """The results as an :class:`xarray.Dataset` (see :func:`run_sweep`)."""
        return self.table.to_dataset()


def execute_sweep(
    spec: SweepSpec,
    runner: Runner | None = None,
    *,
    csv: str | os.PathLike[str] | None = None,
) -> SweepRun:
    """Run a sweep and return the dataset with run statistics; see :func:`run_sweep`.

    `csv`, if given, is written (atomically) before the resume store is removed, so an
    interruption while writing outputs loses nothing.
    """
    if not isinstance(spec, SweepSpec):
        raise InputError("spec", "expected a SweepSpec")
    runner = runner or Runner()
    check_distinct_outputs(runner.store, csv)
    out = run_points(
        spec,
        spec.dims,
        spec.rows,
        spec.n_points,
        spec.digest(),
        runner,
        label="sweep",
        extra_outputs=() if csv is None else (str(csv),),
    )
    table = grid_table(spec, out.t_cr, out.status, out.route)
    # what lies outside the Appendix B runs ("" if nothing; obturator.model.validity)
    table = table.with_attrs(outside_validated_data=out.outside_validated_data or "")
    write_outputs(table, runner, csv)
    return SweepRun(table, out.n_computed, out.n_resumed, out.workers, out.backend, out.elapsed_s)


def run_sweep(spec: SweepSpec, runner: Runner | None = None) -> xarray.Dataset:
    """Evaluate t_cr on the full Cartesian grid of a :class:`SweepSpec`.

    Parameters
    ----------
    spec : SweepSpec
    runner : Runner, optional
        Where and how the points run (:class:`obturator.runs.Runner`: local worker
        processes, default all CPUs, or a dask.distributed scheduler; chunk size,
        default about 8 chunks per worker, at most 1,024 points in lanes, else 256;
        progress). With ``store=PATH`` the dataset is written to that NetCDF file at
        the end, and finished chunks go to ``<PATH>.partial.jsonl`` while running so
        that an interrupted run resumes (``restart=True`` discards a sidecar of a
        different study).

    Returns
    -------
    xarray.Dataset
        ``t_cr`` [s] over the swept dimensions (NaN where not opened),
        ``status`` (:class:`~obturator.status.Status`: 1 opened, 0 not opened
        by t_max, -1 solver failure, 2 step limit, -2 invalid input, 4 opened
        but not converged), coordinates with ``units``, scalar
        coordinates for the parameters not swept, and attributes with the
        case, torque model, spin mode, solver settings, package version and
        the study hash.

    Raises
    ------
    InputError
        On a bad worker count or chunk size, a missing output directory, an
        unreachable scheduler, a sidecar of a different study, or a failed write
        (full disk: the finished points are kept, a rerun resumes).
    """
    return execute_sweep(spec, runner).dataset


def sweep_summary(ds: xarray.Dataset | StudyTable) -> dict[str, Any]:
    """Counts and the t_cr range of a sweep (or Monte Carlo) study.

    Parameters
    ----------
    ds : xarray.Dataset or StudyTable
        The study's results (:func:`run_sweep`, :func:`~.montecarlo.monte_carlo`, or
        :attr:`SweepRun.table`).

    Returns
    -------
    dict
        ``n_points``, ``n_opened``, ``n_unconverged``, ``n_not_opened``,
        ``n_failed`` (solver failure or step limit), ``n_invalid``,
        ``t_cr_min_s``, ``t_cr_max_s`` (None if nothing opened) and
        ``argmin``: the parameter values at the smallest t_cr.
    """
    table = StudyTable.of(ds)
    t = np.asarray(table.values("t_cr"), dtype=float)
    s = table.values("status")
    dims = table.dims("t_cr")
    res: dict[str, Any] = {
        "n_points": int(t.size),
        "n_opened": int(np.sum(s == Status.OPENED)),
        "n_unconverged": int(np.sum(s == Status.UNCONVERGED)),
        "n_not_opened": int(np.sum(s == Status.T_MAX)),
        "n_failed": int(np.sum((s == Status.FAILED) | (s == Status.STEP_LIMIT))),
        "n_invalid": int(np.sum(s == Status.INVALID_INPUT)),
        "t_cr_min_s": None,
        "t_cr_max_s": None,
        "argmin": {},
    }
    if np.any(np.isfinite(t)):
        res["t_cr_min_s"] = float(np.nanmin(t))
        res["t_cr_max_s"] = float(np.nanmax(t))
        if "sample" not in dims and t.ndim:
            where = np.unravel_index(int(np.nanargmin(t)), t.shape)
            res["argmin"] = {d: float(table.values(d)[i]) for d, i in zip(dims, where, strict=True)}
    return res
