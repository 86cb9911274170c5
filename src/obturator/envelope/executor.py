"""Resumable evaluation of many independent points: local processes or Dask.

An adapter of the sweep machinery. :mod:`obturator.sweeps` evaluates
:class:`~obturator.sweeps.SweepSpec` grids whose points are single
``opening_time(case)`` calls; the envelope studies need other point functions (a
trajectory-coupled opening, a design evaluated over several flight conditions,
muzzle spin tied to muzzle velocity) and task lists that are not Cartesian grids
(importance-sampling stages, Sobol designs, optimiser generations). :class:`Runner`
hands chunks of such tasks to the sweeps' executors
(:func:`obturator.sweeps.executors.choose_executor`: in process, a forked process
pool, or a Dask cluster, with the same progress bar and fault handling) and keeps
its own content-addressed store, a JSON-lines sidecar flushed after every chunk.

The store is content-addressed: each finished point is kept under a hash of
its inputs, and the file's first line holds a hash of the study (the model and
the command's settings). A rerun of the same study after an interruption
finds every finished point whatever the chunking, the worker count or the
stage it belonged to, so nothing is lost or computed twice; a store of a
different study is refused unless ``restart=True``.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from ..sweeps.executors import (
    Job,
    ProcessPool,
    choose_executor,
    default_workers,
    make_chunks,
    probe_cost,
    progress_bar,
)

__all__ = ["ResultStore", "Runner", "task_key", "study_digest", "store_path"]

_FORMAT = "obturator-envelope-store/1"

Task = Mapping[str, Any]
Result = dict[str, Any]


def _canon(x: Any) -> Any:
    if isinstance(x, float):
        return x if math.isfinite(x) else repr(x)
    if isinstance(x, Mapping):
        return {str(k): _canon(v) for k, v in sorted(x.items())}
    if isinstance(x, list | tuple):
        return [_canon(v) for v in x]
    if hasattr(x, "item"):  # numpy scalar
        return _canon(x.item())
    return x


def study_digest(identity: Mapping[str, Any]) -> str:
    """SHA-256 (hex) of a JSON-ready study description."""
    text = json.dumps(_canon(identity), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def task_key(task: Task) -> str:
    """Content hash of one task's inputs (floats to full precision)."""
    return study_digest(task)[:32]


def store_path(out: str | os.PathLike[str]) -> Path:
    """Sidecar kept next to the final output while a study runs."""
    p = Path(out)
    return p.with_name(p.name + ".partial.jsonl")


class ResultStore:
    """Append-only JSON-lines store of finished points, keyed by input hash.

    Parameters
    ----------
    path : path
        The sidecar file (see :func:`store_path`).
    identity : mapping
        JSON-ready description of the study; its hash is the first line.
    restart : bool
        Discard a file written for a different study instead of failing.
    """

    def __init__(self, path: str | os.PathLike[str], identity: Mapping[str, Any], restart: bool):
        self.path = Path(path)
        if not self.path.parent.is_dir():
            raise InputError("out", f"directory {str(self.path.parent)!r} does not exist")
        self.digest = study_digest(identity)
        self._done: dict[str, Result] = {}
        header = {"format": _FORMAT, "study": self.digest}
        if self.path.exists() and restart:
            self.path.unlink()
        if self.path.exists():
            self._load(header)
            self._fh = self.path.open("a", encoding="utf-8")
        else:
            self._fh = self.path.open("w", encoding="utf-8")
            self._write(header)

    def _load(self, header: dict[str, Any]) -> None:
        lines = self.path.read_text(encoding="utf-8").splitlines()
        try:
            first = json.loads(lines[0]) if lines else {}
        except json.JSONDecodeError:
            first = {}
        if first != header:
            old = str(first.get("study", "?"))[:12]
            raise InputError(
                "out",
                f"{self.path} holds partial results of a different study (hash {old}, "
                f"this one {self.digest[:12]}); use --restart to discard it",
            )
        for line in lines[1:]:
            try:
                rec = json.loads(line)
                keys, values = rec["keys"], rec["values"]
            except (json.JSONDecodeError, KeyError, TypeError):
                continue  # a line cut short by an interruption
            if isinstance(keys, list) and isinstance(values, list) and len(keys) == len(values):
                self._done.update(zip(keys, values, strict=True))
        if lines and not self.path.read_bytes().endswith(b"\n"):
            with self.path.open("a", encoding="utf-8") as fh:
                fh.write("\n")

    def _write(self, record: dict[str, Any]) -> None:
        self._fh.write(json.dumps(record) + "\n")
        self._fh.flush()
        os.fsync(self._fh.fileno())

    def __len__(self) -> int:
        return len(self._done)

    def get(self, key: str) -> Result | None:
        """The stored result of a task, or None."""
        return self._done.get(key)

    def put(self, keys: Sequence[str], values: Sequence[Result]) -> None:
        """Record finished tasks (flushed to disk at once)."""
        self._write({"keys": list(keys), "values": list(values)})
        self._done.update(zip(keys, values, strict=True))

    def close(self) -> None:
        """Close the file (kept for a later resume)."""
        if not self._fh.closed:
            self._fh.close()

    def remove(self) -> None:
        """Close and delete the file (after the final output is written)."""
        self.close()
        self.path.unlink(missing_ok=True)


