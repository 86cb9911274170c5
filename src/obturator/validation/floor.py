"""Replicate clusters and the pure-error floor of the spin-rig data (issue 9, item 1).

The 54 runs of thesis Appendix B come in groups taken at nearly the same spin
(e.g. six near 199 rad/s, four near 78 rad/s). Treating each group's mean
opening time as a *saturated* model (one free mean per cluster) separates the
scatter of repeated runs (pure error) from any lack of fit of a physical model:
no model that is a function of omega_p alone can beat it on average.

Clustering rule
---------------
Runs are sorted by spin and split wherever two neighbours differ by more than
``gap`` (single linkage in omega_p). The default gap is 2 x 1.75 rad/s, the
width of the rig's regulation band: the regulator held the readout to
+-5 Hz, about +-1.75 rad/s (thesis chapter III.B, p. 91), so two runs whose
spin differs by less than the band could have been taken at the same set
point. On the thesis data this gives 29 clusters, 14 of them with replicates
(see :func:`cluster_runs`); a cluster keeps its runs however far the chain
stretches, and the largest span is reported (:attr:`ReplicateFloor.max_span`).

Floor
-----
With n runs in k clusters, cluster means ybar_j and
SS_pe = sum_j sum_{i in j} (y_i - ybar_j)^2 (the pure-error sum of squares):

* pooled standard deviation s_pe = sqrt(SS_pe / (n - k)), with n - k degrees
  of freedom: the noise of one run if the noise were the same everywhere;
* saturated rms sqrt(SS_pe / n): the in-sample rms of the cluster means, an
  optimistic floor (k parameters fitted to n points);
* perfect-model rms = s_pe: the expected rms, over the n runs, of residuals
  from the *true* mean curve (E[sum r^2] = n sigma^2). This is the floor a
  model with few parameters is compared with; ``floor_rms_s`` in the JSON.

Per band (``BANDS``: < 120, 120-200, 200-300, > 300 rad/s, by cluster mean) the
same numbers use only the clusters of that band; a band without replicates
has no floor (NaN, df 0). Singleton clusters carry no pure-error information
but count in n for the saturated rms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._docs import field_docs
from ..errors import InputError, check_range
from ..json_values import finite_or_none

__all__ = [
    "BANDS",
    "DEFAULT_CLUSTER_GAP",
    "SPIN_REGULATION",
    "BandFloor",
    "ReplicateFloor",
    "band_labels",
    "band_of",
    "cluster_runs",
    "lack_of_fit",
    "replicate_floor",
]

#: Rig spin regulation, thesis chapter III.B: readout held to +-5 Hz, pi/9 rad/s per Hz
#: (about +-1.75 rad/s) [rad/s].
SPIN_REGULATION = 5.0 * math.pi / 9.0
#: Default single-linkage gap: the full width of the regulation band [rad/s].
DEFAULT_CLUSTER_GAP = 2.0 * SPIN_REGULATION
#: Spin bands [rad/s]: (label, low, high), low inclusive, high exclusive.
BANDS: tuple[tuple[str, float, float], ...] = (
    ("<120", 0.0, 120.0),
    ("120-200", 120.0, 200.0),
    ("200-300", 200.0, 300.0),
    (">300", 300.0, math.inf),
)


def band_labels() -> tuple[str, ...]:
    """Labels of :data:`BANDS`, in order."""
    return tuple(b[0] for b in BANDS)


def band_of(spin_rate: ArrayLike) -> NDArray[np.str_]:
    """Band label of each spin rate [rad/s] (see :data:`BANDS`)."""
    w = np.asarray(spin_rate, dtype=float)
    out = np.empty(w.shape, dtype=object)
    for label, lo, hi in BANDS:
        out[(w >= lo) & (w < hi)] = label
    return out.astype(str)


def cluster_runs(
    spin_rate: ArrayLike, gap: float = DEFAULT_CLUSTER_GAP, groups: ArrayLike | None = None
) -> NDArray[np.int64]:
    """Cluster label of each run: single linkage in omega_p with a maximum gap.

    Parameters
    ----------
    spin_rate : array_like
        omega_p of each run [rad/s].
    gap : float
        Neighbours (in sorted order) closer than or equal to `gap` [rad/s]
        share a cluster. Default: 2 x 1.75 rad/s, the rig's regulation band.
    groups : array_like, optional
        A label per run (hashable): runs of different groups are never replicates
        (a data file's runs with another ball, theta_0 or load). Default: one group.

    Returns
    -------
    ndarray of int
        Labels 0..k-1, numbered in increasing spin (then group), in the input order.
    """
    check_range("gap", gap, 0.0, math.inf, hi_open=True, unit="rad/s")
    w = np.asarray(spin_rate, dtype=float).reshape(-1)
    if w.size == 0:
        raise InputError("spin_rate", "no runs to cluster")
    if groups is not None:
        g = list(groups)
        if len(g) != w.size:
            raise InputError("groups", f"has {len(g)} entries, expected {w.size}")
        keys = list(dict.fromkeys(g))
        pieces = []  # (lowest spin, group number, run indices) of every cluster
        for n, key in enumerate(keys):
            idx = np.array([i for i, x in enumerate(g) if x == key])
            sub = cluster_runs(w[idx], gap)
            for c in np.unique(sub):
                pieces.append((float(w[idx[sub == c]].min()), n, idx[sub == c]))
        labels = np.empty(w.size, dtype=np.int64)
        for k, (_, _, idx) in enumerate(sorted(pieces, key=lambda p: (p[0], p[1]))):
            labels[idx] = k
        return labels
    order = np.argsort(w, kind="stable")
    ws = w[order]
    # tiny slack: readouts are integers, so f pi/9 differences of exactly 10 Hz
    # must not fall on either side of the gap by rounding
    new = np.concatenate(([0], (np.diff(ws) > gap * (1.0 + 1e-9)).astype(np.int64)))
    labels_sorted = np.cumsum(new)
    labels = np.empty_like(labels_sorted)
    labels[order] = labels_sorted
    return labels


@field_docs
@dataclass(frozen=True)
class BandFloor:
    """Pure-error numbers of one spin band (or of all runs)."""

    #: Band label ("all" for the whole data set).
    label: str
    #: Runs in the band.
    n_runs: int
    #: Clusters in the band (by cluster mean spin).
    n_clusters: int
    #: Pure-error degrees of freedom n - k.
    dof: int
    #: Pure-error sum of squares [s^2].
    ss_pe: float
    #: sqrt(SS_pe / dof) [s]; NaN when dof = 0.
    pooled_sd: float
    #: sqrt(SS_pe / n) [s], in-sample rms of the cluster means.
    saturated_rms: float

    @property
    def floor_rms(self) -> float:
        """Expected rms of a perfect model [s] (= pooled_sd)."""
        return self.pooled_sd

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict (None for NaN)."""

        return {
            "label": self.label,
            "n_runs": self.n_runs,
            "n_clusters": self.n_clusters,
            "dof": self.dof,
            "ss_pe_s2": finite_or_none(self.ss_pe),
            "pooled_sd_s": finite_or_none(self.pooled_sd),
            "saturated_rms_s": finite_or_none(self.saturated_rms),
            "floor_rms_s": finite_or_none(self.floor_rms),
        }


def _band_floor(label: str, y: NDArray[np.float64], lab: NDArray[np.int64]) -> BandFloor:
    n = int(y.size)
    if n == 0:
        return BandFloor(label, 0, 0, 0, math.nan, math.nan, math.nan)
    ss = 0.0
    uniq = np.unique(lab)
    for c in uniq:
        yc = y[lab == c]
        ss += float(np.sum((yc - yc.mean()) ** 2))
    k = int(uniq.size)
    dof = n - k
    sd = math.sqrt(ss / dof) if dof > 0 else math.nan
    return BandFloor(label, n, k, dof, ss, sd, math.sqrt(ss / n))


@field_docs
@dataclass(frozen=True)
class ReplicateFloor:
    """Replicate clusters of a data set and its pure-error floor."""

    #: Spin rate omega_p of each run [rad/s].
    spin_rate: NDArray[np.float64]
    #: Measured opening time t_cr of each run [s].
    opening_time: NDArray[np.float64]
    #: Cluster label of each run (0.. in increasing spin).
    cluster: NDArray[np.int64]
    #: Single-linkage gap used [rad/s].
    gap: float
    #: The floor of all runs (label "all").
    overall: BandFloor
    #: The floor per spin band (:data:`BANDS`), clusters assigned by their mean spin.
    bands: dict[str, BandFloor] = field(default_factory=dict)

    @property
    def n_clusters(self) -> int:
        """Number of clusters k."""
        return int(np.unique(self.cluster).size)

    @property
    def floor_rms(self) -> float:
        """Overall perfect-model rms [s] (pooled pure-error SD)."""
        return self.overall.floor_rms

    def cluster_table(self) -> list[dict[str, float]]:
        """One row per cluster: mean spin [rad/s], n, mean t [s], SD t [s] (NaN for n = 1),
        spin span [rad/s]."""
        rows = []
        for c in np.unique(self.cluster):
            m = self.cluster == c
            yc, wc = self.opening_time[m], self.spin_rate[m]
            rows.append(
                {
                    "cluster": int(c),
                    "spin_rate_rad_s": float(wc.mean()),
                    "n": int(m.sum()),
                    "t_mean_s": float(yc.mean()),
                    "t_sd_s": float(yc.std(ddof=1)) if yc.size > 1 else math.nan,
                    "span_rad_s": float(wc.max() - wc.min()),
                }
            )
        return rows

    @property
    def max_span(self) -> float:
        """Largest spin span within one cluster [rad/s]."""
        return max(r["span_rad_s"] for r in self.cluster_table())

    def cluster_sd(self) -> NDArray[np.float64]:
        """Per-run error bar [s]: the SD of its cluster, the pooled SD of its band
        for singletons (the overall pooled SD where the band has none)."""
        out = np.empty(self.opening_time.size)
        bands = band_of(self.cluster_mean_spin())
        for c in np.unique(self.cluster):
            m = self.cluster == c
            if m.sum() > 1:
                out[m] = self.opening_time[m].std(ddof=1)
            else:
                b = self.bands.get(str(bands[m][0]))
                sd = b.pooled_sd if b is not None and math.isfinite(b.pooled_sd) else math.nan
                out[m] = sd if math.isfinite(sd) else self.overall.pooled_sd
        return out

    def cluster_mean_spin(self) -> NDArray[np.float64]:
        """Each run's cluster mean spin [rad/s]."""
        out = np.empty(self.spin_rate.size)
        for c in np.unique(self.cluster):
            m = self.cluster == c
            out[m] = self.spin_rate[m].mean()
        return out

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary."""

        return {
            "rule": f"single linkage in omega_p, gap {self.gap:.4g} rad/s",
            "gap_rad_s": self.gap,
            "n_runs": int(self.spin_rate.size),
            "n_clusters": self.n_clusters,
            "n_replicated_clusters": sum(1 for r in self.cluster_table() if r["n"] > 1),
            "max_span_rad_s": self.max_span,
            "overall": self.overall.to_dict(),
            "bands": {k: v.to_dict() for k, v in self.bands.items()},
            "clusters": [
                {k: finite_or_none(v) if isinstance(v, float) else v for k, v in r.items()}
                for r in self.cluster_table()
            ],
        }


def lack_of_fit(floor: ReplicateFloor, residuals: ArrayLike, n_params: int) -> dict[str, float]:
    """Classical lack-of-fit F test of a model's residuals against the pure error.

    SS_res = sum r_i^2 splits into SS_pe (the floor's) and SS_lof = SS_res - SS_pe;
    F = (SS_lof / (k - p)) / (SS_pe / (n - k)) with k clusters and p fitted mean
    parameters; p-value from F(k - p, n - k). Equal variances are assumed (the
    runs near 78 rad/s scatter far more than the others), so read it as a guide.

    Parameters
    ----------
    floor : ReplicateFloor
        Floor of the same runs, in the same order as `residuals`.
    residuals : array_like
        Model - measured per run [s].
    n_params : int
        Fitted parameters of the mean curve (sigma not counted).

    Returns
    -------
    dict
        ``ss_res``, ``ss_lof`` [s^2], ``df_lof``, ``df_pe``, ``F``, ``p_value``.
    """
    from scipy import stats

    r = np.asarray(residuals, dtype=float).reshape(-1)
    if r.size != floor.opening_time.size:
        raise InputError("residuals", f"has {r.size} entries, expected {floor.opening_time.size}")
    ss_res = float(np.sum(r * r))
    ss_pe = floor.overall.ss_pe
    df_pe = floor.overall.dof
    df_lof = floor.n_clusters - int(n_params)
    ss_lof = ss_res - ss_pe
    if df_lof <= 0 or df_pe <= 0 or ss_pe <= 0.0:
        return {
            "ss_res": ss_res,
            "ss_lof": ss_lof,
            "df_lof": df_lof,
            "df_pe": df_pe,
            "F": math.nan,
            "p_value": math.nan,
        }
    f = (ss_lof / df_lof) / (ss_pe / df_pe)
    return {
        "ss_res": ss_res,
        "ss_lof": ss_lof,
        "df_lof": df_lof,
        "df_pe": df_pe,
        "F": float(f),
        "p_value": float(stats.f.sf(f, df_lof, df_pe)),
    }


def replicate_floor(
    spin_rate: ArrayLike,
    opening_time: ArrayLike,
    *,
    gap: float = DEFAULT_CLUSTER_GAP,
    groups: ArrayLike | None = None,
) -> ReplicateFloor:
    """Cluster the runs and compute the pure-error floor, overall and per band.

    Parameters
    ----------
    spin_rate : array_like
        omega_p per run [rad/s].
    opening_time : array_like
        Measured t_cr per run [s].
    gap : float
        Single-linkage gap [rad/s] (:func:`cluster_runs`).
    groups : array_like, optional
        Per run, its settings group: only runs of one group can be replicates.

    Returns
    -------
    ReplicateFloor
    """
    w = np.asarray(spin_rate, dtype=float).reshape(-1)
    y = np.asarray(opening_time, dtype=float).reshape(-1)
    if w.size != y.size:
        raise InputError("opening_time", f"has {y.size} entries, expected {w.size}")
    lab = cluster_runs(w, gap, groups)
    # cluster mean spin decides the band of every run in the cluster
    mean_w = np.empty_like(w)
    for c in np.unique(lab):
        mean_w[lab == c] = w[lab == c].mean()
    b_of = band_of(mean_w)
    bands = {
        label: _band_floor(label, y[b_of == label], lab[b_of == label]) for label in band_labels()
    }
    return ReplicateFloor(w, y, lab, float(gap), _band_floor("all", y, lab), bands)
