"""Where the chunks of a run are computed: in this process or a local process pool.

Both executors (and :class:`~obturator.runs.cluster.DaskCluster`) share one
interface (:class:`Executor`): ``run(job, chunks, sink, advance)`` computes every
chunk of ``job`` and hands each result to ``sink`` as it arrives.
:func:`choose_executor` picks one:

* :class:`InProcess` for ``workers=1`` or a single chunk, and for runs too small
  to repay starting workers (:func:`~obturator.runs.chunks.probe`);
* :class:`ProcessPool` for ``workers=N >= 2``: a
  :class:`concurrent.futures.ProcessPoolExecutor` with N processes. On Linux,
  from a single-threaded parent, the workers are forked after the job's warm-up
  (the compiled integrators) ran once in the parent, so every worker starts warm;
  otherwise they are spawned. Workers die with the main process
  (``PR_SET_PDEATHSIG``, :func:`die_with_parent`);
* :class:`~obturator.runs.cluster.DaskCluster` for a scheduler address or client.

A worker the system kills (the out-of-memory killer, ``kill -9``) breaks a process
pool: the pool's unfinished chunks run again on a fresh pool, at most
:data:`LOST_WORKER_RETRIES` times a run, each time with one notice; then the run stops
with :class:`LostWorker` (the runner turns it into one line saying that a rerun
resumes). Chunks are the unit of work and of results, so a retried chunk gives the
bits it would have given the first time.
"""

from __future__ import annotations

import gc
import multiprocessing
import os
import sys
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor, as_completed
from concurrent.futures.process import BrokenProcessPool
from contextlib import AbstractContextManager, contextmanager, suppress
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from ..errors import InputError
from .chunks import Job

__all__ = [
    "Advance",
    "Executor",
    "InProcess",
    "LOST_WORKER_RETRIES",
    "LostWorker",
    "ProcessPool",
    "Sink",
    "Track",
    "choose_executor",
    "default_workers",
    "die_with_parent",
    "gc_frozen",
    "mp_context",
    "resolve_workers",
]

#: ``sink(indices, result)``: receives each finished chunk's result.
Sink = Callable[[np.ndarray, Any], None]
#: ``advance(n)``: n more tasks are done (the progress display).
Advance = Callable[[int], None]
#: ``track()`` opens the progress display and yields ``advance``.
Track = Callable[[], AbstractContextManager[Advance]]


#: Times a run's unfinished chunks run again on a fresh pool after a worker was lost.
LOST_WORKER_RETRIES = 2


class LostWorker(RuntimeError):
    """A worker process was lost more often than :data:`LOST_WORKER_RETRIES` allows."""


def default_workers() -> int:
    """Number of CPUs this process may use (the default worker count)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


def resolve_workers(workers: int | None) -> int:
    """The local worker count: `workers`, or :func:`default_workers` if None (>= 1)."""
    n = default_workers() if workers is None else int(workers)
    if n < 1:
        raise InputError("workers", f"{workers} is outside the allowed range >= 1")
    return n


class Executor(Protocol):
    """Runs the chunks of a job and hands each result to `sink`."""

    #: ``"local"`` or ``"dask.distributed"`` (stored in the results).
    backend: str
    #: Local processes used (1: in this process; 0: a cluster).
    workers: int

    def run(self, job: Job, chunks: list[np.ndarray], sink: Sink, track: Track) -> None:
        """Compute every chunk; call ``sink(idx, result)`` as each finishes, and advance
        the display that ``track()`` opens (after any worker has started)."""


@dataclass
class InProcess:
    """Every chunk in this process, in order."""

    backend: str = "local"
    workers: int = 1

    def run(self, job: Job, chunks: list[np.ndarray], sink: Sink, track: Track) -> None:
        """See :class:`Executor`."""
        with track() as advance:
            for idx in chunks:
                sink(idx, job.run(idx))
                advance(idx.size)


@dataclass
class ProcessPool:
    """Chunks on `workers` local processes (forked warm where safe, else spawned)."""

    workers: int
    backend: str = "local"

    def run(self, job: Job, chunks: list[np.ndarray], sink: Sink, track: Track) -> None:
        """See :class:`Executor`; a lost worker's chunks are retried (module notes)."""
        ctx = mp_context()
        if ctx.get_start_method() == "fork" and job.warm is not None:
            with gc_frozen():
                job.warm()  # workers inherit the loaded integrator
        pool, pending = self._start(ctx, job, chunks)
        retries = 0
        try:
            if job.meanwhile is not None:
                job.meanwhile()  # this process would only wait
            # as_completed registers one waiter per future once; wait(FIRST_COMPLETED) in
            # a loop re-registered on every pending future per call, O(chunks^2): 15 % of
            # a core in this process during a 3,907-chunk sweep, taken from the workers
            with track() as advance:
                while True:
                    lost = []
                    for fut in as_completed(pending):
                        idx = pending[fut]
                        try:
                            result = fut.result()
                        except BrokenProcessPool:
                            lost.append(idx)
                            continue
                        sink(idx, result)
                        advance(idx.size)
                    if not lost:
                        break
                    why = _why_lost(pool)
                    _stop(pool)
                    if retries == LOST_WORKER_RETRIES:
                        raise LostWorker(f"{why}, {retries + 1} times in this run")
                    retries += 1
                    print(
                        f"obturator: notice: {why}; its pool's {len(lost)} unfinished "
                        f"chunk{'s' if len(lost) != 1 else ''} run again on fresh workers "
                        f"(retry {retries} of {LOST_WORKER_RETRIES})",
                        file=sys.stderr,
                    )
                    # forked only while no other thread runs (a progress bar's may)
                    pool, pending = self._start(mp_context(), job, lost)
        except BaseException:
            _stop(pool)
            raise
        pool.shutdown(wait=True)

    def _start(
        self, ctx: multiprocessing.context.BaseContext, job: Job, chunks: list[np.ndarray]
    ) -> tuple[ProcessPoolExecutor, dict[Any, np.ndarray]]:
        """A pool with every chunk submitted (and, with fork, every worker started, frozen)
        before the progress display starts its refresh thread."""
        pool = ProcessPoolExecutor(
            max_workers=self.workers,
            mp_context=ctx,
            initializer=die_with_parent,
            initargs=(os.getpid(),),
        )
        try:
            with gc_frozen():
                pending = {pool.submit(job.fn, *job.args_of(idx)): idx for idx in chunks}
        except BaseException:
            _stop(pool)
            raise
        pool._obturator_workers = list(  # type: ignore[attr-defined]
            (getattr(pool, "_processes", None) or {}).values()
        )
        return pool, pending


