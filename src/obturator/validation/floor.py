"""The replicate-scatter floor: how well any model can predict the spin-rig runs.

Runs come in clusters at nearly the same spin (e.g. six near 199 rad/s, four near
78 rad/s). Within a cluster the runs repeat one experiment, so their scatter is
pure measurement error; a model cannot predict the runs better than they repeat.

Clustering rule: sort the runs by omega_p and start a new cluster wherever the
gap to the previous run exceeds :data:`CLUSTER_GAP` = 3.5 rad/s, twice the rig's
spin regulation of +-1.75 rad/s (thesis chapter III.B: +-5 Hz on the readout):
two runs closer than that may have had the same true spin.

Floor (the cluster means are the saturated model): pooled standard deviation
s_p = sqrt(SS_w / df) with SS_w the sum of squared deviations from the cluster
means and df = N - (number of clusters); s_p is the rms residual a perfect model
(one that predicts each cluster's true mean) would have. The rms about the
sample cluster means, sqrt(SS_w / N), is smaller and is reported too. Per spin
band (cluster mean < 120, 120-200, 200-300, > 300 rad/s) the same with the
band's clusters; singleton clusters add no degrees of freedom.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError

__all__ = ["CLUSTER_GAP", "BANDS", "ReplicateFloor", "cluster_runs", "replicate_floor"]

#: Largest spin gap inside one cluster [rad/s]: twice the +-1.75 rad/s regulation.
CLUSTER_GAP = 3.5
#: Spin bands [rad/s] for per-band floors: (name, lower, upper).
BANDS: tuple[tuple[str, float, float], ...] = (
    ("<120", 0.0, 120.0),
    ("120-200", 120.0, 200.0),
    ("200-300", 200.0, 300.0),
    (">300", 300.0, math.inf),
)


def cluster_runs(spin_rate: ArrayLike, gap: float = CLUSTER_GAP) -> NDArray[np.int64]:
    """Cluster label of each run (single linkage on sorted omega_p, 0, 1, ... by spin).

    Parameters
    ----------
    spin_rate : array_like
        omega_p of each run [rad/s].
    gap : float
        A gap larger than this starts a new cluster [rad/s].
    """
    w = np.asarray(spin_rate, dtype=float)
    if w.ndim != 1 or w.size == 0 or not np.all(np.isfinite(w)):
        raise InputError("spin_rate", "expected a non-empty 1-D array of finite values")
    order = np.argsort(w, kind="stable")
    new = np.concatenate([[0], (np.diff(w[order]) > gap).astype(np.int64)])
    labels = np.empty(w.size, dtype=np.int64)
    labels[order] = np.cumsum(new)
    return labels


@dataclass(frozen=True)
class ReplicateFloor:
    """Pure-error floor of a data set, overall and per band.

    Attributes
    ----------
    pooled_sd_s : float
        s_p [s]: the rms residual a perfect model would have (NaN without replicates).
    rms_about_means_s : float
        sqrt(SS_w / N) [s].
    df : int
        Degrees of freedom of s_p (N minus the number of clusters).
    n_runs, n_clusters : int
    by_band : dict
        Band name -> (pooled_sd_s, df, n_runs) for the clusters whose mean lies in it.
    labels : ndarray
        Cluster of each run.
    """

    pooled_sd_s: float
    rms_about_means_s: float
    df: int
    n_runs: int
    n_clusters: int
    by_band: dict[str, tuple[float, int, int]]
    labels: NDArray[np.int64]

    def to_dict(self) -> dict[str, object]:
        """JSON-ready summary (None for NaN)."""

        def clean(x: float) -> float | None:
            return x if math.isfinite(x) else None

        return {
            "floor_rms_s": clean(self.pooled_sd_s),
            "rms_about_cluster_means_s": clean(self.rms_about_means_s),
            "df": self.df,
            "n_runs": self.n_runs,
            "n_clusters": self.n_clusters,
            "floor_rms_by_band_s": {k: clean(v[0]) for k, v in self.by_band.items()},
            "df_by_band": {k: v[1] for k, v in self.by_band.items()},
            "cluster_gap_rad_s": CLUSTER_GAP,
        }


def _pooled(t: NDArray[np.float64], labels: NDArray[np.int64]) -> tuple[float, float, int]:
    ss = 0.0
    groups = np.unique(labels)
    for g in groups:
        x = t[labels == g]
        ss += float(np.sum((x - x.mean()) ** 2))
    df = t.size - groups.size
    sd = math.sqrt(ss / df) if df > 0 else math.nan
    return sd, math.sqrt(ss / t.size) if t.size else math.nan, df


def replicate_floor(
    spin_rate: ArrayLike, opening_time: ArrayLike, gap: float = CLUSTER_GAP
) -> ReplicateFloor:
    """The replicate-scatter floor of measured opening times.

    Parameters
    ----------
    spin_rate : array_like
        omega_p of each run [rad/s].
    opening_time : array_like
        Measured t_cr of each run [s].
    gap : float
        Clustering gap [rad/s] (see :func:`cluster_runs`).
    """
    w = np.asarray(spin_rate, dtype=float)
    t = np.asarray(opening_time, dtype=float)
    if t.shape != w.shape or not np.all(np.isfinite(t)):
        raise InputError("opening_time", "expected finite values, one per run")
    labels = cluster_runs(w, gap)
    sd, rms, df = _pooled(t, labels)
    means = {int(g): float(w[labels == g].mean()) for g in np.unique(labels)}
    by_band = {}
    for name, lo, hi in BANDS:
        keep = np.array([lo <= means[int(g)] < hi for g in labels])
        if keep.any():
            bsd, _, bdf = _pooled(t[keep], labels[keep])
            by_band[name] = (bsd, bdf, int(keep.sum()))
        else:
            by_band[name] = (math.nan, 0, 0)
    return ReplicateFloor(sd, rms, df, int(t.size), len(means), by_band, labels)
