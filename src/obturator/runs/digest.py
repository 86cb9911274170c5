"""The one study digest: a SHA-256 of a canonical JSON description.

Every study names itself by :func:`study_digest` of its identity (model, settings,
inputs, package version where it matters); the resume store refuses a file written
for another digest. :func:`task_key` addresses one task of a content-addressed run.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Mapping
from typing import Any

__all__ = ["canonical", "study_digest", "task_key"]


def canonical(x: Any) -> Any:
    """`x` as plain JSON: sorted mappings, lists, non-finite floats as their repr."""
    if isinstance(x, float):
        return x if math.isfinite(x) else repr(x)
    if isinstance(x, Mapping):
        return {str(k): canonical(v) for k, v in sorted(x.items())}
    if isinstance(x, list | tuple):
        return [canonical(v) for v in x]
    if hasattr(x, "item"):  # numpy scalar
        return canonical(x.item())
    return x


def study_digest(identity: Mapping[str, Any]) -> str:
    """SHA-256 (hex) of a JSON-ready study description (floats to full precision)."""
    text = json.dumps(canonical(identity), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def task_key(task: Mapping[str, Any]) -> str:
    """Content hash of one task's inputs (128 bits of :func:`study_digest`)."""
    return study_digest(task)[:32]
