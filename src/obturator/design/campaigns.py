"""Simulated campaigns: does a plan pick the model that generated the data?

For each generating model g and campaign c (seeded):

1. draw the parameters x_c from g's Laplace posterior (:class:`.posterior.Posterior`);
2. compute the **exact** t_cr of g at x_c at every setting any plan uses (front-door
   solves, :func:`.surrogate.opening_time_table`);
3. for each plan, add replicate noise N(0, s^2), s the replicate SD of the run
   (:class:`.study.ReplicateNoise`: its spin band's pooled SD from
   :func:`obturator.validation.replicate_floor` of the measured runs, or the band's
   coefficient of variation times the predicted t_cr where larger): the synthetic
   campaign y;
4. fit every candidate to y and compare them by the Bayes factor: each candidate's
   marginal likelihood of y with its parameters integrated over its posterior (the prior
   of the new campaign is what the measured runs taught), in the surrogate's Gaussian
   form N(E t, Cov t + diag s^2) (:class:`.surrogate.Surrogate`; for a model linear in
   its parameters this is the exact evidence of the refit). Prior odds 1.

Decision rule: the campaign is *decisive* when the Bayes factor of g over every other
candidate exceeds 10 (Jeffreys's "strong"); g is *picked* when its evidence is the
largest.

"Neither": a Bayes factor only ranks the candidates; it cannot say that none of them is
right. Every campaign therefore also gets a posterior predictive check: under each
candidate m the campaign's y has the predictive N(mu_m, Sigma_m + diag s^2), so
d_m^2 = (y - mu_m)^T (Sigma_m + diag s^2)^-1 (y - mu_m) is chi^2 with N degrees of
freedom; the campaign *exposes a misfit* when every candidate fails at 5 %
(:data:`MISFIT_LEVEL`). Under a candidate's own truth this is the test's false-alarm
rate (reported with the campaigns); to see how often a plan would expose a truth
outside the candidates, each generating model g is also run with a *discrepancy*
delta_g(omega_p) added (:func:`discrepancy`): its all-run fit's mean residual per
replicate cluster (y - t_cr), interpolated in ln omega_p, so that the truth fits every
measured cluster (the 96 rad/s cluster too, which every candidate misses); applied at
any setting by its spin (an assumption: the misfit is a function of spin).
For such a truth "decisive" can only mislead.

The data come from exact solves, the evidence from the surrogate, so the surrogate's
error enters the rates as it would with real data; it is also measured directly at the
same draws (:func:`surrogate_error`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.stats import chi2

from .._docs import field_docs
from .posterior import Posterior
from .surrogate import Surrogate

__all__ = [
    "DECISIVE_BAYES_FACTOR",
    "MISFIT_LEVEL",
    "OUTSIDE",
    "Rates",
    "campaign_draws",
    "decision_rates",
    "discrepancy",
    "discrepancy_at",
    "log_evidence",
    "surrogate_error",
]

#: Bayes factor of a decisive campaign (Jeffreys 1961, Kass and Raftery 1995: "strong").
DECISIVE_BAYES_FACTOR = 10.0
#: Level of the posterior predictive check: a campaign every candidate fails at this level
#: exposes a misfit (module notes).
MISFIT_LEVEL = 0.05
#: Name of a generating model with its discrepancy added (module notes).
OUTSIDE = "{}+discrepancy"


def discrepancy(
    spin_rate: NDArray[np.float64],
    residual: NDArray[np.float64],
    cluster: NDArray[np.int64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The discrepancy of a fit: per replicate cluster its mean spin [rad/s] and mean
    residual measured - model [s] (censored runs left out), in increasing spin."""
    ok = np.isfinite(residual)
    spins, means = [], []
    for c in np.unique(cluster[ok]):
        m = ok & (cluster == c)
        spins.append(float(np.mean(spin_rate[m])))
        means.append(float(np.mean(residual[m])))
    order = np.argsort(spins)
    return np.asarray(spins)[order], np.asarray(means)[order]


