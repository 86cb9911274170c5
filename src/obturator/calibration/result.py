"""The result of the exact-model fit (:class:`ExactFit`): numbers only.

Its text forms are :mod:`.report` (as lmfit keeps ``fit_report`` apart from
``MinimizerResult``); its parameters are :class:`obturator.fitting.FitParameter`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._docs import field_docs
from ..fitting import FitParameter
from .bootstrap import BootstrapResult
from .report import fit_to_dict, fit_to_json, format_fit
from .thesis_fit import ThesisLeastSquares

__all__ = ["ExactFit"]


@field_docs
@dataclass(frozen=True)
class ExactFit:
    """Result of :func:`~.exact.fit_exact` (lmfit-style, frozen)."""

    #: Fitted parameters, in fit order (the order of the covariance rows).
    names: tuple[str, ...]
    #: Every model parameter reported: mu_s, theta_0, S and anything fitted, each with its value,
    #: unit, and (fitted ones) bounds, stderr and ci95.
    params: dict[str, FitParameter]
    #: Covariance of the fitted parameters (order of `names`).
    covariance: NDArray[np.float64]
    #: Correlation matrix of the fitted parameters [-] (order of `names`).
    correlation: NDArray[np.float64]
    #: Sum of squared (weighted) residuals.
    chisqr: float
    #: Reduced chi-square, chisqr / dof.
    redchi: float
    #: Number of runs fitted.
    ndata: int
    #: Number of fitted parameters (the length of `names`).
    nvarys: int
    #: Degrees of freedom, ndata - nvarys (at least 1).
    dof: int
    #: t_model - t_measured [s].
    residuals: NDArray[np.float64]
    #: Spin omega_p of each run [rad/s].
    spin_rate: NDArray[np.float64]
    #: Measured t_cr of each run [s].
    measured: NDArray[np.float64]
    #: Model t_cr of each run at the best fit [s].
    model: NDArray[np.float64]
    #: Run numbers.
    run: NDArray[np.int64]
    #: Assumed measurement standard deviation of t_cr [s] (None: unit weights, covariance scaled by
    #: redchi).
    sigma: float | None
    #: Whether the least-squares optimizer reports convergence.
    success: bool
    #: The optimizer's termination message.
    message: str
    #: Number of objective (model) evaluations by the optimizer.
    nfev: int
    #: Fixed inputs, solver options and the data source.
    settings: dict[str, Any]
    #: Bootstrap of mu_s over resampled runs (None if no bootstrap was run).
    bootstrap: BootstrapResult | None = None
    #: The chapter IV fit on the same runs, for comparison.
    thesis: ThesisLeastSquares | None = None
    #: Runs whose model t_cr exceeds the horizon ``t_max`` (right-censored: the model only says t_cr
    #: > t_max). Their residual is taken at t_max, the smallest model value consistent with the
    #: censoring, so a model that opens too late is never rewarded; they are listed in the report.
    censored: NDArray[np.bool_] | None = None

    @property
    def censored_runs(self) -> list[int]:
        """Runs the best-fit model does not open within ``t_max`` (right-censored)."""
        if self.censored is None:
            return []
        return [int(r) for r in self.run[self.censored]]

    @property
    def mu_s(self) -> float:
        """Best-fit mu_s [-]."""
        return self.params["mu_s"].value

    @property
    def values(self) -> dict[str, float]:
        """Name -> value of every reported parameter (fitted and fixed)."""
        return {k: p.value for k, p in self.params.items()}

    @property
    def units(self) -> dict[str, str]:
        """Name -> unit of every reported parameter."""
        return {k: p.unit for k, p in self.params.items()}

    @property
    def stderr(self) -> dict[str, float]:
        """Name -> standard error of the fitted parameters."""
        return {k: p.stderr for k, p in self.params.items() if p.stderr is not None}

    @property
    def ci95(self) -> dict[str, tuple[float, float]]:
        """Name -> 95 % interval of the fitted parameters."""
        return {k: p.ci95 for k, p in self.params.items() if p.ci95 is not None}

    @property
    def rms(self) -> float:
        """Root-mean-square residual [s]."""
        return float(np.sqrt(np.mean(self.residuals**2)))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (see :func:`.report.fit_to_dict`)."""
        return fit_to_dict(self)

    def to_json(self) -> str:
        """:meth:`to_dict` as JSON (NaN written as null)."""
        return fit_to_json(self)

    def report(self) -> str:
        """Readable text report (see :func:`.report.format_fit`)."""
        return format_fit(self)
