"""Order statistics of a Monte Carlo study: t_cr quantiles with distribution-free
confidence intervals, and the fraction not opened with a Clopper-Pearson interval.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._docs import field_docs
from ..errors import check_range
from ..json_values import finite_or_none
from ..status import Status

__all__ = [
    "CI_METHOD",
    "QuantileEstimate",
    "MonteCarloSummary",
    "quantile_ci",
    "summarize_monte_carlo",
]


@field_docs
@dataclass(frozen=True)
class QuantileEstimate:
    """One t_cr quantile with its confidence interval."""

    #: Probability p of the quantile, in (0, 1).
    probability: float
    #: Estimated p-quantile of t_cr [s]; ``inf`` means "beyond t_max" (the order statistic is a
    #: sample that did not open).
    value: float
    #: Lower end of the confidence interval [s]; ``-inf`` when it is missing (too few samples for
    #: the confidence asked).
    lower: float
    #: Upper end of the confidence interval [s]; ``inf`` when it is open (the order statistic is a
    #: sample that did not open, or too few samples).
    upper: float
    #: Exact binomial coverage of [lower, upper] (>= the confidence asked).
    coverage: float

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready; non-finite bounds become None with flags."""

        return {
            "probability": self.probability,
            "t_cr_s": finite_or_none(self.value),
            "lower_s": finite_or_none(self.lower),
            "upper_s": finite_or_none(self.upper),
            "coverage": self.coverage,
            "beyond_t_max": bool(self.value == math.inf),
        }