def _why_lost(pool: ProcessPoolExecutor) -> str:
    """How the pool's lost worker ended, from the exit codes of its processes."""
    import signal

    workers = getattr(pool, "_obturator_workers", [])
    for proc in workers:  # the dead one is reaped at once; the others as the pool ends them
        with suppress(Exception):
            proc.join(timeout=1.0)
    # The pool's manager thread reaps the same processes: where it won the race for
    # waitpid, `exitcode` reads None here until that thread has stored the code.
    deadline = time.monotonic() + 5.0
    while True:
        # the pool ends the other workers itself, with SIGTERM
        ended = [c for c in (p.exitcode for p in workers) if c not in (None, 0, -signal.SIGTERM)]
        if ended or time.monotonic() > deadline:
            break
        time.sleep(0.02)
    if not ended:
        return "a worker process ended abruptly"
    code = ended[0]
    if code > 0:
        return f"a worker process exited with code {code}"
    try:
        name = signal.Signals(-code).name
    except ValueError:
        name = f"signal {-code}"
    if -code == signal.SIGKILL:
        name += " (the out-of-memory killer, or kill -9)"
    return f"a worker process was killed by {name}"


def _stop(pool: ProcessPoolExecutor) -> None:
    """End a pool now: cancel the waiting chunks and terminate the running ones.

    Without it the interpreter's exit waits for every running chunk (a full disk or
    Ctrl-C during a Monte Carlo study with convergence checks: minutes). Their results
    would be lost anyway; the finished chunks are in the resume store.
    """
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for proc in processes:
        with suppress(Exception):
            proc.terminate()
    for proc in processes:
        with suppress(Exception):
            proc.join(timeout=5)


def choose_executor(workers: int, scheduler: Any, n_chunks: int) -> Executor:
    """Dask if a scheduler is given, else a pool of up to `workers` processes, or this
    process when one would do. With no chunk to compute nothing is started (the
    executor still reports `workers`).
    """
    if scheduler is not None:
        from .cluster import DaskCluster

        return DaskCluster(scheduler)
    if n_chunks == 0:
        return InProcess(workers=workers)
    if min(workers, n_chunks) <= 1:
        return InProcess()
    return ProcessPool(min(workers, n_chunks))


@contextmanager
def gc_frozen() -> Iterator[None]:
    """Leave the objects alive now out of garbage collection while loading and forking.

    A collection of the oldest generation visits every tracked object: while a fresh
    process loads the compiled integrators (numba allocates much) that is a sizeable
    share of the load (``docs/benchmarks.md``), and a forked child that collects writes to every
    inherited object's page, which copy-on-write then copies. Python's documented
    remedy is :func:`gc.freeze` before fork (the children keep those objects frozen);
    this process unfreezes them afterwards and collects as before.
    """
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()


def mp_context() -> multiprocessing.context.BaseContext:
    """fork where it is safe (Linux, no other thread but the signal watcher), else spawn."""
    # fork is cheap and inherits the loaded integrator; it is only used on Linux while
    # this process runs a single thread (a progress bar's refresh thread starts after
    # the workers, see ProcessPool.start); otherwise spawn, which is safe but needs the
    # usual ``if __name__ == "__main__":`` guard in scripts
    others = [t for t in threading.enumerate() if t.name != "obturator-signals"]
    if sys.platform == "linux" and len(others) == 1:  # the signal watcher only reads a pipe
        return multiprocessing.get_context("fork")
    return multiprocessing.get_context("spawn")


def die_with_parent(parent: int) -> None:
    """Worker initializer: end this worker when the main process ends, however it ends.

    Linux ``prctl(PR_SET_PDEATHSIG, SIGKILL)``: a SIGKILL or SIGTERM of the main
    process (which runs no clean-up) must not leave workers computing for good.
    Elsewhere nothing is set (the pool still ends them on a normal exit).
    """
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the main process's to handle
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.set_wakeup_fd(-1)  # the main process's watcher pipe is not ours
    if sys.platform.startswith("linux"):
        import ctypes

        try:
            ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
        except (OSError, AttributeError):  # pragma: no cover - unusual libc
            return
        if os.getppid() != parent:  # the parent died before prctl took effect
            os._exit(1)
