"""Goodness of fit per spin band and per replicate cluster, against the replicate floor.

The fitted sigmas of the ``"band"`` likelihood (:mod:`.likelihood`) absorb any
misfit of their band, so a chi-square built on them is about n by construction.
The test here uses the independent scale: the pure error of the replicate
clusters (:mod:`.floor`), band by band.

Per band b (clusters assigned by their mean spin, as the floor's bands):

* lack-of-fit sum of squares SS_lof,b = sum_j n_j (mbar_j - ybar_j)^2 over the
  band's clusters j (n_j runs, mean measured ybar_j, mean model mbar_j; a
  censored run counts as opening at ``t_max``), the part of the residual sum
  of squares that replicates cannot explain;
* F_b = (SS_lof,b / k_b) / s_pe,b^2 with k_b clusters and s_pe,b the band's
  pooled pure-error SD on df_pe,b degrees of freedom; p-value from
  F(k_b, df_pe,b). The model's parameters are fitted to all bands at once, so
  none of them is charged to one band (k_b, not k_b - p): per band the test is
  slightly conservative. A band without replicates has no test (NaN).
* the descriptive chi-square sum r_i^2 / s_i^2 with the fit's own effective SDs.

Overall, X^2 = sum_b SS_lof,b / s_pe,b^2 over the bands with a pure error,
referred to chi-square with sum_b k_b - p degrees of freedom (the band SDs
taken as known: an approximation, read the p-value as a guide).

Per cluster j the standardized residual is z_j = (mbar_j - ybar_j) /
(s_pe,b / sqrt(n_j)), the band's pure-error SD as the scale (a cluster's own
SD from two or three runs is too unsteady to divide by); the cluster's own SD
is reported beside it. Clusters are named by their mean spin
("96 rad/s"), as an experimentalist would.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import InputError
from .floor import ReplicateFloor, band_labels, band_of
from .results import CandidateFit

__all__ = [
    "band_goodness",
    "cluster_goodness",
    "cluster_name",
    "goodness_summary",
    "overall_goodness",
]


def cluster_name(spin_rate: float) -> str:
    """A cluster's name: its mean spin, rounded to 1 rad/s ("96 rad/s")."""
    return f"{spin_rate:.0f} rad/s"


def _check(floor: ReplicateFloor, fit: CandidateFit) -> None:
    if fit.measured.size != floor.opening_time.size or not np.array_equal(
        fit.measured, floor.opening_time
    ):
        raise InputError("fit", "its runs are not the floor's runs (same runs, same order)")


def _band_sd(floor: ReplicateFloor, label: str) -> tuple[float, int]:
    b = floor.bands.get(label)
    if b is not None and b.dof > 0 and math.isfinite(b.pooled_sd) and b.pooled_sd > 0:
        return b.pooled_sd, b.dof
    return math.nan, 0


def cluster_goodness(floor: ReplicateFloor, fit: CandidateFit) -> list[dict[str, Any]]:
    """One row per replicate cluster: measured and model means, residual, z (see notes).

    Parameters
    ----------
    floor : ReplicateFloor
        Floor of the same runs, in the same order as the fit's.
    fit : CandidateFit
        An all-run fit.

    Returns
    -------
    list of dict
        Keys ``cluster``, ``name``, ``band``, ``n``, ``spin_rate_rad_s``,
        ``t_mean_s``, ``t_sd_s`` (NaN for one run), ``model_mean_s``,
        ``residual_s`` (model - measured), ``z_band`` (residual over the band's
        pure-error SD / sqrt(n)), ``z_cluster`` (over the cluster's own SD /
        sqrt(n); NaN for one run).
    """
    _check(floor, fit)
    model = np.where(fit.censored, fit.t_max, fit.model)
    mean_w = floor.cluster_mean_spin()
    bands = band_of(mean_w)
    rows = []
    for c in np.unique(floor.cluster):
        m = floor.cluster == c
        n = int(m.sum())
        y = floor.opening_time[m]
        res = float(model[m].mean() - y.mean())
        sd_c = float(y.std(ddof=1)) if n > 1 else math.nan
        band = str(bands[m][0])
        sd_b, _ = _band_sd(floor, band)
        rows.append(
            {
                "cluster": int(c),
                "name": cluster_name(float(mean_w[m][0])),
                "band": band,
                "n": n,
                "spin_rate_rad_s": float(mean_w[m][0]),
                "t_mean_s": float(y.mean()),
                "t_sd_s": sd_c,
                "model_mean_s": float(model[m].mean()),
                "residual_s": res,
                "z_band": res / (sd_b / math.sqrt(n)) if math.isfinite(sd_b) else math.nan,
                "z_cluster": res / (sd_c / math.sqrt(n)) if n > 1 and sd_c > 0 else math.nan,
            }
        )
    return rows


