"""Validation of the model against the spin-rig measurements (thesis Appendix B).

:mod:`~obturator.validation.floor`: the replicate-scatter floor, from the data alone.
"""

from .floor import BANDS, CLUSTER_GAP, ReplicateFloor, cluster_runs, replicate_floor

__all__ = ["BANDS", "CLUSTER_GAP", "ReplicateFloor", "cluster_runs", "replicate_floor"]
