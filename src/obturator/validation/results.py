"""Result objects of the validation study (numbers only; text in :mod:`.textreport`).

:class:`CandidateFit` is one fit of one candidate to one selection of runs;
:class:`ModelResult` gathers a candidate's fits (all runs, starred runs, the
two out-of-band fits), its t_cr(omega_p) curve and its convergence check;
:class:`ValidationResult` is the whole study with the replicate floor, the
ranking and the recommendation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._docs import field_docs
from ..fitting import FitParameter
from ..json_values import finite_or_none
from .candidates import CANDIDATES, PARAMETERS
from .floor import ReplicateFloor, band_labels

__all__ = ["CandidateFit", "ModelResult", "ValidationResult", "rms_by_band"]


def _clean(x: Any) -> Any:
    """NaN/inf -> None, numpy scalars -> Python, recursively."""
    if isinstance(x, dict):
        return {str(k): _clean(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_clean(v) for v in x]
    if isinstance(x, np.ndarray):
        return [_clean(v) for v in x.tolist()]
    if isinstance(x, (bool, np.bool_)):
        return bool(x)
    if isinstance(x, (int, np.integer)):
        return int(x)
    if isinstance(x, (float, np.floating)):
        return finite_or_none(x)
    return x


def rms_by_band(residuals: NDArray[np.float64], band: NDArray[np.str_]) -> dict[str, float]:
    """rms of the residuals [s] per band label (NaN for an empty band)."""
    out = {}
    for label in band_labels():
        m = band == label
        out[label] = float(np.sqrt(np.mean(residuals[m] ** 2))) if m.any() else math.nan
    return out


@field_docs
@dataclass(frozen=True)
class CandidateFit:
    """Maximum-likelihood fit of one candidate to a selection of runs."""

    #: Candidate name.
    name: str
    #: Which runs ("all", "starred", "omega_p >= 200", "omega_p < 200").
    selection: str
    #: Fitted physical parameters.
    params: tuple[str, ...]
    #: Best values (physical units, see :data:`~.candidates.PARAMETERS`).
    values: dict[str, float]
    #: Standard errors (Wald: inverse Gauss-Newton information at the optimum).
    stderr: dict[str, float]
    #: 95 % intervals (low, high); method per parameter in `ci_method`.
    ci95: dict[str, tuple[float, float]]
    #: How each interval of `ci95` was computed: "wald" (Student-t on the optimiser scale,
    #: log10 for scale parameters) or "profile" (profile likelihood, 2 delta(-log L) <= 3.84).
    ci_method: dict[str, str]
    #: Whether each value lies in its physically argued range.
    plausible: dict[str, bool]
    #: ML run-to-run scatter [s]: the one sigma of ``noise="pooled"``; under ``"band"`` the rms of
    #: the runs' sigmas (each band's in `sigma_by_group`).
    sigma: float
    #: Minimised -log L.
    nll: float
    #: Free parameters (physical + sigma).
    k: int
    #: Spin rate omega_p of each run [rad/s].
    spin_rate: NDArray[np.float64]
    #: Measured opening time y of each run [s].
    measured: NDArray[np.float64]
    #: Model t_cr of each run [s] (NaN: censored).
    model: NDArray[np.float64]
    #: Slope dt_cr/domega_p of the model at each run [s^2].
    slope: NDArray[np.float64]
    #: Effective SD s_i of each run [s].
    sd: NDArray[np.float64]
    #: Spin band of each run (by its cluster's mean spin).
    band: NDArray[np.str_]
    #: Run number of each run.
    run: NDArray[np.int64]
    #: Horizon [s].
    t_max: float
    #: Covariance of the physical parameters (delta method).
    covariance: NDArray[np.float64]
    #: Whether the optimiser (:func:`~obturator.fitting.minimize_least_squares`) reported
    #: convergence on its last pass (True when no parameter is free).
    success: bool = True
    #: The optimiser's stop message ("no free parameters" when none is free).
    message: str = ""
    #: Objective evaluations (each one t_cr per run).
    nfev: int = 0
    #: Trajectories integrated (cache misses).
    n_integrations: int = 0
    #: Integrations that failed (counted as censored).
    n_failed: int = 0
    #: Wall time of the fit [s].
    elapsed_s: float = math.nan
    #: Noise model of the likelihood (:mod:`.likelihood`): "band" (one sigma per spin band)
    #: or "pooled" (one sigma for all runs).
    noise: str = "pooled"
    #: ML sigma of each noise group [s] (a spin band, or "all").
    sigma_by_group: dict[str, float] = field(default_factory=dict)
    #: Noise group of each run, a key of `sigma_by_group` (None: `sigma` for every run).
    noise_group: NDArray[np.str_] | None = None
    #: Each run's own settings as (name, SI value) pairs, where a data file gave them (None:
    #: Table 1 for every run).
    conditions: tuple[tuple[tuple[str, float], ...], ...] | None = None
    #: Flat directions of the likelihood at the optimum (:func:`.valley.flat_directions`;
    #: empty: none, or not looked for).
    flat_directions: tuple[dict[str, Any], ...] = ()
    #: Fits of the bounded multi-start along the flattest direction that ran (0: none).
    n_restarts: int = 0

    @property
    def sigma_per_run(self) -> NDArray[np.float64]:
        """sigma_b(i) of each run [s] (without the spin-error term)."""
        if self.noise_group is None or not self.sigma_by_group:
            return np.full(self.ndata, self.sigma)
        return np.array([self.sigma_by_group[g] for g in self.noise_group.tolist()])

    @property
    def ndata(self) -> int:
        """Number of runs fitted."""
        return int(self.measured.size)

    @property
    def censored(self) -> NDArray[np.bool_]:
        """Runs the model did not open by ``t_max``."""
        return ~np.isfinite(self.model)

    @property
    def n_censored(self) -> int:
        """Number of censored runs."""
        return int(self.censored.sum())

    @property
    def residuals(self) -> NDArray[np.float64]:
        """Model - measured [s]; a censored run counts as opening at ``t_max``."""
        return np.where(self.censored, self.t_max, self.model) - self.measured

    @property
    def rms(self) -> float:
        """rms of :attr:`residuals` over the fitted runs [s]."""
        return float(np.sqrt(np.mean(self.residuals**2)))

    @property
    def rms_by_band(self) -> dict[str, float]:
        """rms per spin band [s]."""
        return rms_by_band(self.residuals, self.band)

    @property
    def aic(self) -> float:
        """2k + 2 nll."""
        return 2.0 * self.k + 2.0 * self.nll

    @property
    def bic(self) -> float:
        """k ln n + 2 nll."""
        return self.k * math.log(self.ndata) + 2.0 * self.nll

    @property
    def all_plausible(self) -> bool:
        """Every fitted value in its physical range."""
        return all(self.plausible.values())

    @property
    def parameters(self) -> dict[str, FitParameter]:
        """Each fitted parameter: its registry entry with this fit's estimate."""
        return {
            k: replace(
                PARAMETERS[k],
                value=self.values[k],
                stderr=self.stderr.get(k, math.nan),
                ci95=self.ci95.get(k, (math.nan, math.nan)),
                ci_method=self.ci_method.get(k, "wald"),
            )
            for k in self.params
        }

    def params_dict(self) -> dict[str, dict[str, Any]]:
        """{name: {value, stderr, ci95, ci_method, unit, plausible_range, plausible}}."""
        return {
            k: {
                "value": p.value,
                "stderr": p.stderr,
                "ci95": list(p.ci95 or (math.nan, math.nan)),
                "ci_method": p.ci_method,
                "unit": p.unit,
                "plausible_range": list(p.plausible),
                "plausible": self.plausible.get(k, True),
            }
            for k, p in self.parameters.items()
        }

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary."""
        return _clean(
            {
                "name": self.name,
                "selection": self.selection,
                "params": self.params_dict(),
                "sigma_s": self.sigma,
                "noise": self.noise,
                "sigma_by_group_s": self.sigma_by_group,
                "nll": self.nll,
                "k": self.k,
                "ndata": self.ndata,
                "aic": self.aic,
                "bic": self.bic,
                "rms_s": self.rms,
                "rms_by_band_s": self.rms_by_band,
                "n_censored": self.n_censored,
                "n_failed": self.n_failed,
                "success": self.success,
                "message": self.message,
                "nfev": self.nfev,
                "n_integrations": self.n_integrations,
                "elapsed_s": self.elapsed_s,
                "flat_directions": list(self.flat_directions),
                "n_restarts": self.n_restarts,
            }
        )


@field_docs
@dataclass(frozen=True)
class ModelResult:
    """Everything the study computed for one candidate."""

    #: Candidate name.
    name: str
    #: Fit to all runs (the ranked one).
    fit: CandidateFit
    #: Fit to the starred runs (the thesis's selection), None if the data have none.
    starred: CandidateFit | None = None
    #: Fit to the runs with cluster-mean omega_p >= 200 rad/s (None: not fitted).
    high: CandidateFit | None = None
    #: Fit to the runs with cluster-mean omega_p < 200 rad/s (None: not fitted).
    low: CandidateFit | None = None
    #: rms [s] of the predictions of `high` on the low runs ("high->low") and of `low` on the high
    #: runs ("low->high"), and of `starred` on all runs ("starred->all").
    out_of_band_rms: dict[str, float] = field(default_factory=dict)
    #: Spin grid of the all-run fit's curve t_cr(omega_p) [rad/s].
    curve_spin: NDArray[np.float64] = field(default_factory=lambda: np.empty(0))
    #: t_cr of the all-run fit at each spin of `curve_spin` [s] (NaN: censored).
    curve_t: NDArray[np.float64] = field(default_factory=lambda: np.empty(0))
    #: Max relative changes of t_cr at every run under :func:`obturator.solve.convergence_check`
    #: (empty if not run).
    convergence: dict[str, Any] = field(default_factory=dict)
    #: Lack-of-fit F test of the all-run fit (:func:`.floor.lack_of_fit`).
    lack_of_fit: dict[str, float] = field(default_factory=dict)
    #: Per-band and per-cluster goodness of fit of the all-run fit against the replicate floor
    #: (:func:`.goodness.goodness_summary`).
    goodness: dict[str, Any] = field(default_factory=dict)
    #: Predictive scores by cross-validation, per scheme ("leave_one_cluster_out",
    #: "leave_one_band_out"; :mod:`.predictive`); empty: not computed.
    predictive: dict[str, dict[str, Any]] = field(default_factory=dict)

    @property
    def description(self) -> str:
        """The candidate's one-line description."""
        c = CANDIDATES.get(self.name)
        return c.description if c is not None else self.name

    def to_dict(self) -> dict[str, Any]:
        """JSON entry of ``models`` (schema of ``obturator validate --json``)."""
        f = self.fit
        return _clean(
            {
                "name": self.name,
                "description": self.description,
                "params": f.params_dict(),
                "sigma_s": f.sigma,
                "noise": f.noise,
                "sigma_by_group_s": f.sigma_by_group,
                "k": f.k,
                "ndata": f.ndata,
                "rms_all_s": f.rms,
                "rms_by_band_s": f.rms_by_band,
                "aic": f.aic,
                "bic": f.bic,
                "nll": f.nll,
                "n_censored": f.n_censored,
                "all_plausible": f.all_plausible,
                "out_of_band_rms_s": self.out_of_band_rms,
                "predictive": self.predictive,
                "flat_directions": list(f.flat_directions),
                "n_restarts": f.n_restarts,
                "fits": {
                    sel.selection: sel.to_dict()
                    for sel in (self.starred, self.high, self.low)
                    if sel is not None
                },
                "convergence": self.convergence,
                "lack_of_fit": self.lack_of_fit,
                "goodness": self.goodness,
                "fit_elapsed_s": f.elapsed_s,
                "runs": {
                    "run": f.run,
                    "spin_rate_rad_s": f.spin_rate,
                    "measured_s": f.measured,
                    "model_s": f.model,
                    "slope_s2": f.slope,
                    "sd_s": f.sd,
                },
            }
        )


