"""The thesis's numbers: inputs (:mod:`.thesis`), the printed values the report
checks (``printed_values.toml``, :mod:`.printed`) and the Appendix B runs (a CSV file).

Data files are read with :func:`data_text` so they work from an installed wheel.
"""

from __future__ import annotations

from importlib.resources import files

from .printed import CHAPTER4_SUMS, PRINTED_VALUES
from .thesis import (
    CAPTION_SHEAR_CONSTANT,
    COUETTE_P52,
    EQ95_COEFFICIENT,
    EQ95_WEIGHT,
    FLIGHT_SOBOL_RANGES,
    PRINTED_SUMS_OMITTED_RUNS,
    RIG_TEETH,
    TABLE1,
    THESIS_FIT_MIN_SPIN,
    THESIS_MU_S,
    THESIS_REYNOLDS,
    THESIS_REYNOLDS_MACH,
)

__all__ = [
    "APPENDIX_B_CSV",
    "CAPTION_SHEAR_CONSTANT",
    "CHAPTER4_SUMS",
    "COUETTE_P52",
    "EQ95_COEFFICIENT",
    "EQ95_WEIGHT",
    "FLIGHT_SOBOL_RANGES",
    "PRINTED_SUMS_OMITTED_RUNS",
    "PRINTED_VALUES",
    "RIG_TEETH",
    "TABLE1",
    "THESIS_FIT_MIN_SPIN",
    "THESIS_MU_S",
    "THESIS_REYNOLDS",
    "THESIS_REYNOLDS_MACH",
    "data_text",
]

#: File name of the Appendix B runs (transcribed as printed).
APPENDIX_B_CSV = "bloomer1980_appendix_b.csv"


def data_text(name: str) -> str:
    """The UTF-8 text of a data file of this package (e.g. :data:`APPENDIX_B_CSV`)."""
    return files(__name__).joinpath(name).read_text(encoding="utf-8")
