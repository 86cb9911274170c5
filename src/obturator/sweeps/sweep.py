"""Running a study: :func:`run_points` (store, executor, progress) and the sweep API.

:func:`run_sweep` evaluates the full Cartesian grid of a
:class:`~obturator.sweeps.spec.SweepSpec` and returns an :class:`xarray.Dataset`
with ``t_cr`` [s] (NaN where the bore did not open) and an integer ``status``
(:class:`~obturator.status.Status`); :func:`execute_sweep` also reports how it
ran (:class:`SweepRun`). Points are grouped into chunks that run where
:func:`~obturator.sweeps.executors.choose_executor` says; with ``store=PATH``
finished chunks survive an interruption (:mod:`obturator.sweeps.store`).
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from ..solve import batchable
from ..status import Status
from .executors import (
    LANE_CHUNK,
    TASK_CHUNK,
    ProcessPool,
    choose_executor,
    make_chunks,
    probe_cost,
    progress_bar,
    resolve_workers,
    sweep_job,
)
from .export import check_distinct_outputs, grid_dataset, write_outputs
from .spec import SweepSpec
from .store import Sidecar, StoreLock, remove_stale_temporaries, sidecar_path

if TYPE_CHECKING:  # pragma: no cover
    import xarray

__all__ = ["Outcome", "SweepRun", "run_points", "execute_sweep", "run_sweep", "sweep_summary"]


@dataclass(frozen=True)
class Outcome:
    """Results of :func:`run_points` and how they were computed."""

    t_cr: np.ndarray
    status: np.ndarray
    n_resumed: int
    n_computed: int
    workers: int
    backend: str
    elapsed_s: float
    sidecar: Sidecar | None


def run_points(
    spec: SweepSpec,
    names: tuple[str, ...],
    rows_of: Callable[[np.ndarray], np.ndarray],
    n_points: int,
    digest: str,
    *,
    workers: int | None,
    scheduler: Any,
    store: str | os.PathLike[str] | None,
    restart: bool,
    chunk_size: int | None,
    progress: bool,
    label: str,
    extra_outputs: tuple[str, ...] = (),
) -> Outcome:
    """Compute t_cr and the status of `n_points` points, resuming from and writing to
    the sidecar of `store` when given (see :mod:`.store`)."""
    t0 = time.perf_counter()
    n_workers = 0 if scheduler is not None else resolve_workers(workers)
    t_cr = np.full(n_points, np.nan)
    status = np.full(n_points, -128, dtype=np.int8)  # -128: not computed yet
    sidecar = None
    if store is not None:
        out = Path(store)
        if not out.parent.is_dir():
            raise InputError("out", f"directory {str(out.parent)!r} does not exist")
        lock = StoreLock(out, digest)
        try:
            for p in (out, sidecar_path(out), *extra_outputs):
                remove_stale_temporaries(Path(p))
            sidecar = Sidecar(sidecar_path(out), digest, n_points, restart)
        except BaseException:
            lock.release()
            raise
        sidecar.lock = lock
        if sidecar.n_discarded:
            print(
                f"obturator: notice: {sidecar.n_discarded} damaged or foreign records in "
                f"{sidecar.path.name} discarded; their points are recomputed",
                file=sys.stderr,
            )
        for idx, t, s in zip(sidecar.done_index, sidecar.done_t, sidecar.done_s, strict=True):
            t_cr[idx], status[idx] = t, s
    todo = np.flatnonzero(status == -128)
    n_resumed = n_points - todo.size

    def sink(idx: np.ndarray, result: tuple[np.ndarray, np.ndarray]) -> None:
        t, s = result
        t_cr[idx], status[idx] = t, s
        if sidecar is not None:
            sidecar.append(idx, t, s)

    try:
        lanes = batchable(spec.options, spec.check_convergence)
        chunks = make_chunks(
            todo, n_workers if scheduler is None else 8, chunk_size,
            LANE_CHUNK if lanes else TASK_CHUNK,
        )  # fmt: skip
        executor = choose_executor(n_workers, scheduler, len(chunks))
        job = sweep_job(spec, names, rows_of, max((c.size for c in chunks), default=0))
        if isinstance(executor, ProcessPool):
            if job.ahead is not None:
                job = job.ahead(chunks)
            executor = probe_cost(executor, job, chunks, sink)
        bar = partial(progress_bar, progress, n_points, n_resumed, label)
        if chunks:
            executor.run(job, chunks, sink, bar)
    except BaseException:
        if sidecar is not None:
            sidecar.close()
        raise
    if np.any(status == -128):  # pragma: no cover - a chunk went missing
        raise RuntimeError("some points were not computed")
    return Outcome(
        t_cr,
        status,
        n_resumed,
        int(todo.size),
        executor.workers,
        executor.backend,
        time.perf_counter() - t0,
        sidecar,
    )


@dataclass(frozen=True)
class SweepRun:
    """Outcome of :func:`execute_sweep`.

    Attributes
    ----------
    dataset : xarray.Dataset
        The results (see :func:`run_sweep`).
    n_computed, n_resumed : int
        Points integrated in this call and points taken from the sidecar.
    workers : int
        Local processes used (1: in this process; 0: a dask cluster).
    backend : str
        ``"local"`` or ``"dask.distributed"``.
    elapsed_s : float
        Wall time of the computation [s] (without writing files).
    """

    dataset: xarray.Dataset
    n_computed: int
    n_resumed: int
    workers: int
    backend: str
    elapsed_s: float


def execute_sweep(
    spec: SweepSpec,
    *,
    workers: int | None = None,
    scheduler: Any = None,
    store: str | os.PathLike[str] | None = None,
    restart: bool = False,
    chunk_size: int | None = None,
    progress: bool = True,
    csv: str | os.PathLike[str] | None = None,
) -> SweepRun:
    """Run a sweep and return the dataset with run statistics; see :func:`run_sweep`.

    `csv`, if given, is written (atomically) before the partial-results file is
    removed, so an interruption while writing outputs loses nothing.
    """
    if not isinstance(spec, SweepSpec):
        raise InputError("spec", "expected a SweepSpec")
    check_distinct_outputs(store, csv)
    out = run_points(
        spec,
        spec.dims,
        spec.rows,
        spec.n_points,
        spec.digest(),
        workers=workers,
        scheduler=scheduler,
        store=store,
        restart=restart,
        chunk_size=chunk_size,
        progress=progress,
        label="sweep",
        extra_outputs=() if csv is None else (str(csv),),
    )
    ds = grid_dataset(spec, out.t_cr, out.status)
    write_outputs(ds, out, store, csv)
    return SweepRun(ds, out.n_computed, out.n_resumed, out.workers, out.backend, out.elapsed_s)


def run_sweep(
    spec: SweepSpec,
    *,
    workers: int | None = None,
    scheduler: Any = None,
    store: str | os.PathLike[str] | None = None,
    progress: bool = True,
    restart: bool = False,
    chunk_size: int | None = None,
) -> xarray.Dataset:
    """Evaluate t_cr on the full Cartesian grid of a :class:`SweepSpec`.

    Parameters
    ----------
    spec : SweepSpec
    workers : int, optional
        Local worker processes (default: the CPUs available). 1 runs in this
        process. Ignored when `scheduler` is given.
    scheduler : str or distributed.Client, optional
        Address of a dask.distributed scheduler (``"tcp://host:8786"``) or a
        client; the chunks are computed on that cluster instead.
    store : path, optional
        NetCDF file to write at the end; while running, finished chunks go to
        ``<store>.partial.jsonl`` so that an interrupted run resumes.
    progress : bool
        Show a rich progress bar on stderr.
    restart : bool
        Discard a sidecar left by a *different* study instead of failing.
    chunk_size : int, optional
        Points per task (default: about 8 tasks per worker, at most 1,024 points in
        lanes, else 256).

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
        unreachable scheduler, or a sidecar of a different study.
    """
    return execute_sweep(
        spec,
        workers=workers,
        scheduler=scheduler,
        store=store,
        restart=restart,
        chunk_size=chunk_size,
        progress=progress,
    ).dataset


def sweep_summary(ds: xarray.Dataset) -> dict[str, Any]:
    """Counts and the t_cr range of a sweep (or Monte Carlo) dataset.

    Returns
    -------
    dict
        ``n_points``, ``n_opened``, ``n_unconverged``, ``n_not_opened``,
        ``n_failed`` (solver failure or step limit), ``n_invalid``,
        ``t_cr_min_s``, ``t_cr_max_s`` (None if nothing opened) and
        ``argmin``: the parameter values at the smallest t_cr.
    """
    t = np.asarray(ds["t_cr"].values, dtype=float)
    s = np.asarray(ds["status"].values)
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
        if "sample" not in ds["t_cr"].dims and t.ndim:
            where = np.unravel_index(int(np.nanargmin(t)), t.shape)
            res["argmin"] = {
                d: float(ds[d].values[i]) for d, i in zip(ds["t_cr"].dims, where, strict=True)
            }
    return res