@field_docs
@dataclass(frozen=True)
class ValidationResult:
    """The whole study."""

    #: Replicate clusters and pure-error floor of the measured runs.
    floor: ReplicateFloor
    #: Result of each candidate, ranked: ascending AIC of the all-run fit.
    models: list[ModelResult]
    #: Name of the recommended model (see :func:`.study.recommend`).
    recommended: str
    #: Why that model is recommended (one paragraph).
    recommendation: str
    #: Settings of the study: data source, horizon, solver, spin SD, workers.
    settings: dict[str, Any] = field(default_factory=dict)
    #: Wall time of the study [s].
    elapsed_s: float = math.nan
    #: Spread of the recommended model's t_cr over the release phase psi_0.
    phase_scatter: dict[str, Any] = field(default_factory=dict)

    def model(self, name: str) -> ModelResult:
        """The result of one candidate by name."""
        for m in self.models:
            if m.name == name:
                return m
        raise KeyError(name)

    def to_dict(self) -> dict[str, Any]:
        """One JSON object (``obturator validate --json``)."""
        fl = self.floor
        return _clean(
            {
                "floor_rms_s": fl.floor_rms,
                "floor_rms_by_band_s": {k: b.floor_rms for k, b in fl.bands.items()},
                "floor": fl.to_dict(),
                "models": [m.to_dict() for m in self.models],
                "recommended": self.recommended,
                "recommendation": self.recommendation,
                "phase_scatter": self.phase_scatter,
                "settings": self.settings,
                "elapsed_s": self.elapsed_s,
            }
        )
