"""A sweep or Monte Carlo study as a :class:`~obturator.runs.Job` of the runner.

:func:`sweep_job` computes t_cr and the status of chunks of points (rows of parameter
values) with :func:`~.points.run_chunk`; :class:`PointResults` holds them in flat
arrays and stores each chunk as ``keys`` = flat point indices, ``values`` =
``{"t_cr": [...], "status": [...]}`` in the runner's resume store.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import replace
from functools import partial
from typing import Any

import numpy as np

from ..runs.chunks import Job
from ..runs.pools import default_workers, gc_frozen, mp_context
from ..solve import batchable
from ..solve.plan import ROUTES
from .ahead import pack_ahead
from .points import POINT_STATUSES, is_warm, run_chunk, warm
from .spec import SweepSpec

__all__ = ["LANE_CHUNK", "PointResults", "sweep_job"]

#: Largest default chunk of points integrated in lanes (:func:`obturator.solve.opening_times`):
#: a chunk's stiff points go through Radau IIA lanes together, which pay off from a few
#: dozen per chunk and keep improving with more, flat from about a thousand points
#: (``python -m benchmarks.lanes``; ``docs/benchmarks.md``, history).
LANE_CHUNK = 1024

_NOT_DONE = -128
_KNOWN = frozenset(int(s) for s in POINT_STATUSES)


class PointResults:
    """t_cr [s], status and route (:data:`~obturator.solve.plan.ROUTES` code) of `n`
    points (status -128: not computed yet)."""

    def __init__(self, n: int) -> None:
        self.n = n
        self.t_cr = np.full(n, np.nan)
        self.status = np.full(n, _NOT_DONE, dtype=np.int8)
        self.route = np.zeros(n, dtype=np.int8)

    def todo(self) -> np.ndarray:
        """Flat indices of the points not computed yet."""
        return np.flatnonzero(self.status == _NOT_DONE)

    def put(
        self, idx: np.ndarray, result: tuple[np.ndarray, np.ndarray, np.ndarray]
    ) -> tuple[list[Any], Any]:
        """Keep a chunk's ``(t_cr, status, route)``; its store record."""
        t, s, r = result
        self.t_cr[idx], self.status[idx], self.route[idx] = t, s, r
        return idx.tolist(), {"t_cr": t.tolist(), "status": s.tolist(), "route": r.tolist()}

    def restore(self, keys: list[Any], values: Any) -> bool:
        """Take a stored chunk; False if its indices, shapes or statuses do not fit."""
        try:
            idx = np.asarray(keys, dtype=np.int64)
            t = np.asarray(values["t_cr"], dtype=float)
            s = np.asarray(values["status"], dtype=np.int64)
            r = np.asarray(values["route"], dtype=np.int64)
        except (KeyError, TypeError, ValueError):
            return False
        ok = idx.ndim == 1 and idx.shape == t.shape == s.shape == r.shape
        ok = ok and bool(np.all((idx >= 0) & (idx < self.n)))
        ok = ok and bool(np.all((r >= 0) & (r < len(ROUTES))))
        if not (ok and all(int(x) in _KNOWN for x in s)):
            return False
        self.t_cr[idx], self.status[idx], self.route[idx] = t, s.astype(np.int8), r.astype(np.int8)
        return True

    def check_complete(self) -> None:
        """Fail loudly if a chunk went missing."""
        if np.any(self.status == _NOT_DONE):  # pragma: no cover
            raise RuntimeError("some points were not computed")


def sweep_job(
    spec: SweepSpec,
    names: tuple[str, ...],
    rows_of,
    meanwhile: Callable[[], Any] | None = None,
) -> Job:
    """The :class:`Job` of a sweep or Monte Carlo study: :func:`run_chunk` on rows of
    values of `names` (``rows_of(idx)``), returning ``(t_cr, status, route)`` per chunk;
    while workers compute, this process imports the output writer
    (:func:`prefetch_output`) and then calls `meanwhile` (the study's own serial work).

    A point's result never depends on its chunk (:mod:`obturator.solve.plan`), so the
    job is separable. Where the points are packed, the job can
    pack them ahead (:mod:`.ahead`), and its chunks are runs of consecutive points: with
    ``shared_maps`` the cases of one spin band reuse the band's grid within a worker
    (a spin axis varies fastest), which saves time, not bits.
    """
    lanes = batchable(spec.options)
    job = Job(
        run_chunk,
        lambda idx: (spec, names, rows_of(idx)),
        partial(warm, spec.options),
        meanwhile=prefetch_output
        if meanwhile is None
        else partial(_both, prefetch_output, meanwhile),
        contiguous=lanes,
    )
    if lanes:
        job = replace(job, ahead=partial(_pack_while_loading, job, spec, names, rows_of))
    return job


def _both(first: Callable[[], Any], second: Callable[[], Any]) -> None:
    first()
    second()


def _pack_while_loading(
    job: Job,
    spec: SweepSpec,
    names: tuple[str, ...],
    rows_of: Callable[[np.ndarray], np.ndarray],
    chunks: list[np.ndarray],
) -> Job:
    """`job` with the points a helper packed while this process loaded the integrators
    (:func:`.ahead.pack_ahead`): where fork is safe, a core is spare and the integrators
    are not loaded yet; else `job` as it is, warm."""
    assert job.warm is not None
    with gc_frozen():
        if (
            mp_context().get_start_method() != "fork"
            or default_workers() < 2
            or is_warm(spec.options)
            or not chunks
        ):
            job.warm()
            return job
        done = pack_ahead(spec, names, rows_of, np.concatenate(chunks), job.warm)
    if not len(done):
        return job
    return replace(job, args_of=lambda idx: (spec, names, rows_of(idx), done.take(idx)))


def prefetch_output() -> None:
    """Load the NetCDF writer (netCDF4 and HDF5) while pool workers compute.

    Its first import and first file are serial work that would otherwise follow the
    computation. Done while the workers run even with as many workers as cores: the
    chunks beside it slow down by the share of a core it takes, less than the same work
    after the last chunk costs (``python -m benchmarks.sweeps``; ``docs/benchmarks.md``,
    history, "a sweep's serial tail"). Not done in a thread for in-process studies:
    that work holds the GIL and made a short sweep slower (same document, history).
    """
    import tempfile

    from .table import StudyTable, write_table_netcdf

    tiny = StudyTable({"t_cr": ("x", np.zeros(1), {})}, {})
    with tempfile.TemporaryDirectory(prefix="obturator-") as tmp:
        write_table_netcdf(tiny, os.path.join(tmp, "warm.nc"))
