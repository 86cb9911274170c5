"""Chunks of a run as tasks on a Dask cluster (``scheduler="tcp://host:port"`` or a client).

The same chunks as ``client.submit`` tasks (the workers need ``obturator``
importable). A lost scheduler or worker is a :class:`~obturator.errors.ClusterError`
within seconds, never a hang.
"""

from __future__ import annotations

import threading
import time
from contextlib import suppress
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ClusterError, InputError
from .chunks import Job
from .pools import Sink, Track

__all__ = ["CONNECT_TIMEOUT_S", "LOST_SCHEDULER_S", "DaskCluster", "needs_cluster_extra"]


def needs_cluster_extra() -> None:
    """Raise InputError naming the fix when dask.distributed (the ``cluster`` extra) is
    missing: a scheduler address is refused before any work, not at the first chunk."""
    try:
        import distributed  # noqa: F401
    except ImportError:
        raise InputError(
            "scheduler",
            'needs dask.distributed, which is not installed: pip install "obturator[cluster]"',
        ) from None


@dataclass
class DaskCluster:
    """Chunks as tasks on a Dask cluster (an address or a ``distributed.Client``)."""

    scheduler: Any
    backend: str = "dask.distributed"
    workers: int = 0

    def run(self, job: Job, chunks: list[np.ndarray], sink: Sink, track: Track) -> None:
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
            if job.meanwhile is not None:
                job.meanwhile()
            pending = set(futures)
            lost_since: float | None = None
            with track() as advance:
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
    needs_cluster_extra()
    from distributed import Client

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