def discrepancy_at(
    table: tuple[NDArray[np.float64], NDArray[np.float64]], spin_rate: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The discrepancy [s] at given spins: linear in ln omega_p between the clusters, the
    end clusters' beyond them."""
    w, d = table
    return np.interp(np.log(np.asarray(spin_rate, dtype=float)), np.log(w), d)


def campaign_draws(post: Posterior, n: int, seed: int, model_index: int) -> NDArray[np.float64]:
    """The n seeded parameter draws of one generating model (optimiser variables)."""
    return post.draws(np.random.default_rng([seed, model_index, 1]), n)


def log_evidence(
    y: NDArray[np.float64], mean: NDArray[np.float64], cov: NDArray[np.float64]
) -> NDArray[np.float64]:
    """log N(y_c; mean, cov) for every campaign c (rows of y) [nats]."""
    lc = np.linalg.cholesky(cov)
    r = np.linalg.solve(lc, (np.atleast_2d(y) - mean).T)
    n = mean.size
    return (
        -0.5 * np.sum(r * r, axis=0)
        - np.sum(np.log(np.diag(lc)))
        - 0.5 * n * math.log(2.0 * math.pi)
    )


@field_docs
@dataclass(frozen=True)
class Rates:
    """Decision rates of one plan for one generating model."""

    #: Fraction of campaigns with a Bayes factor > 10 for the generating model over every other.
    p_decisive: float
    #: Fraction of campaigns where the generating model has the largest evidence.
    p_picked: float
    #: Fraction of campaigns decisive for a wrong model.
    p_misleading: float
    #: Number of simulated campaigns the fractions are over.
    n_campaigns: int
    #: Median log10 Bayes factor of the generating model over its nearest rival (a truth
    #: outside the candidates: of the best candidate over the next).
    median_log10_bf: float
    #: Fraction of campaigns that every candidate fails by its posterior predictive check
    #: at 5 % (module notes): a misfit exposed.
    p_misfit: float = math.nan

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready (the fields; the Bayes factor's spelled out)."""
        out: dict[str, Any] = asdict(self)
        out["median_log10_bayes_factor"] = out.pop("median_log10_bf")
        return out


def decision_rates(
    exact: Mapping[str, NDArray[np.float64]],
    plan: Sequence[int],
    surrogates: Mapping[str, Surrogate],
    noise_sd: NDArray[np.float64],
    rng: np.random.Generator,
) -> dict[str, Rates]:
    """Rates of one plan per generating model (module notes).

    Parameters
    ----------
    exact : mapping of str to ndarray, shape (campaigns, settings)
        Exact t_cr of each generating model at its draws, columns indexing every setting.
    plan : sequence of int
        The plan's runs (column indices, repeats allowed).
    surrogates : mapping of str to Surrogate
        Every candidate's surrogate over the same settings.
    noise_sd : ndarray
        Replicate SD at every setting [s].
    rng : numpy.random.Generator
        Source of the replicate noise.
    """
    idx = np.asarray(plan, dtype=np.intp)
    names = list(surrogates)
    noise = noise_sd[idx]
    forms = {m: (s.mean(idx), s.covariance(idx) + np.diag(noise**2)) for m, s in surrogates.items()}
    out = {}
    for g in exact:  # the candidates, then any truth outside them
        t = exact[g][:, idx]
        y = t + rng.standard_normal(t.shape) * noise
        ev = np.array([log_evidence(y, *forms[m]) for m in names])  # (models, campaigns)
        best = np.argmax(ev, axis=0)
        second = np.sort(ev, axis=0)[-2] if len(names) > 1 else np.full(ev.shape[1], -np.inf)
        top_margin = ev.max(axis=0) - second
        misfit = np.mean(np.all([_ppc_fails(y, *forms[m]) for m in names], axis=0))
        if g not in names:  # outside the candidates: whatever is decisive misleads
            decisive = top_margin > math.log(DECISIVE_BAYES_FACTOR)
            out[g] = Rates(
                math.nan,
                math.nan,
                float(np.mean(decisive)),
                int(y.shape[0]),
                float(np.median(top_margin) / math.log(10.0)),
                float(misfit),
            )
            continue
        gi = names.index(g)
        others = np.delete(ev, gi, axis=0)
        margin = ev[gi] - others.max(axis=0)
        wrong_decisive = (best != gi) & (top_margin > math.log(DECISIVE_BAYES_FACTOR))
        out[g] = Rates(
            float(np.mean(margin > math.log(DECISIVE_BAYES_FACTOR))),
            float(np.mean(best == gi)),
            float(np.mean(wrong_decisive)),
            int(y.shape[0]),
            float(np.median(margin) / math.log(10.0)),
            float(misfit),
        )
    return out


def _ppc_fails(
    y: NDArray[np.float64], mean: NDArray[np.float64], cov: NDArray[np.float64]
) -> NDArray[np.bool_]:
    """Per campaign (rows of y): the model's predictive check fails at
    :data:`MISFIT_LEVEL` (d^2 beyond the chi^2_N quantile; module notes)."""
    lc = np.linalg.cholesky(cov)
    r = np.linalg.solve(lc, (np.atleast_2d(y) - mean).T)
    d2 = np.sum(r * r, axis=0)
    return np.asarray(chi2.sf(d2, mean.size) < MISFIT_LEVEL)


def surrogate_error(
    exact: NDArray[np.float64],
    draws: NDArray[np.float64],
    post: Posterior,
    sur: Surrogate,
    columns: Sequence[int],
    noise_sd: NDArray[np.float64],
) -> dict[str, float]:
    """The surrogate against the exact t_cr at the campaign draws (one generating model).

    Returns rms and largest absolute error [s] and the rms in replicate SDs, over every
    (draw, setting) pair, and the count of exact runs not opened by the horizon.
    """
    cols = np.asarray(columns, dtype=np.intp)
    approx = sur.at(cols, post.whiten(draws))
    err = approx - exact
    ok = np.isfinite(err)
    rel = err / noise_sd[cols]
    return {
        "n_compared": int(ok.sum()),
        "rms_s": float(np.sqrt(np.mean(err[ok] ** 2))) if ok.any() else math.nan,
        "max_abs_s": float(np.max(np.abs(err[ok]))) if ok.any() else math.nan,
        "rms_in_replicate_sd": float(np.sqrt(np.mean(rel[ok] ** 2))) if ok.any() else math.nan,
        "p95_abs_in_replicate_sd": float(np.quantile(np.abs(rel[ok]), 0.95))
        if ok.any()
        else math.nan,
        "n_not_opened": int((~np.isfinite(exact)).sum()),
    }
