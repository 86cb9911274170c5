"""Where the chunks of a study run: in this process, a process pool, or a Dask cluster.

The three executors share one interface (:class:`Executor`): ``run(job,
chunks, sink, progress)`` computes every chunk of ``job`` and hands each
result to ``sink`` as it arrives. :func:`choose_executor` picks one:

* :class:`InProcess` for ``workers=1`` or a single chunk, and for studies
  too small to repay starting workers (:func:`probe_cost`);
* :class:`ProcessPool` for ``workers=N >= 2``: a
  :class:`concurrent.futures.ProcessPoolExecutor` with N processes. On Linux,
  from a single-threaded parent, the workers are forked after the compiled
  integrator has been loaded once in the parent, so every worker starts warm;
  otherwise they are spawned and each loads the numba cache once, in its
  first chunk. Workers die with the main process (``PR_SET_PDEATHSIG``);
* :class:`DaskCluster` for ``scheduler="tcp://host:port"`` or a
  :class:`distributed.Client`: the same chunks as ``client.submit`` tasks (the
  workers need ``obturator`` importable). A lost scheduler or worker is a
  :class:`~obturator.errors.ClusterError` within seconds, never a hang.
"""

from __future__ import annotations

import gc
import math
import multiprocessing
import os
import sys
import threading
import time
from collections.abc import Callable, Iterator
from concurrent.futures import ProcessPoolExecutor, as_completed
from contextlib import AbstractContextManager, contextmanager, suppress
from dataclasses import dataclass, replace
from functools import partial
from typing import Any, Protocol

import numpy as np

from ..errors import ClusterError, InputError
from ..solve import batchable
from ..solve.many import RADAU_LANES_MIN
from .ahead import pack_ahead
from .points import is_warm, run_chunk, warm
from .spec import SweepSpec

__all__ = [
    "CONNECT_TIMEOUT_S",
    "LOST_SCHEDULER_S",
    "Job",
    "sweep_job",
    "mp_context",
    "die_with_parent",
    "Executor",
    "InProcess",
    "ProcessPool",
    "DaskCluster",
    "choose_executor",
    "probe_cost",
    "POOL_MIN_SERIAL_S",
    "resolve_workers",
    "default_workers",
    "gc_frozen",
    "LANE_CHUNK",
    "TASK_CHUNK",
    "make_chunks",
    "progress_bar",
]

#: Largest default chunk of tasks computed one by one (a chunk is the unit of resumed work).
TASK_CHUNK = 256
#: Largest default chunk of points integrated in lanes (:func:`obturator.solve.opening_times`):
#: a chunk's stiff points go through Radau IIA lanes together, which pay off from a few
#: dozen per chunk and keep improving with more (measured, 10,000 rig points over
#: 100-700 rad/s in one process, AMD EPYC Zen 5: 1.84-1.96 s in 256-point chunks,
#: 1.71-1.78 s in 500-625, 1.70-1.71 s in 1,250-5,000; on the Intel machine of the
#: previous release 7.0 s with 64-point chunks, 5.1 s with 256).
LANE_CHUNK = 1024
_CHUNKS_PER_WORKER = 8

#: ``sink(indices, result)``: receives each finished chunk's result.
Sink = Callable[[np.ndarray, Any], None]
#: ``progress()`` opens the progress display and yields ``advance(n_points)``.
Progress = Callable[[], AbstractContextManager[Callable[[int], None]]]


