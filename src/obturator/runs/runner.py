"""The one runner of every study: workers, scheduler, chunking, resume store, progress.

A study describes its work as a :class:`~obturator.runs.chunks.Job` over flat task
indices and collects the results in a :class:`Results`; :meth:`Runner.run` restores
finished tasks from the resume store, splits the rest into chunks, probes their cost
(not before a pool that pays at any cost: :data:`POOL_SURE_TASKS`), announces the plan,
computes them where :func:`~obturator.runs.pools.choose_executor` says (this process, a
process pool, a Dask cluster) and records every finished chunk.
:meth:`Runner.map` is the same for a list of picklable tasks with JSON-ready results,
stored under the content hash of each task (:class:`~obturator.runs.results.MapResults`).
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import partial
from typing import Any, Protocol

import numpy as np

from ..errors import InputError
from .chunks import PROBE_TASKS, TASK_CHUNK, Job, make_chunks, probe
from .cluster import needs_cluster_extra
from .pools import InProcess, LostWorker, ProcessPool, choose_executor, default_workers
from .progress import Progress
from .results import MapResults, run_tasks
from .store import ResumeStore, full_disk_error

__all__ = ["POOL_MIN_SERIAL_S", "POOL_SURE_TASKS", "Results", "RunInfo", "Runner"]

#: A pool is started only when the tasks left after the probe would take at least this
#: long in this process [s]: below it, starting the workers costs more than they save
#: (the sweep table of ``python -m benchmarks``; ``docs/benchmarks.md``, history).
POOL_MIN_SERIAL_S = 0.1
#: A pool run of at least this many tasks whose probe would be one task starts its
#: workers without it: that many of the cheapest t_cr (``docs/benchmarks.md``, "Cost
#: across the operating range") are already more than :data:`POOL_MIN_SERIAL_S` of
#: work, and the one task (the costliest end of a sweep) is serial work with the other
#: cores idle.
POOL_SURE_TASKS = 8192


class Results(Protocol):
    """Where a run's results go, and how they are stored and restored."""

    def todo(self) -> np.ndarray:
        """Flat indices of the tasks still to compute."""

    def put(self, idx: np.ndarray, result: Any) -> tuple[list[Any], Any]:
        """Keep one chunk's result; return its store record ``(keys, values)``."""

    def restore(self, keys: list[Any], values: Any) -> bool:
        """Take a stored record; False if it does not fit this study (recomputed)."""


@dataclass(frozen=True)
class RunInfo:
    """How one :meth:`Runner.run` went: tasks computed and resumed, where, how long [s]."""

    n_computed: int
    n_resumed: int
    workers: int
    backend: str
    elapsed_s: float


