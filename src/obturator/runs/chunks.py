"""What a run computes (:class:`Job`), in which chunks (:func:`make_chunks`), and a timed
probe of its cost per task (:func:`probe`).

A chunk is the unit of work handed to a worker and of resumed work (one record of
the resume store).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._docs import field_docs
from ..errors import InputError

__all__ = ["Job", "PROBE_TASKS", "Probe", "TASK_CHUNK", "chunk_length", "make_chunks", "probe"]

#: Largest default chunk of tasks computed one by one.
TASK_CHUNK = 256
_CHUNKS_PER_WORKER = 8
#: Tasks of the probe (from the first chunk). Timing it in this process delays the
#: workers; a whole chunk as the probe delayed a rig sweep noticeably and left an odd
#: number of chunks for two workers (``docs/benchmarks.md``, history).
PROBE_TASKS = 32


@field_docs
@dataclass(frozen=True)
class Job:
    """What every chunk computes: ``fn(*args_of(idx))`` for the flat task indices `idx`."""

    #: Module-level (picklable) function computing one chunk; its result goes to the sink as it is.
    fn: Callable[..., Any]
    #: Flat task indices -> the arguments of `fn` (called in this process).
    args_of: Callable[[np.ndarray], tuple[Any, ...]]
    #: Loads the compiled code once before workers are forked (they inherit it) and before a probe
    #: is timed.
    warm: Callable[[], None] | None = None
    #: ``ahead(chunks)``: does what `warm` does while a helper process prepares the chunks'
    #: arguments, and returns the job that uses them (pool runs only).
    ahead: Callable[[list[np.ndarray]], Job] | None = None
    #: Work for this process while pool or Dask workers compute (a study imports its output writer
    #: and checks its points against the validated data); in-process runs skip it.
    meanwhile: Callable[[], None] | None = None
    #: Whether a task's result is the same whatever chunk it runs in (False for points integrated in
    #: lanes, where a chunk's count of stiff points picks the Radau path: a probe in this process
    #: then only times, and its tasks run again in their chunk, so a run's results do not depend on
    #: whether it was probed).
    separable: bool = True
    #: Whether neighbouring tasks share work, so a chunk is a run of consecutive tasks
    #: (a sweep's spins share the set-valued solver's return maps,
    #: :mod:`obturator.core.integrators.stick_slip_family`); else every k-th task.
    contiguous: bool = False

    def run(self, idx: np.ndarray) -> Any:
        """Compute one chunk in this process."""
        return self.fn(*self.args_of(idx))


def make_chunks(
    todo: np.ndarray,
    workers: int,
    chunk_size: int | None,
    max_chunk: int = TASK_CHUNK,
    contiguous: bool = False,
) -> list[np.ndarray]:
    """Split the flat indices `todo` into chunks of about `chunk_size` tasks.

    A chunk takes every k-th remaining task, which mixes cheap and expensive
    points (t_cr grows with spin) and balances the load; with `contiguous` it is a
    run of consecutive tasks (:attr:`Job.contiguous`), and the chunks come in the
    order first, last, second, second last, ...: the pools hand them out in order as
    workers free up, so the last ones handed out come from the middle of the run, and
    a cost that rises (or falls) along the run leaves no costly chunk for the end (the
    workers of a rig sweep over 40-1000 rad/s end closer together: ``docs/benchmarks.md``).
    Default size: about 8 chunks per worker, at most `max_chunk` tasks.
    """
    if todo.size == 0:
        return []
    n_chunks = math.ceil(todo.size / chunk_length(todo.size, workers, chunk_size, max_chunk))
    if contiguous:
        runs = np.array_split(todo, n_chunks)
        ends = np.c_[np.arange(n_chunks), np.arange(n_chunks)[::-1]].ravel()
        return [runs[k] for k in dict.fromkeys(ends.tolist())]
    return [todo[k::n_chunks] for k in range(n_chunks)]


def chunk_length(n_todo: int, workers: int, chunk_size: int | None, max_chunk: int) -> int:
    """Tasks per chunk of :func:`make_chunks` (the largest chunk holds about this many)."""
    if chunk_size is None:
        return max(1, min(max_chunk, math.ceil(n_todo / (_CHUNKS_PER_WORKER * workers))))
    if int(chunk_size) < 1:
        raise InputError("chunk_size", f"{chunk_size} is outside the allowed range >= 1")
    return int(chunk_size)


@field_docs
@dataclass(frozen=True)
class Probe:
    """Cost of the probe's tasks, timed in this process."""

    #: Tasks the probe ran (at most :data:`PROBE_TASKS`).
    n_tasks: int
    #: CPU time of this thread per task [s].
    seconds_per_task: float

    def serial_s(self, n_tasks: int) -> float:
        """Estimated time of `n_tasks` more tasks in one process [s]."""
        return self.seconds_per_task * n_tasks


def probe(
    job: Job,
    chunks: list[np.ndarray],
    sink: Callable[[np.ndarray, Any], None],
    keep: bool = True,
    n_tasks: int = PROBE_TASKS,
) -> Probe:
    """Run the first `n_tasks` tasks of the first chunk here, timed.

    Chunks take every k-th task of the run (see :func:`make_chunks`), so the probe's
    cost per task is representative (of a contiguous job's first chunk, less so).
    With `keep`, its result goes to `sink` (and the resume store) like any other
    chunk's and its tasks are removed from `chunks` (in place); else it is only timed.
    The count is fixed, never from a timing: where a task's result depends on the tasks
    it runs with (:attr:`Job.separable`), the probe's tasks run as one chunk of their own.
    """
    if job.warm is not None:
        job.warm()  # compile/load once; not part of the per-task cost
    first, rest = chunks[0][:n_tasks], chunks[0][n_tasks:]
    if keep:
        if rest.size:
            chunks[0] = rest
        else:
            chunks.pop(0)
    # CPU time of this thread: other threads (or a busy machine) must not inflate it
    t0 = time.thread_time()
    result = job.run(first)
    seconds = time.thread_time() - t0
    if keep:
        sink(first, result)
    return Probe(int(first.size), seconds / first.size)