def default_workers() -> int:
    """Number of CPUs this process may use (the default worker count)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


def make_chunks(
    todo: np.ndarray, workers: int, chunk_size: int | None, max_chunk: int = TASK_CHUNK
) -> list[np.ndarray]:
    """Split the flat indices `todo` into chunks of about `chunk_size` points.

    A chunk takes every k-th remaining point, which mixes cheap and expensive
    points (t_cr grows with spin) and balances the load. Default size: about
    8 chunks per worker, at most `max_chunk` points (256; sweeps in lanes
    :data:`LANE_CHUNK`).
    """
    if todo.size == 0:
        return []
    if chunk_size is None:
        chunk_size = max(1, min(max_chunk, math.ceil(todo.size / (_CHUNKS_PER_WORKER * workers))))
    elif int(chunk_size) < 1:
        raise InputError("chunk_size", f"{chunk_size} is outside the allowed range >= 1")
    n_chunks = math.ceil(todo.size / int(chunk_size))
    return [todo[k::n_chunks] for k in range(n_chunks)]


@dataclass(frozen=True)
class Job:
    """What every chunk computes: ``fn(*args_of(idx))`` for the flat indices `idx`.

    Attributes
    ----------
    fn : callable
        Module-level (picklable) function computing one chunk; its result goes to
        the sink as it is.
    args_of : callable
        Flat point indices -> the arguments of `fn` (called in this process).
    warm : callable, optional
        Loads the compiled code once before workers are forked (they inherit it)
        and before a probe chunk is timed.
    ahead : callable, optional
        ``ahead(chunks)``: does what `warm` does while a helper process prepares the
        chunks' arguments, and returns the job that uses them (:mod:`.ahead`).
    """

    fn: Callable[..., Any]
    args_of: Callable[[np.ndarray], tuple[Any, ...]]
    warm: Callable[[], None] | None = None
    ahead: Callable[[list[np.ndarray]], Job] | None = None

    def run(self, idx: np.ndarray) -> Any:
        """Compute one chunk in this process."""
        return self.fn(*self.args_of(idx))


def sweep_job(spec: SweepSpec, names: tuple[str, ...], rows_of, largest_chunk: int = 0) -> Job:
    """The :class:`Job` of a sweep or Monte Carlo study: :func:`run_chunk` on rows of
    values of `names` (``rows_of(idx)``), returning ``(t_cr, status)`` per chunk.

    The warm-up loads the Radau IIA lanes only when a chunk (`largest_chunk` points)
    can hold enough stiff points to use them: a small sweep does not pay their load.
    Where the points run in lanes, the job can pack points ahead (:mod:`.ahead`).
    """
    radau_lanes = largest_chunk >= RADAU_LANES_MIN
    job = Job(
        run_chunk,
        lambda idx: (spec, names, rows_of(idx)),
        partial(warm, spec.options, radau_lanes=radau_lanes),
    )
    if batchable(spec.options, spec.check_convergence):
        job = replace(
            job, ahead=partial(_pack_while_loading, job, spec, names, rows_of, radau_lanes)
        )
    return job


def _pack_while_loading(
    job: Job,
    spec: SweepSpec,
    names: tuple[str, ...],
    rows_of: Callable[[np.ndarray], np.ndarray],
    radau_lanes: bool,
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
            or is_warm(spec.options, radau_lanes)
            or not chunks
        ):
            job.warm()
            return job
        done = pack_ahead(spec, names, rows_of, np.concatenate(chunks), job.warm)
    if not len(done):
        return job
    return replace(job, args_of=lambda idx: (spec, names, rows_of(idx), done.take(idx)))


class Executor(Protocol):
    """Runs the chunks of a job and hands each result to `sink`."""

    #: ``"local"`` or ``"dask.distributed"`` (stored in the results).
    backend: str
    #: Local processes used (1: in this process; 0: a cluster).
    workers: int

    def run(self, job: Job, chunks: list[np.ndarray], sink: Sink, progress: Progress) -> None:
        """Compute every chunk; call ``sink(idx, result)`` as each finishes."""


@dataclass
class InProcess:
    """Every chunk in this process, in order."""

    backend: str = "local"
    workers: int = 1

    def run(self, job: Job, chunks: list[np.ndarray], sink: Sink, progress: Progress) -> None:
        """See :class:`Executor`."""
        with progress() as advance:
            for idx in chunks:
                sink(idx, job.run(idx))
                advance(idx.size)


@dataclass
class ProcessPool:
    """Chunks on `workers` local processes (forked warm where safe, else spawned)."""

    workers: int
    backend: str = "local"

    def run(self, job: Job, chunks: list[np.ndarray], sink: Sink, progress: Progress) -> None:
        """See :class:`Executor`."""
        ctx = mp_context()
        if ctx.get_start_method() == "fork" and job.warm is not None:
            with gc_frozen():
                job.warm()  # workers inherit the loaded integrator
        pool = ProcessPoolExecutor(
            max_workers=self.workers,
            mp_context=ctx,
            initializer=die_with_parent,
            initargs=(os.getpid(),),
        )
        try:
            # every task is submitted (and, with fork, every worker started, frozen)
            # before the progress bar starts its refresh thread
            with gc_frozen():
                pending = {pool.submit(job.fn, *job.args_of(idx)): idx for idx in chunks}
            if default_workers() > self.workers:  # a core is idle: use it meanwhile
                _prefetch_output()
            # as_completed registers one waiter per future once; wait(FIRST_COMPLETED) in
            # a loop re-registered on every pending future per call, O(chunks^2): 15 % of
            # a core in this process during a 3,907-chunk sweep, taken from the workers
            with progress() as advance:
                for fut in as_completed(pending):
                    idx = pending[fut]
                    sink(idx, fut.result())
                    advance(idx.size)
        except BaseException:
            pool.shutdown(wait=False, cancel_futures=True)
            raise
        pool.shutdown(wait=True)


@dataclass
class DaskCluster:
    """Chunks as tasks on a Dask cluster (an address or a ``distributed.Client``)."""

    scheduler: Any
    backend: str = "dask.distributed"
    workers: int = 0

    def run(self, job: Job, chunks: list[np.ndarray], sink: Sink, progress: Progress) -> None:
        """Chunks as tasks on a Dask cluster; finished chunks go to `sink` as they arrive.

        A scheduler or worker that dies mid-study is a :class:`ClusterError` (one
        line on the command line) within LOST_SCHEDULER_S, never a hang: the
        finished chunks are already in the resume store, so the study resumes
        (locally or on a new cluster) to the same result.
        """
        from distributed import wait as dask_wait

        client, owned = _client(self.scheduler)
        futures = []
        try:
            index_of = {}
            for idx in chunks:
                fut = client.submit(job.fn, *job.args_of(idx), pure=False)
                index_of[fut.key] = idx
                futures.append(fut)
            _prefetch_output()
            pending = set(futures)
            lost_since: float | None = None
            with progress() as advance:
                while pending:
                    try:
                        dask_wait(list(pending), timeout=1.0, return_when="FIRST_COMPLETED")
                    except Exception:  # nothing finished within 1 s (or the wait itself broke)
                        pass
                    if client.status != "running":
                        lost_since = lost_since or time.monotonic()
                        if time.monotonic() - lost_since > LOST_SCHEDULER_S:
                            raise ClusterError(f"lost the Dask scheduler {client.scheduler!s}")
                    else:
                        lost_since = None
                    for fut in [f for f in pending if f.status != "pending"]:
                        pending.discard(fut)
                        if fut.status != "finished":
                            raise ClusterError(f"a Dask task ended with status {fut.status!r}")
                        try:
                            result = fut.result(timeout=LOST_SCHEDULER_S)
                        except Exception as exc:
                            raise ClusterError(f"a Dask task failed: {exc}") from None
                        idx = index_of[fut.key]
                        sink(idx, result)
                        advance(idx.size)
        except BaseException:
            if futures:
                with suppress(Exception):
                    client.cancel(futures)
            raise
        finally:
            if owned:
                with suppress(Exception):
                    client.close(timeout=2)


def resolve_workers(workers: int | None) -> int:
    """The local worker count: `workers`, or :func:`default_workers` if None (>= 1)."""
    n = default_workers() if workers is None else int(workers)
    if n < 1:
        raise InputError("workers", f"{workers} is outside the allowed range >= 1")
    return n


def choose_executor(workers: int, scheduler: Any, n_chunks: int) -> Executor:
    """Dask if a scheduler is given, else a pool of up to `workers` processes, or this
    process when one would do. With no chunk to compute nothing is started (the
    executor still reports `workers`).
    """
    if scheduler is not None:
        return DaskCluster(scheduler)
    if n_chunks == 0:
        return InProcess(workers=workers)
    if min(workers, n_chunks) <= 1:
        return InProcess()
    return ProcessPool(min(workers, n_chunks))


#: A pool is started only when the points left after the probe chunk would take at
#: least this long in this process [s]. Two forked workers cost ~0.04 s on the 2-core
#: reference machine (``python -m benchmarks``: 200 rig points took 0.32 s in a loop
#: and 0.196 s on a 2-process pool), so below ~0.1 s of work the pool cannot win.
POOL_MIN_SERIAL_S = 0.1
#: Points of the probe (from the first chunk). Timing it in this process delays the
#: workers; with whole 256-point chunks the probe was ~4 % of a 10,000-point rig sweep
#: and left an odd number of chunks for 2 workers.
PROBE_POINTS = 32


def probe_cost(pool: ProcessPool, job: Job, chunks: list[np.ndarray], sink: Sink) -> Executor:
    """Run the first :data:`PROBE_POINTS` points of the first chunk here, timed, and keep
    the rest here if that is cheaper.

    Chunks take every k-th point of the study (see :func:`make_chunks`), so the probe's
    cost per point is representative. Its results go to `sink` (and the resume store)
    like any other chunk's; they are removed from `chunks`. Returns `pool`, or an
    :class:`InProcess` executor when the remaining points would take less than
    :data:`POOL_MIN_SERIAL_S` here.
    """
    if len(chunks) < 2:
        return pool
    if job.warm is not None:
        job.warm()  # compile/load once; not part of the per-point cost
    # the probe runs here before the workers start: a slice of the first chunk is
    # enough to time, and the rest of the chunk goes to the workers like the others
    probe, rest = chunks[0][:PROBE_POINTS], chunks[0][PROBE_POINTS:]
    if rest.size:
        chunks[0] = rest
    else:
        chunks.pop(0)
    # CPU time of this thread: other threads (or a busy machine) must not inflate it
    t0 = time.thread_time()
    sink(probe, job.run(probe))
    per_point = (time.thread_time() - t0) / probe.size
    remaining = per_point * sum(c.size for c in chunks)
    return pool if remaining >= POOL_MIN_SERIAL_S else InProcess()


@contextmanager
def gc_frozen() -> Iterator[None]:
    """Leave the objects alive now out of garbage collection while loading and forking.

    A collection of the oldest generation visits every tracked object: while a fresh
    process loads the compiled integrators (numba allocates much) that was ~15 % of the
    load (0.36 -> 0.31 s measured), and a forked child that collects writes to every
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
    # fork is cheap and inherits the loaded integrator; it is only used on
    # Linux while this process runs a single thread (the progress bar's thread
    # starts after the workers, see ProcessPool.run); otherwise spawn, which is safe
    # but needs the usual ``if __name__ == "__main__":`` guard in scripts
    others = [t for t in threading.enumerate() if t.name != "obturator-signals"]
    if sys.platform == "linux" and len(others) == 1:  # the signal watcher only reads a pipe
        return multiprocessing.get_context("fork")
    return multiprocessing.get_context("spawn")


