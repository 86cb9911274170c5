"""Validation of the model against the spin-rig measurements (thesis Appendix B).

:mod:`~obturator.validation.floor`: the replicate-scatter floor, from the data alone;
:mod:`~obturator.validation.study`: candidate mechanisms fitted to all runs, ranked.
"""

from .floor import BANDS, CLUSTER_GAP, ReplicateFloor, cluster_runs, replicate_floor
from .study import CANDIDATES, ValidationStudy, run_validation

__all__ = [
    "BANDS",
    "CANDIDATES",
    "CLUSTER_GAP",
    "ReplicateFloor",
    "ValidationStudy",
    "cluster_runs",
    "replicate_floor",
    "run_validation",
]