@field_docs
@dataclass(frozen=True)
class MonteCarloSummary:
    """Summary of a Monte Carlo study of t_cr."""

    #: Number of samples in the study, whatever their status.
    n_samples: int
    #: Samples that opened (and converged) before t_max.
    n_opened: int
    #: Samples that did not open by t_max (right-censored, t_cr > t_max).
    n_not_opened: int
    #: Samples whose integration failed or hit the step limit (left out of the statistics).
    n_failed: int
    #: Samples that were not a valid case and were not integrated (left out).
    n_invalid: int
    #: Fraction [-] of samples not opened by t_max, among the opened + not opened samples.
    fraction_not_opened: float
    #: Clopper-Pearson interval (low, high) [-] of `fraction_not_opened` at ``confidence``.
    fraction_not_opened_ci: tuple[float, float]
    #: The requested t_cr quantiles with their confidence intervals.
    quantiles: tuple[QuantileEstimate, ...]
    #: Confidence level of the intervals, in (0, 1).
    confidence: float
    #: Give-up time [s] (not-opened samples count as t_cr > t_max).
    t_max: float
    #: Mean of t_cr over the opened samples [s] (NaN if none opened).
    mean_s: float
    #: Sample standard deviation of t_cr over the opened samples [s] (NaN if fewer than two).
    std_s: float
    #: Samples that opened but whose t_cr did not pass the convergence check (left out of the
    #: quantiles and mean, counted apart).
    n_unconverged: int = 0

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict."""
        d = {
            k: getattr(self, k)
            for k in (
                "n_samples",
                "n_opened",
                "n_not_opened",
                "n_failed",
                "n_invalid",
                "n_unconverged",
                "fraction_not_opened",
                "confidence",
                "t_max",
            )
        }
        d["fraction_not_opened_ci"] = list(self.fraction_not_opened_ci)
        d["mean_s"] = finite_or_none(self.mean_s)
        d["std_s"] = finite_or_none(self.std_s)
        d["quantiles"] = [q.to_dict() for q in self.quantiles]
        d["ci_method"] = CI_METHOD
        return d


CI_METHOD = (
    "quantile: order statistic x_(ceil(n p)); interval [x_(l), x_(u)] with "
    "l = binom.ppf(a/2, n, p), u = binom.ppf(1 - a/2, n, p) + 1 (distribution-free); "
    "fraction not opened: Clopper-Pearson"
)


def quantile_ci(x_sorted: np.ndarray, p: float, confidence: float) -> QuantileEstimate:
    """The p-quantile of sorted samples with its distribution-free order-statistic interval."""
    from scipy.stats import binom

    n = x_sorted.size
    if n == 0:
        return QuantileEstimate(p, math.nan, math.nan, math.nan, math.nan)
    k = min(max(math.ceil(n * p - 1e-12), 1), n)
    alpha = 1.0 - confidence
    lo = int(binom.ppf(alpha / 2, n, p))
    hi = int(binom.ppf(1 - alpha / 2, n, p)) + 1
    coverage = float(binom.cdf(hi - 1, n, p) - binom.cdf(lo - 1, n, p))
    lower = float(x_sorted[lo - 1]) if lo >= 1 else -math.inf
    upper = float(x_sorted[hi - 1]) if hi <= n else math.inf
    return QuantileEstimate(p, float(x_sorted[k - 1]), lower, upper, coverage)


def summarize_monte_carlo(
    t_cr: np.ndarray,
    status: np.ndarray,
    *,
    t_max: float,
    quantiles: Sequence[float] = (0.05, 0.5, 0.95),
    confidence: float = 0.95,
) -> MonteCarloSummary:
    """Quantiles of t_cr with confidence intervals, and the fraction not opened.

    Samples that did not open by t_max are kept as right-censored values
    (t_cr > t_max, ranked last), so a quantile that falls among them is
    reported as ``inf`` ("beyond t_max"). Solver failures and invalid samples
    are left out (and counted). Quantile intervals are distribution-free
    order-statistic intervals: with B ~ Binomial(n, p) the number of samples
    below the true quantile, [x_(l), x_(u)] covers it with probability
    P(l <= B <= u - 1) >= ``confidence``; the exact coverage is reported.

    Parameters
    ----------
    t_cr : array_like
        Opening times [s] (NaN where not opened).
    status : array_like
        Status codes (:class:`~obturator.status.Status`).
    t_max : float
        Give-up time of the runs [s].
    quantiles : sequence of float
        Probabilities in (0, 1).
    confidence : float
        Confidence level of the intervals, in (0, 1).
    """
    from scipy.stats import beta

    conf = check_range("confidence", confidence, 0.0, 1.0, lo_open=True, hi_open=True)
    probs = [check_range("quantile", q, 0.0, 1.0, lo_open=True, hi_open=True) for q in quantiles]
    t = np.asarray(t_cr, dtype=float).reshape(-1)
    s = np.asarray(status).reshape(-1)
    # opened-but-not-converged samples (UNCONVERGED) are regularisation artefacts
    # until shown otherwise: excluded from quantiles and mean, counted apart
    opened = t[s == Status.OPENED]
    n_not = int(np.sum(s == Status.T_MAX))
    ranked = np.sort(np.concatenate([opened, np.full(n_not, np.inf)]))
    n_valid = ranked.size
    alpha = 1.0 - conf
    if n_valid:
        frac = n_not / n_valid
        lo = 0.0 if n_not == 0 else float(beta.ppf(alpha / 2, n_not, n_valid - n_not + 1))
        hi = 1.0 if n_not == n_valid else float(beta.ppf(1 - alpha / 2, n_not + 1, n_valid - n_not))
    else:
        frac, lo, hi = math.nan, math.nan, math.nan
    return MonteCarloSummary(
        n_samples=int(t.size),
        n_opened=int(opened.size),
        n_not_opened=n_not,
        n_failed=int(np.sum((s == Status.FAILED) | (s == Status.STEP_LIMIT))),
        n_invalid=int(np.sum(s == Status.INVALID_INPUT)),
        fraction_not_opened=frac,
        fraction_not_opened_ci=(lo, hi),
        quantiles=tuple(quantile_ci(ranked, p, conf) for p in probs),
        confidence=conf,
        t_max=float(t_max),
        mean_s=float(opened.mean()) if opened.size else math.nan,
        std_s=float(opened.std(ddof=1)) if opened.size > 1 else math.nan,
        n_unconverged=int(np.sum(s == Status.UNCONVERGED)),
    )