def band_goodness(floor: ReplicateFloor, fit: CandidateFit) -> dict[str, dict[str, Any]]:
    """Per band: rms, fitted sigma, chi-square, lack-of-fit F against the pure error.

    Returns
    -------
    dict of str to dict
        Per band label (:data:`~.floor.BANDS` order, bands with runs): ``n_runs``,
        ``n_clusters``, ``rms_s``, ``sigma_s`` (the fit's sigma for the band),
        ``pure_error_sd_s``, ``df_pe``, ``chi2`` (sum r^2/s^2 with the fit's SDs),
        ``ss_lof_s2``, ``F``, ``p_value``.
    """
    from scipy import stats

    clusters = cluster_goodness(floor, fit)
    r = fit.residuals
    z2 = (r / fit.sd) ** 2
    run_band = band_of(floor.cluster_mean_spin())
    sigma = fit.sigma_per_run
    out: dict[str, dict[str, Any]] = {}
    for label in band_labels():
        sel = run_band == label
        if not sel.any():
            continue
        rows = [c for c in clusters if c["band"] == label]
        ss_lof = float(sum(c["n"] * c["residual_s"] ** 2 for c in rows))
        sd_pe, df_pe = _band_sd(floor, label)
        k = len(rows)
        f = p = math.nan
        if df_pe > 0:
            f = (ss_lof / k) / sd_pe**2
            p = float(stats.f.sf(f, k, df_pe))
        out[label] = {
            "n_runs": int(sel.sum()),
            "n_clusters": k,
            "rms_s": float(np.sqrt(np.mean(r[sel] ** 2))),
            "sigma_s": float(np.sqrt(np.mean(sigma[sel] ** 2))),
            "pure_error_sd_s": sd_pe,
            "df_pe": df_pe,
            "chi2": float(z2[sel].sum()),
            "ss_lof_s2": ss_lof,
            "F": f,
            "p_value": p,
        }
    return out


def overall_goodness(bands: dict[str, dict[str, Any]], n_params: int) -> dict[str, float | int]:
    """Heteroscedastic lack of fit over the bands with a pure error (see notes).

    Parameters
    ----------
    bands : dict
        :func:`band_goodness` of a fit.
    n_params : int
        Fitted parameters of the mean curve (sigmas not counted).

    Returns
    -------
    dict
        ``X2``, ``dof``, ``p_value`` and ``n_bands`` tested.
    """
    from scipy import stats

    tested = [b for b in bands.values() if b["df_pe"] > 0]
    x2 = float(sum(b["ss_lof_s2"] / b["pure_error_sd_s"] ** 2 for b in tested))
    dof = int(sum(b["n_clusters"] for b in tested)) - int(n_params)
    p = float(stats.chi2.sf(x2, dof)) if tested and dof > 0 else math.nan
    return {"X2": x2, "dof": dof, "p_value": p, "n_bands": len(tested)}


def goodness_summary(floor: ReplicateFloor, fit: CandidateFit) -> dict[str, Any]:
    """Bands, overall test and clusters of one fit, JSON-ready by :mod:`.results`."""
    bands = band_goodness(floor, fit)
    return {
        "bands": bands,
        "overall": overall_goodness(bands, len(fit.params)),
        "clusters": cluster_goodness(floor, fit),
    }