def _run_chunk(fn: Callable[[Task], Result], tasks: list[Task]) -> list[Result]:
    """Evaluate one chunk (module level so that pools and dask workers import it)."""
    return [fn(t) for t in tasks]


def _warm() -> None:
    """Load the compiled integrators once (forked workers inherit them)."""
    from ..model.cases import flight_case
    from ..solve import opening_time

    try:
        opening_time(flight_case(t_max=1e-3))
    except RuntimeError:  # pragma: no cover - warm-up only
        pass


@dataclass
class Runner:
    """Where and how point functions are evaluated.

    Parameters
    ----------
    workers : int, optional
        Local processes (default: the CPUs this process may use); 1 runs in
        this process. Ignored with `scheduler`.
    scheduler : str or distributed.Client, optional
        ``tcp://host:port`` of a dask.distributed scheduler, or a client.
    store : ResultStore, optional
        Resume store; finished points are read from and written to it.
    progress : bool
        Rich progress bar on stderr.
    chunk_size : int, optional
        Points per task (default as in sweeps: about eight tasks per worker, at most 256).
    """

    workers: int | None = None
    scheduler: Any = None
    store: ResultStore | None = None
    progress: bool = False
    chunk_size: int | None = None
    n_computed: int = 0
    n_resumed: int = 0

    def __post_init__(self) -> None:
        if self.workers is not None and int(self.workers) < 1:
            raise InputError("workers", f"{self.workers} is outside the allowed range >= 1")
        if self.chunk_size is not None and int(self.chunk_size) < 1:
            raise InputError("chunk_size", f"{self.chunk_size} is outside the allowed range >= 1")

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

    def map(self, fn: Callable[[Task], Result], tasks: Sequence[Task], label: str = "points"):
        """Evaluate ``fn`` on every task; results in task order.

        Parameters
        ----------
        fn : callable
            Picklable function of one task (a mapping of JSON-ready inputs)
            returning a JSON-ready dict.
        tasks : sequence of mapping
        label : str
            Progress-bar label.

        Returns
        -------
        list of dict
        """
        keys = [task_key(t) for t in tasks]
        results: list[Result | None] = [None] * len(tasks)
        todo: list[int] = []
        first_of: dict[str, int] = {}
        for i, k in enumerate(keys):
            hit = self.store.get(k) if self.store is not None else None
            if hit is not None:
                results[i] = hit
            elif k in first_of:
                continue  # duplicate task: filled in from its first occurrence
            else:
                first_of[k] = i
                todo.append(i)
        self.n_resumed += sum(r is not None for r in results)
        workers = 8 if self.scheduler is not None else max(self.n_workers, 1)
        chunks = make_chunks(np.asarray(todo, dtype=np.intp), workers, self.chunk_size)

        def sink(idx: np.ndarray, vals: list[Result]) -> None:
            idx = idx.tolist()
            for i, v in zip(idx, vals, strict=True):
                results[i] = v
            if self.store is not None:
                self.store.put([keys[i] for i in idx], vals)
            self.n_computed += len(idx)

        done = len(tasks) - len(todo)
        if chunks:
            job = Job(_run_chunk, lambda idx: (fn, [tasks[i] for i in idx.tolist()]), _warm)
            executor = choose_executor(self.n_workers, self.scheduler, len(chunks))
            if isinstance(executor, ProcessPool):
                executor = probe_cost(executor, job, chunks, sink)
            bar = partial(progress_bar, self.progress, len(tasks), done, label)
            executor.run(job, chunks, sink, bar)
        for i, k in enumerate(keys):
            if results[i] is None:
                results[i] = results[first_of[k]]
        return results