@dataclass
class Runner:
    """Where and how a study's tasks are computed.

    Parameters
    ----------
    workers : int, optional
        Local processes (default: the CPUs this process may use); 1 runs in this
        process. Ignored with `scheduler`.
    scheduler : str or distributed.Client, optional
        ``tcp://host:port`` of a dask.distributed scheduler, or a client.
    chunk_size : int, optional
        Tasks per chunk (default: about eight chunks per worker, at most 256 tasks,
        or the study's own limit).
    store : path, optional
        The study's output file; while it runs, finished chunks go to its resume
        sidecar ``<store>.partial.jsonl`` (:mod:`.store`) so that a rerun resumes.
    restart : bool
        Discard a sidecar of a *different* study instead of failing.
    progress : Progress or bool
        How to report (:class:`~.progress.Progress`; True: :meth:`Progress.auto`).
    """

    workers: int | None = None
    scheduler: Any = None
    chunk_size: int | None = None
    store: str | os.PathLike[str] | None = None
    restart: bool = False
    progress: Progress | bool = False
    n_computed: int = 0
    n_resumed: int = 0
    sidecar: ResumeStore | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        if self.workers is not None and int(self.workers) < 1:
            raise InputError("workers", f"{self.workers} is outside the allowed range >= 1")
        if self.chunk_size is not None and int(self.chunk_size) < 1:
            raise InputError("chunk_size", f"{self.chunk_size} is outside the allowed range >= 1")
        if isinstance(self.progress, bool):
            self.progress = Progress.auto(self.progress)
        if isinstance(self.scheduler, str):
            needs_cluster_extra()

    @property
    def reporter(self) -> Progress:
        """The progress reporter."""
        assert isinstance(self.progress, Progress)
        return self.progress

    @property
    def backend(self) -> str:
        """``"dask.distributed"`` or ``"local"``."""
        return "dask.distributed" if self.scheduler is not None else "local"

    @property
    def n_workers(self) -> int:
        """Local worker processes (0 with a dask scheduler)."""
        if self.scheduler is not None:
            return 0
        return default_workers() if self.workers is None else int(self.workers)

    # ------------------------------------------------------------------ store

    def open(self, digest: str, extra_outputs: Sequence[str | os.PathLike[str]] = ()) -> None:
        """Open (lock, create or resume) the resume store of the study `digest`.

        Without a `store` path nothing is kept. Opening the same study twice is a no-op.
        """
        if self.store is None:
            return
        if self.sidecar is not None:
            if self.sidecar.digest != digest:
                raise InputError("store", "one runner's store serves one study")
            return
        self.sidecar = ResumeStore(
            self.store, digest, restart=self.restart, extra_outputs=extra_outputs
        )

    def close(self) -> None:
        """Close the resume store, keeping it for a rerun (after an error)."""
        if self.sidecar is not None:
            self.sidecar.close()

    def write_outputs(self, writes: Sequence[tuple[Any, Callable[[Any], Any]]]) -> None:
        """``write(path)`` for every ``(path, write)`` (None paths skipped), then remove
        the resume store; on a failed write (full disk, quota, HDF error) one
        :class:`InputError` that says the finished work is kept, and the store is kept.
        """
        for path, write in writes:
            if path is None:
                continue
            try:
                write(path)
            except (OSError, RuntimeError) as exc:
                self.close()
                kept = self.sidecar.path if self.sidecar is not None else None
                raise full_disk_error(path, exc, kept) from None
        if self.sidecar is not None:
            self.sidecar.remove()
            self.sidecar = None

    # ------------------------------------------------------------------ running

    def run(
        self,
        job: Job,
        results: Results,
        n_tasks: int,
        *,
        label: str,
        unit: str = "points",
        max_chunk: int = TASK_CHUNK,
        chunk_size: int | None = None,
        probe_first: bool = True,
    ) -> RunInfo:
        """Compute every task of `job` that `results` still lacks (see the module notes).

        `chunk_size` overrides the runner's for this run (1: every task its own chunk,
        in order). `probe_first`: time the first tasks here before starting a pool (and
        keep the rest here when they are cheap); off for runs of few long, unequal tasks.
        """
        t0 = time.perf_counter()
        n_workers = self.n_workers
        if self.sidecar is not None:
            n_bad = self.sidecar.n_discarded
            for keys, values in self.sidecar.records:
                n_bad += not results.restore(keys, values)
            if n_bad:
                print(
                    f"obturator: notice: {n_bad} damaged or foreign records in "
                    f"{self.sidecar.path.name} discarded; their tasks are recomputed",
                    file=sys.stderr,
                )
        todo = results.todo()
        n_resumed = n_tasks - todo.size
        computed = [0]

        def sink(idx: np.ndarray, result: Any) -> None:
            keys, values = results.put(idx, result)
            computed[0] += idx.size
            if self.sidecar is not None:
                self.sidecar.append(keys, values)

        try:
            chunks = make_chunks(
                todo,
                n_workers if self.scheduler is None else 8,
                chunk_size or self.chunk_size,
                max_chunk,
                job.contiguous,
            )
            executor = choose_executor(n_workers, self.scheduler, len(chunks))
            estimate = None
            if isinstance(executor, ProcessPool) and job.ahead is not None:
                job = job.ahead(chunks)
            pool = isinstance(executor, ProcessPool)
            if chunks and probe_first and self.scheduler is None:
                # in this process only to announce the estimate: timed, not kept, where
                # splitting a chunk could change results (and where that costs <3 %)
                keep = pool or job.separable
                # before a pool of a job whose chunks run consecutive tasks, one task: the
                # probe is serial work (the workers start after it), and a longer probe of
                # a rig sweep's lowest spins delayed the whole sweep (docs/benchmarks.md)
                n_probe = 1 if pool and (job.contiguous or not job.separable) else PROBE_TASKS
                sure = pool and n_probe == 1 and todo.size >= POOL_SURE_TASKS
                wanted = pool or (self.reporter.enabled and (keep or todo.size > 32 * PROBE_TASKS))
                if wanted and not sure:
                    cost = probe(job, chunks, sink, keep, n_probe)
                    serial = cost.serial_s(sum(c.size for c in chunks))
                    if pool and serial < POOL_MIN_SERIAL_S:
                        executor = InProcess()
                    # one task (the costliest end of a sweep, with the first loads) tells
                    # whether a pool pays, not how long the run takes: no estimate then
                    if n_probe > 1:
                        estimate = serial / max(1, executor.workers)
            if chunks:
                where = (
                    "a Dask cluster"
                    if self.scheduler is not None
                    else f"{executor.workers} worker" + ("s" if executor.workers != 1 else "")
                )
                work = f"{todo.size} {unit} on {where}"
                if n_resumed:
                    work += f" ({n_resumed} resumed)"
                self.reporter.plan(label, work, estimate)
                left = sum(c.size for c in chunks)  # the probe's tasks are done
                track = partial(self.reporter.track, label, n_tasks, n_tasks - left, unit)
                executor.run(job, chunks, sink, track)
        except LostWorker as exc:
            self.n_computed += computed[0]
            self.close()
            if self.sidecar is not None:
                kept = (
                    f"the {computed[0] + n_resumed} finished {unit} are kept: run the same "
                    "command again to resume"
                )
            else:
                kept = "nothing is kept without a resume store (--out): run it again"
            raise InputError("workers", f"{exc}; {kept} (fewer workers need less memory)") from None
        except BaseException:
            self.n_computed += computed[0]  # kept in the store: a rerun resumes them
            self.close()
            raise
        self.n_computed += computed[0]
        self.n_resumed += n_resumed
        return RunInfo(
            computed[0], n_resumed, executor.workers, executor.backend, time.perf_counter() - t0
        )

    def map(
        self,
        fn: Callable[[Any], Any],
        tasks: Sequence[Any],
        *,
        label: str = "points",
        unit: str = "points",
        warm: Callable[[], None] | None = None,
        chunk_size: int | None = None,
        probe_first: bool = True,
        batched: bool = False,
        pickled: bool = False,
    ) -> list[Any]:
        """``[fn(t) for t in tasks]``, computed as :meth:`run` computes.

        Parameters
        ----------
        fn : callable
            Picklable function of one task; with a store, the task must be JSON-ready
            (its content hash is its key) and the result too. With `batched`, a
            function of a list of tasks that returns their results in order (one call
            per chunk: the lanes of :func:`obturator.solve.opening_times`).
        tasks : sequence
        label, unit : str
            What the progress display calls the run and its tasks.
        warm : callable, optional
            Loads compiled code once (before workers fork and before the probe).
        chunk_size : int, optional
            Tasks per chunk of this map (default the runner's).
        probe_first : bool
            See :meth:`run`.
        batched : bool
            `fn` takes a chunk's tasks at once; a task's result may then depend on its
            chunk at the rounding level, so a probe only times (``Job.separable``).
        pickled : bool
            Tasks and results need not be JSON-ready: tasks are keyed by their canonical
            content, results stored pickled (:mod:`.results`).
        """
        results = MapResults(tasks, keyed=self.sidecar is not None, pickled=pickled)
        if batched:
            job = Job(fn, lambda idx: ([tasks[i] for i in idx.tolist()],), warm, separable=False)
        else:
            job = Job(run_tasks, lambda idx: (fn, [tasks[i] for i in idx.tolist()]), warm)
        self.run(
            job,
            results,
            results.n_unique,
            label=label,
            unit=unit,
            chunk_size=chunk_size,
            probe_first=probe_first,
        )
        return results.values()

    def memo(self, identity: Any, compute: Callable[[], Any]) -> Any:
        """``compute()`` in this process, or its value from the resume store when a run of
        the same study finished it before (a step of a study that runs its own steps in
        order, such as a section of ``reproduce``). `identity` describes the step (its
        content is the key); the value is stored pickled.
        """
        results = MapResults([identity], keyed=self.sidecar is not None, pickled=True)
        if self.sidecar is not None:
            for keys, values in self.sidecar.records:
                results.restore(keys, values)
        if results.todo().size == 0:
            self.n_resumed += 1
            return results.values()[0]
        value = compute()
        keys, values = results.put(np.zeros(1, dtype=np.intp), [value])
        if self.sidecar is not None:
            try:
                self.sidecar.append(keys, values)
            except BaseException:
                self.close()
                raise
        self.n_computed += 1
        return value
