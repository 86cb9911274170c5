"""Monte Carlo input distributions against their exact moments and quantiles, tails included.

References are computed independently of the sampler: closed-form moments, and the
truncated-normal mean and CDF written with scipy.special's log-space normal CDF
(``log_ndtr``), not with scipy.stats.truncnorm (which the sampler uses).
"""

import math

import numpy as np
import pytest
from scipy import stats
from scipy.special import log_ndtr

from obturator.sweeps import Distribution, sample_inputs

N = 4000


def _draw(dist: Distribution, n: int = N, seed: int = 7) -> np.ndarray:
    return sample_inputs({"mu_s": dist}, n, seed)["mu_s"]


def _log_upper(x: float) -> float:
    """log P(Z > x) for a standard normal."""
    return float(log_ndtr(-x))


def _trunc_mean(m: float, s: float, lo: float, hi: float) -> float:
    # E = m + s (phi(a) - phi(b)) / (Phi(b) - Phi(a)); in the upper tail with
    # Phi(b) - Phi(a) = Q(a) - Q(b) and every term in logs.
    a, b = (lo - m) / s, (hi - m) / s
    if a < 0 and b < 0:  # mirror into the upper tail
        return -_trunc_mean(-m, s, -hi, -lo)
    log_phi = lambda x: -0.5 * x * x - 0.5 * math.log(2 * math.pi)  # noqa: E731
    log_z = _log_upper(a) + math.log1p(-math.exp(_log_upper(b) - _log_upper(a)))
    return m + s * (math.exp(log_phi(a) - log_z) - math.exp(log_phi(b) - log_z))


def _trunc_cdf(x: np.ndarray, m: float, s: float, lo: float, hi: float) -> np.ndarray:
    a, b = (lo - m) / s, (hi - m) / s
    if a < 0 and b < 0:  # mirror into the upper tail
        return 1.0 - _trunc_cdf(-np.asarray(x), -m, s, -hi, -lo)
    z = (np.clip(x, lo, hi) - m) / s
    # 1 - (Q(z) - Q(b)) / (Q(a) - Q(b)), all in logs (Q(a) underflows 52 sd out)
    lqa, lqb, lqz = _log_upper(a), _log_upper(b), log_ndtr(-z)
    ratio = np.exp(lqz - lqa) * (-np.expm1(lqb - lqz)) / (-math.expm1(lqb - lqa))
    return 1.0 - ratio


@pytest.mark.parametrize(
    ("params", "exact_mean"),
    [
        ((0.5473, 0.001, 0.6, 0.7), None),  # 52.7 sd above the mean (issue: returned 0.7)
        ((0.7, 0.001, 0.5, 0.6), None),  # 100 sd below (issue: returned 0.5)
        ((0.5, 0.1, 0.3, 0.7), 0.5),  # symmetric window: mean exact by symmetry
        ((0.5, 0.05, 0.55, 0.9), None),  # one sd into the tail
    ],
)
def test_truncnormal_mean_and_cdf(params, exact_mean):
    m, s, lo, hi = params
    x = _draw(Distribution("truncnormal", params))
    assert np.all((x >= lo) & (x <= hi))
    ref = _trunc_mean(m, s, lo, hi) if exact_mean is None else exact_mean
    sd = float(np.std(x))
    assert abs(float(np.mean(x)) - ref) < 5 * sd / math.sqrt(N) + 1e-12
    ks = stats.kstest(x, lambda v: _trunc_cdf(np.asarray(v), m, s, lo, hi))
    assert ks.pvalue > 1e-3


def test_truncnormal_far_tail_mean_matches_issue_value():
    # The issue's example: truncnormal:0.5473,0.001,0.6,0.7 has mean ~0.60002 (Mills ratio:
    # lo + sd / a for a = 52.7 sd), and no sample equals the upper end.
    x = _draw(Distribution("truncnormal", (0.5473, 0.001, 0.6, 0.7)))
    a = (0.6 - 0.5473) / 0.001
    assert float(np.mean(x)) == pytest.approx(0.6 + 0.001 / a, abs=2e-6)
    assert np.max(x) < 0.6002


@pytest.mark.parametrize(
    ("dist", "mean", "var", "cdf"),
    [
        (Distribution("normal", (0.5, 0.03)), 0.5, 0.03**2, stats.norm(0.5, 0.03).cdf),
        (Distribution("uniform", (0.4, 0.6)), 0.5, 0.2**2 / 12, stats.uniform(0.4, 0.2).cdf),
        (
            Distribution("lognormal", (0.5, 0.1)),
            0.5 * math.exp(0.1**2 / 2),
            0.25 * math.exp(0.01) * (math.exp(0.01) - 1),
            lambda v: stats.norm.cdf(np.log(np.asarray(v) / 0.5) / 0.1),
        ),
    ],
    ids=["normal", "uniform", "lognormal"],
)
def test_distribution_moments_and_quantiles(dist, mean, var, cdf):
    x = _draw(dist)
    assert abs(float(np.mean(x)) - mean) < 5 * math.sqrt(var / N)
    # sample variance: standard error ~ var sqrt(2/N) for these near-normal shapes
    assert abs(float(np.var(x)) - var) < 6 * var * math.sqrt(2 / N)
    assert stats.kstest(x, cdf).pvalue > 1e-3
