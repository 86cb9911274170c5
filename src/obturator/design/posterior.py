"""Parameter uncertainty of each candidate: the Laplace posterior of its validation fit.

The maximum-likelihood fit of :func:`obturator.validation.fit_candidate` to the measured
runs gives the optimum x_hat on the optimiser's scale (log10 for ``slip_speed``, value /
scale for the others; :data:`obturator.params.FIT_SPECS`) and the Gauss-Newton
covariance C = (J^T J)^-1 there. With a flat prior on that scale the posterior is, to
second order, N(x_hat, C) (Laplace's approximation); draws outside the fit bounds are
clipped to them. The design propagates these draws, not the point estimate alone.

Parameters that belong to a ball
--------------------------------
The fitted theta_0 offset is the as-built ball's: the laser reads the reflection of a
polished spot on the ball, not the hole axis (:data:`obturator.params.FIT_SPECS`), so the
offset is the spot's, and a new ball (another hole radius or density) has its own. A
posterior of a candidate that fits such a parameter (:data:`BALL_SPECIFIC`) carries a
second copy of it, ``<name>@new_ball``, the new ball's, independent of everything fitted:
its prior is the parameter's stated range (the fit registry's plausible range: theta_0
87.25 +- 1 deg, "could only vary by +-1 deg", thesis chapter IV p. 97), as a Gaussian
with the mean and SD of that uniform range (SD 0.58 deg). The as-built ball's fitted
offset (85.3 deg under band-wise noise: outside the range) is not carried over: it is
what one spot did. A wider prior was tried (SD the as-built offset, 1.95 deg): it puts
the new ball's release within 0.3 deg of 90 deg in about a tenth of the draws, where
t_cr grows without bound, and the second-order surrogate of t_cr then missed the exact
solves by 2.2 replicate SDs rms (17.7 s at worst). A run on a new ball uses that copy
(:func:`.settings.design_case`); a run on the as-built ball the fitted one.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._docs import field_docs
from ..errors import InputError
from ..fitting import ParameterSet
from ..validation.candidates import PARAMETERS
from ..validation.results import CandidateFit
from .settings import NEW_BALL

__all__ = ["BALL_SPECIFIC", "NEW_BALL", "Posterior", "base_name", "new_ball_prior_sd"]

#: Fitted parameters that belong to the ball (module notes), with the half-width of
#: their stated tolerance (physical units).
BALL_SPECIFIC: dict[str, float] = {"theta0_deg": 1.0}


def base_name(name: str) -> str:
    """The registry name of a posterior parameter (its new-ball copy's without suffix)."""
    return name.removesuffix(NEW_BALL)


def new_ball_prior_sd(name: str) -> float:
    """Prior SD of a new ball's `name` (physical units): its stated tolerance as the SD of
    a uniform range (module notes)."""
    return BALL_SPECIFIC[name] / math.sqrt(3.0)


@field_docs
@dataclass(frozen=True)
class Posterior:
    """N(mean, covariance) of one candidate's parameters on the optimiser's scale."""

    #: Candidate name.
    model: str
    #: The candidate's fitted parameters, in order.
    params: tuple[str, ...]
    #: Posterior mean x_hat: the best fit in optimiser variables, one per parameter.
    mean: NDArray[np.float64]
    #: Posterior covariance C of x (optimiser variables), shape (k, k) for k parameters.
    covariance: NDArray[np.float64]
    #: Best value of each parameter (physical units).
    values: dict[str, float]
    #: The fit's ML run-to-run scatter [s] (reported; the design's noise is the floor).
    sigma: float
    #: AIC of the fit.
    aic: float

    def __post_init__(self) -> None:
        c = self.covariance
        if not self.params:
            raise InputError("models", f"{self.model!r} fits no parameter: nothing to design")
        if c.shape != (len(self.params),) * 2 or not np.all(np.isfinite(c)):
            raise InputError(
                "models", f"{self.model!r}: its fit has no finite covariance (not identified)"
            )

    @property
    def parameter_set(self) -> ParameterSet:
        """The fit registry's parameters (bounds, transforms)."""
        return ParameterSet(tuple(PARAMETERS[base_name(k)] for k in self.params))

    @property
    def cholesky(self) -> NDArray[np.float64]:
        """Lower factor L of the covariance (C = L L^T; a tiny ridge if it is singular)."""
        c = 0.5 * (self.covariance + self.covariance.T)
        try:
            return np.linalg.cholesky(c)
        except np.linalg.LinAlgError:
            ridge = 1e-12 * max(float(np.max(np.diag(c))), 1e-300)
            return np.linalg.cholesky(c + ridge * np.eye(c.shape[0]))

    @property
    def sd(self) -> NDArray[np.float64]:
        """Posterior SD of each optimiser variable."""
        return np.sqrt(np.diag(self.covariance))

    def clip(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """x clipped into the fit bounds (rows of x: points)."""
        lo, hi = self.parameter_set.internal_bounds()
        return np.clip(x, lo, hi)

    def draws(self, rng: np.random.Generator, n: int) -> NDArray[np.float64]:
        """n draws (rows) of x, clipped into the fit bounds."""
        z = rng.standard_normal((n, len(self.params)))
        return self.clip(self.mean + z @ self.cholesky.T)

    def whiten(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """z = L^-1 (x - mean) per row: the draw in posterior SDs along L's columns."""
        return np.linalg.solve(self.cholesky, (np.atleast_2d(x) - self.mean).T).T

    def to_values(self, x: NDArray[np.float64]) -> dict[str, float]:
        """Physical values of one point x (a new ball's copies under their own names)."""
        vals = [p.from_internal(float(v)) for p, v in zip(self.parameter_set, x, strict=True)]
        return dict(zip(self.params, vals, strict=True))

    @property
    def new_ball_params(self) -> tuple[str, ...]:
        """The new ball's copies of the ball-specific parameters (module notes)."""
        return tuple(k for k in self.params if k.endswith(NEW_BALL))

    @classmethod
    def from_fit(cls, fit: CandidateFit) -> Posterior:
        """The Laplace posterior of a validation fit (physical covariance -> optimiser's),
        with a new ball's copy of each ball-specific parameter (module notes)."""
        pset = ParameterSet(tuple(PARAMETERS[k] for k in fit.params))
        x = pset.to_internal([fit.values[k] for k in fit.params])
        d = pset.derivatives(x)
        cov = np.asarray(fit.covariance, dtype=float) / np.outer(d, d)
        params, values = list(fit.params), dict(fit.values)
        for k in fit.params:
            if k in BALL_SPECIFIC:
                par = PARAMETERS[k]
                sd = new_ball_prior_sd(k)
                x0 = par.to_internal(par.start)
                # on the optimiser's scale (value / scale for theta_0: linear)
                sd_int = abs(par.to_internal(par.start + sd) - x0)
                params.append(k + NEW_BALL)
                values[k + NEW_BALL] = par.start
                x = np.append(x, x0)
                grown = np.zeros((x.size, x.size))
                grown[:-1, :-1] = cov
                grown[-1, -1] = sd_int**2
                cov = grown
        return cls(fit.name, tuple(params), x, cov, values, fit.sigma, fit.aic)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready (also the stored result of :func:`fit_task`)."""
        return {
            "model": self.model,
            "params": list(self.params),
            "mean_internal": self.mean.tolist(),
            "covariance_internal": self.covariance.tolist(),
            "values": dict(self.values),
            "sd_internal": self.sd.tolist(),
            "sigma_s": self.sigma,
            "aic": self.aic,
            "scale": {
                k: "log10" if PARAMETERS[base_name(k)].log else "linear" for k in self.params
            },
        }

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> Posterior:
        """Inverse of :meth:`to_dict`."""
        return cls(
            str(d["model"]),
            tuple(d["params"]),
            np.asarray(d["mean_internal"], dtype=float),
            np.asarray(d["covariance_internal"], dtype=float),
            {k: float(v) for k, v in d["values"].items()},
            float(d["sigma_s"]) if d["sigma_s"] is not None else math.nan,
            float(d["aic"]) if d["aic"] is not None else math.nan,
        )
