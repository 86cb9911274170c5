"""The printed values the reproduction report checks (``printed_values.toml``).

>>> CHAPTER4_SUMS["t2"], len(PRINTED_VALUES["row"]) > 40
(0.00086603508, True)
"""

from __future__ import annotations

import tomllib
from importlib.resources import files
from typing import Any

__all__ = ["PRINTED_VALUES_FILE", "PRINTED_VALUES", "CHAPTER4_SUMS"]

#: The data file, beside this module.
PRINTED_VALUES_FILE = "printed_values.toml"
#: Its contents: ``chapter4`` (the printed least-squares sums) and ``row`` (report rows).
PRINTED_VALUES: dict[str, Any] = tomllib.loads(
    files(__package__).joinpath(PRINTED_VALUES_FILE).read_text(encoding="utf-8")
)
#: Chapter IV's least-squares sums and results, as printed (typos included).
CHAPTER4_SUMS: dict[str, float] = dict(PRINTED_VALUES["chapter4"])
