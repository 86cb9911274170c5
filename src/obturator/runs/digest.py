"""The one study digest: a SHA-256 of a canonical JSON description.

Every study names itself by :func:`study_digest` of its identity (model, settings,
inputs, package version where it matters); the resume store refuses a file written
for another digest. :func:`task_key` addresses one task of a content-addressed run.
Arrays, dataclasses (frozen settings, fit results) and module-level functions have a
canonical form too, so a task of any of them is addressed by its content.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

__all__ = ["canonical", "study_digest", "task_key"]


def canonical(x: Any) -> Any:
    """`x` as plain JSON: sorted mappings, lists, non-finite floats as their repr;
    an array as its dtype, shape and values; a dataclass as its type and fields (and
    what its ``digest_extra()`` adds, where it has one); a function as its qualified
    name."""
    if isinstance(x, float):
        return x if math.isfinite(x) else repr(x)
    if isinstance(x, Mapping):
        return {str(k): canonical(v) for k, v in sorted(x.items())}
    if isinstance(x, list | tuple):
        return [canonical(v) for v in x]
    if isinstance(x, np.ndarray):
        return {"array": x.dtype.str, "shape": list(x.shape), "data": canonical(x.ravel().tolist())}
    if hasattr(x, "item"):  # numpy scalar
        return canonical(x.item())
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        fields = {f.name: getattr(x, f.name) for f in dataclasses.fields(x)}
        if callable(extra := getattr(x, "digest_extra", None)):
            fields |= extra()  # what the fields alone do not say (solver options' "auto")
        return {"type": _qualified(type(x)), "fields": canonical(fields)}
    if callable(x) and hasattr(x, "__qualname__"):
        return {"function": _qualified(x)}
    return x


def _qualified(x: Any) -> str:
    return f"{x.__module__}.{x.__qualname__}"


def study_digest(identity: Mapping[str, Any]) -> str:
    """SHA-256 (hex) of a JSON-ready study description (floats to full precision)."""
    text = json.dumps(canonical(identity), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def task_key(task: Any) -> str:
    """Content hash of one task's inputs (128 bits of :func:`study_digest`)."""
    return study_digest(task if isinstance(task, Mapping) else {"task": task})[:32]
