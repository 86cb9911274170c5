"""Numbers for JSON summaries: JSON has no NaN or infinity, so they are written as null.

>>> finite_or_none(float("nan")) is None, finite_or_none(2.5)
(True, 2.5)
"""

from __future__ import annotations

import math
from typing import SupportsFloat

__all__ = ["finite_or_none"]


def finite_or_none(x: SupportsFloat) -> float | None:
    """``x`` as a Python float, or None where it is NaN or infinite."""
    value = float(x)
    return value if math.isfinite(value) else None