@contextmanager
def progress_bar(
    enabled: bool, total: int, done: int, label: str
) -> Iterator[Callable[[int], None]]:
    """Yield ``advance(n)``: a rich progress bar on stderr (a no-op when not enabled)."""
    if not enabled:
        yield lambda n: None
        return
    from rich.console import Console
    from rich.progress import (
        BarColumn,
        MofNCompleteColumn,
        Progress,
        TextColumn,
        TimeElapsedColumn,
        TimeRemainingColumn,
    )

    with Progress(
        TextColumn("{task.description}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        TextColumn("eta"),
        TimeRemainingColumn(),
        console=Console(stderr=True),
        transient=True,
    ) as bar:
        task = bar.add_task(label, total=total, completed=done)
        yield lambda n: bar.advance(task, n)


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


def _prefetch_output() -> None:
    """Import xarray and its NetCDF writer while pool workers compute (~0.7-1 s).

    A first write to a file imports the engine, the encoders and the scheduler
    probes behind xarray's write locks (with dask installed: dask.distributed).
    Only where a core is left over for it: with as many workers as cores it took
    that time from them (a 10,000-point rig sweep on 2 workers and 2 cores: the
    chunks running beside it took up to twice as long).
    Not done in a thread for in-process studies: that work holds the GIL and
    made a 20-point sweep slower (measured 1.6-1.7 s without, 1.8-2.1 s with).
    """
    import tempfile

    import xarray as xr

    tiny = xr.Dataset({"t_cr": ("x", np.zeros(1))})
    with tempfile.TemporaryDirectory(prefix="obturator-") as tmp:
        tiny.to_netcdf(os.path.join(tmp, "warm.nc"))


#: Seconds after which connecting to a Dask scheduler is given up.
CONNECT_TIMEOUT_S = 10.0


def _client(scheduler: Any) -> tuple[Any, bool]:
    """A connected ``distributed.Client``, or one InputError within CONNECT_TIMEOUT_S.

    The connection is made in a helper thread with a hard deadline: a port that
    accepts a connection but never speaks the Dask protocol would otherwise
    block the handshake for many minutes.
    """
    if not isinstance(scheduler, str):
        return scheduler, False
    try:
        from distributed import Client
    except ImportError:
        raise InputError(
            "scheduler", "needs dask.distributed: pip install 'obturator[cluster]'"
        ) from None
    box: dict[str, Any] = {}

    def connect() -> None:
        try:
            box["client"] = Client(scheduler, timeout=f"{CONNECT_TIMEOUT_S:g}s")
        except Exception as exc:  # any failure becomes one line for the user
            box["error"] = exc

    thread = threading.Thread(target=connect, name="obturator-dask-connect", daemon=True)
    thread.start()
    thread.join(CONNECT_TIMEOUT_S + 2.0)
    if "client" in box:
        return box["client"], True
    why = box.get("error")
    text = " ".join(str(why).split()) if why is not None else "no answer"
    raise InputError(
        "scheduler",
        f"cannot connect to {scheduler!r} within {CONNECT_TIMEOUT_S:g} s: {text}",
    )


#: Seconds without a connected scheduler after which a running study gives up.
LOST_SCHEDULER_S = 10.0
