"""Uncertainties of a fit: covariance, standard errors, Wald and profile intervals.

* :func:`covariance_internal`: (J^T J)^-1 of the residuals' Jacobian at the
  optimum, in the optimiser variables (Gauss-Newton information; times the
  reduced chi-square when the residuals carry no measurement SD);
* :func:`wald`: the delta method to the parameters' units, standard errors,
  correlations and Wald intervals x +- t_{0.975, dof} se on the optimiser's
  scale (log10 for scale parameters), clipped to the bounds (an interval that
  reaches a bound: the parameter is not identified on that side);
* :func:`profile_limit`: one side of a profile-likelihood interval
  {v : 2 delta(-log L) <= chi2_1(0.95)} by the secant method on the signed
  root r(v) = +-sqrt(2 delta(-log L)), about linear in v.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy import special

from .parameters import ParameterSet

__all__ = ["CHI2_95", "Estimate", "covariance_internal", "profile_limit", "wald"]

# The quantiles come from scipy.special (chdtri, stdtrit: what scipy.stats' chi2 and t
# evaluate), not scipy.stats, whose import would join every command's start-up
# (docs/benchmarks.md, import costs).

#: chi-square(1) 95 % quantile: the profile-likelihood threshold on 2 delta(-log L).
CHI2_95 = float(special.chdtri(1, 0.05))


def covariance_internal(jac: NDArray[np.float64], factor: float = 1.0) -> NDArray[np.float64]:
    """(J^T J)^-1 times `factor` (NaN where J^T J is singular), optimiser variables."""
    p = jac.shape[1]
    try:
        cov = np.linalg.inv(jac.T @ jac)
    except np.linalg.LinAlgError:
        cov = np.full((p, p), math.nan)
    return cov * factor if factor != 1.0 else cov


class Estimate(NamedTuple):
    """Uncertainties of the fitted parameters, in their units (order of the set)."""

    covariance: NDArray[np.float64]
    correlation: NDArray[np.float64]
    stderr: dict[str, float]
    ci95: dict[str, tuple[float, float]]


def wald(
    params: ParameterSet,
    x: NDArray[np.float64],
    cov_internal: NDArray[np.float64],
    dof: int,
    level: float = 0.95,
) -> Estimate:
    """Delta-method covariance, standard errors and Student-t Wald intervals.

    Parameters
    ----------
    params : ParameterSet
    x : ndarray
        Optimum in the optimiser variables.
    cov_internal : ndarray
        Covariance of x (:func:`covariance_internal`).
    dof : int
        Degrees of freedom of the t quantile (data minus every fitted quantity).
    level : float
        Two-sided level of the intervals.
    """
    d = params.derivatives(x)
    cov = cov_internal * np.outer(d, d)
    var_int, var = np.diag(cov_internal), np.diag(cov)
    se_int = np.sqrt(np.where(var_int >= 0.0, var_int, math.nan))
    se = np.sqrt(np.where(var >= 0.0, var, math.nan))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(se, se)
    tq = float(special.stdtrit(max(dof, 1), 0.5 + 0.5 * level))  # Student t quantile
    lo, hi = params.internal_bounds()
    ci = {}
    for j, p in enumerate(params):
        a = p.from_internal(float(max(x[j] - tq * se_int[j], lo[j])))
        b = p.from_internal(float(min(x[j] + tq * se_int[j], hi[j])))
        ci[p.name] = (min(a, b), max(a, b))
    stderr = {p.name: float(s) for p, s in zip(params, se, strict=True)}
    return Estimate(cov, corr, stderr, ci)


def profile_limit(
    signed_root: Callable[[float], float],
    x_best: float,
    side: int,
    bounds: tuple[float, float],
    guess: float,
    max_probes: int = 3,
) -> float:
    """One limit of a profile-likelihood 95 % interval, in the optimiser variable.

    Parameters
    ----------
    signed_root : callable
        x -> sign(x - x_best) sqrt(2 (nll_profile(x) - nll_best)); each call a refit
        of the other parameters with this one held at x.
    x_best : float
        The optimum.
    side : {-1, 1}
        Lower or upper limit.
    bounds : (float, float)
        The fit bounds of x; a side that reaches its bound without crossing the
        threshold returns the bound.
    guess : float
        First probe (the Wald limit; NaN or x_best: 5 % of max(|x_best|, 1) away).
    max_probes : int
        Refits on this side.
    """
    lo_b, hi_b = bounds
    bound = lo_b if side < 0 else hi_b
    zq = math.sqrt(CHI2_95)
    target = side * zq
    if not math.isfinite(guess) or guess == x_best:
        guess = x_best + side * 0.05 * max(abs(x_best), 1.0)
    xa, ra = x_best, 0.0
    xb = min(max(guess, lo_b), hi_b)
    rb = signed_root(xb)
    for _ in range(max_probes - 1):
        if abs(rb - target) < 0.05 or (xb == bound and side * rb < zq) or rb == ra:
            break
        xn = min(max(xb + (target - rb) * (xb - xa) / (rb - ra), lo_b), hi_b)
        xa, ra = xb, rb
        xb, rb = xn, signed_root(xn)
    if (ra - target) * (rb - target) < 0.0:  # bracketed: interpolate
        return xa + (target - ra) * (xb - xa) / (rb - ra)
    return xb
