"""Strict JSON (RFC 8259) for every ``--json`` output: no NaN or Infinity tokens.

Non-finite floats (Python or NumPy) become ``null``; NumPy scalars and arrays
become plain numbers and lists; anything else that json cannot encode is an error.
Every top-level object carries ``obturator_version``, so that a saved result says
which release made it. Keys of quantities with a unit end in the unit
(``pressure_Pa``, ``wall_s``; ``tests/cli/test_json_outputs.py`` checks the commands).
"""

from __future__ import annotations

import json
import math
from typing import Any

import numpy as np

__all__ = ["to_jsonable", "dumps"]


def to_jsonable(obj: Any) -> Any:
    """A copy of `obj` with non-finite floats as None and NumPy values as Python ones."""
    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def dumps(obj: Any, **kwargs: Any) -> str:
    """``json.dumps`` of :func:`to_jsonable` (obj) with ``allow_nan=False``; a dict
    gains ``obturator_version`` (the package version) unless it has it."""
    if isinstance(obj, dict) and "obturator_version" not in obj:
        from .._provenance import package_version

        obj = {**obj, "obturator_version": package_version()}
    return json.dumps(to_jsonable(obj), allow_nan=False, **kwargs)
