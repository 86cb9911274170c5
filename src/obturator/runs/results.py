"""Results of :meth:`~obturator.runs.runner.Runner.map`: one value per task, stored under
the content hash of the task (:func:`~obturator.runs.digest.task_key`).

Keyed by content, a resumed run finds every finished task whatever the chunking, the
worker count or the stage (importance-sampling stage, optimiser generation) it
belonged to; a task repeated in one list is computed once.

Values are stored as JSON. Results that are not JSON-ready (a validation fit, a thesis
study's arrays) are stored ``pickled``: the pickle, base64 in the record. Such a record is
read back only from the study's own sidecar, under its digest (which names the package
version) and after its CRC check; it is a cache of this installation's own work, not an
exchange format.
"""

from __future__ import annotations

import base64
import pickle
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np

from ..errors import InputError
from .digest import task_key

__all__ = ["MapResults", "run_tasks"]


def run_tasks(fn: Callable[[Any], Any], tasks: list[Any]) -> list[Any]:
    """Evaluate one chunk (module level so that pools and Dask workers import it)."""
    return [fn(t) for t in tasks]


class MapResults:
    """One value per task; see the module notes.

    Parameters
    ----------
    tasks : sequence
        Mappings of JSON-ready inputs are keyed by content (and may be stored);
        other tasks (not stored) by their position.
    keyed : bool
        Whether a resume store is open (every task must then be a mapping, unless
        `pickled`).
    pickled : bool
        Values are stored pickled (see the module notes), and tasks of any kind that
        :func:`~obturator.runs.digest.canonical` describes are keyed by content.
    """

    def __init__(self, tasks: Sequence[Any], keyed: bool, pickled: bool = False) -> None:
        self.pickled = pickled
        by_content = pickled or all(isinstance(t, Mapping) for t in tasks)
        if keyed and not by_content:
            raise InputError(
                "store", "only tasks that are mappings of JSON-ready inputs are stored"
            )
        self.keys: list[Any] = (
            [task_key(t) for t in tasks] if by_content else list(range(len(tasks)))
        )
        self._first: dict[Any, int] = {}
        for i, k in enumerate(self.keys):
            self._first.setdefault(k, i)
        self._done: dict[Any, Any] = {}

    @property
    def n_unique(self) -> int:
        """Distinct tasks."""
        return len(self._first)

    def todo(self) -> np.ndarray:
        """First occurrences of the tasks not done yet."""
        todo = [i for k, i in self._first.items() if k not in self._done]
        return np.asarray(sorted(todo), dtype=np.intp)

    def put(self, idx: np.ndarray, result: list[Any]) -> tuple[list[Any], Any]:
        """Keep one chunk's values; the store record is ``(task keys, values)``."""
        keys = [self.keys[i] for i in idx.tolist()]
        self._done.update(zip(keys, result, strict=True))
        if self.pickled:
            result = [base64.b64encode(pickle.dumps(v, protocol=5)).decode("ascii") for v in result]
        return keys, result

    def restore(self, keys: list[Any], values: Any) -> bool:
        """Take the values of a stored chunk (any of them may belong to this list)."""
        if not isinstance(values, list) or len(values) != len(keys):
            return False
        for k, v in zip(keys, values, strict=True):
            if isinstance(k, str) and k in self._first:
                if self.pickled:
                    try:
                        v = pickle.loads(base64.b64decode(v, validate=True))
                    except Exception:  # noqa: BLE001 - a record of another kind: recompute
                        return False
                self._done[k] = v
        return True

    def values(self) -> list[Any]:
        """Every task's value, in task order."""
        return [self._done[k] for k in self.keys]
