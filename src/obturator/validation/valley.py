"""Flat directions of a fit, and the bounded multi-start that makes its optimum one point.

A likelihood with a long, curved valley (mu_s against the slip speed of a slip-speed law)
lets a local optimiser stop anywhere along the valley floor at nearly equal -log L: two
fits of one model to the same runs then report different parameters at equal AIC
(issue 47: 'strengthening' fitted by ``design-experiment`` at mu_s 0.7627, ratio 0.2909,
slip speed 0.1319 m/s and by ``validate`` at 0.7662, 0.2692, 0.1274). Two remedies:

* one fit per model and data (:func:`obturator.validation.study.all_run_fits`, shared
  by both studies);
* this module: the valley is found from the Gauss-Newton covariance of the fit, on the
  optimiser's scale, standardised to unit SDs (its correlation matrix R). An eigenvector
  of R whose eigenvalue exceeds the smallest by :data:`FLAT_CONDITION` is a *flat
  direction*: along it the data constrain a combination of the parameters
  sqrt(lambda_max / lambda_min) times more weakly than across it. The fit is restarted
  from :data:`STARTS_PER_VALLEY` points two SDs along the flattest direction (a bounded
  multi-start: two extra fits, only for a model with a valley) and the lowest -log L
  kept; the flat directions are reported with the fit, so a reader knows which
  combination of parameters the point estimate does not pin down.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..fitting import ParameterSet
from .candidates import PARAMETERS
from .results import CandidateFit

__all__ = ["FLAT_CONDITION", "STARTS_PER_VALLEY", "flat_directions", "valley_starts"]

#: Eigenvalue ratio of the correlation matrix above which a direction is flat (an axis
#: ratio of 10: a combination ten times less constrained than the best one).
FLAT_CONDITION = 100.0
#: Restarts per flat fit: two SDs either way along the flattest direction.
STARTS_PER_VALLEY = 2
_STEP_SD = 2.0


def _internal(fit: CandidateFit) -> tuple[ParameterSet, NDArray[np.float64], NDArray[np.float64]]:
    pset = ParameterSet(tuple(PARAMETERS[k] for k in fit.params))
    x = pset.to_internal([fit.values[k] for k in fit.params])
    d = pset.derivatives(x)
    cov = np.asarray(fit.covariance, dtype=float) / np.outer(d, d)
    return pset, x, cov


def _valleys(fit: CandidateFit) -> list[tuple[float, NDArray[np.float64], NDArray[np.float64]]]:
    """(axis ratio, unit direction in standardised variables, one-SD step in optimiser
    variables) of every flat direction, flattest first."""
    if len(fit.params) < 2:
        return []
    _, _, cov = _internal(fit)
    if not np.all(np.isfinite(cov)):
        return []
    sd = np.sqrt(np.diag(cov))
    if not np.all(sd > 0.0):
        return []
    corr = cov / np.outer(sd, sd)
    lam, vec = np.linalg.eigh(0.5 * (corr + corr.T))
    lam_min = max(float(lam[0]), 1e-300)
    out = []
    for j in range(len(lam) - 1, 0, -1):
        if lam[j] / lam_min < FLAT_CONDITION:
            break
        v = vec[:, j] * np.sign(vec[np.argmax(np.abs(vec[:, j])), j])
        out.append((float(np.sqrt(lam[j] / lam_min)), v, np.sqrt(lam[j]) * v * sd))
    return out


def flat_directions(fit: CandidateFit) -> list[dict[str, Any]]:
    """The flat directions of a fit (module notes), flattest first.

    Each entry: ``axis_ratio`` sqrt(lambda / lambda_min), ``direction`` (unit weights of
    the standardised optimiser variables, by parameter) and ``one_sd_change`` (the
    change of each parameter, physical units, one SD along the direction). Empty where
    the fit has fewer than two parameters or no finite covariance.
    """
    out = []
    for ratio, v, step in _valleys(fit):
        pset, x, _ = _internal(fit)
        moved = pset.values(np.clip(x + step, *pset.internal_bounds()))
        out.append(
            {
                "axis_ratio": ratio,
                "direction": {k: float(a) for k, a in zip(fit.params, v, strict=True)},
                "one_sd_change": {k: moved[k] - fit.values[k] for k in fit.params},
            }
        )
    return out


def valley_starts(fit: CandidateFit) -> list[dict[str, float]]:
    """Start values of the bounded multi-start: :data:`STARTS_PER_VALLEY` points two SDs
    either way along the flattest direction (none without a flat direction)."""
    valleys = _valleys(fit)
    if not valleys:
        return []
    pset, x, _ = _internal(fit)
    step = valleys[0][2]
    lo, hi = pset.internal_bounds()
    return [
        pset.values(np.clip(x + sign * _STEP_SD * step, lo, hi))
        for sign in (1.0, -1.0)[:STARTS_PER_VALLEY]
    ]


def with_flat_directions(fit: CandidateFit) -> CandidateFit:
    """The fit with its flat directions recorded."""
    return replace(fit, flat_directions=tuple(flat_directions(fit)))
