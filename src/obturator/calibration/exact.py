"""Friction calibration with the exact model (beyond the thesis's chapter IV).

mu_s (optionally also theta_0, the viscous constant S and the validation
study's mechanisms) chosen so that the integrated equations of motion
(:func:`~.rig_model.model_opening_times`) reproduce the measured t_cr, by
bounded least squares (the fit engine, :mod:`obturator.fitting`; bounds,
transforms and their reasons in :data:`obturator.params.FIT_SPECS`). The
result (:class:`~.result.ExactFit`) is frozen and holds lmfit-style named
parameters (:class:`obturator.fitting.FitParameter`): best values,
covariance from the Jacobian at the optimum (central differences, scaled by
the reduced chi-square when no measurement sigma is given), standard errors,
95 % Student-t intervals, chi-square, residuals; its text report is
:mod:`.report`. An optional bootstrap of mu_s (:mod:`.bootstrap`) and the
chapter IV method on the same runs (:mod:`.thesis_fit`) come with it.

The thesis's method rests on the linearised solution, which underestimates
the exact t_cr by 3.4-4.8 % at 300-700 rad/s (mu_s = 0.5473). Convergence: on
the thesis data the fitted mu_s moves by < 1e-5 when rtol is divided by 100,
the friction regularisation width by 10, or the integrator is switched to
Rosenbrock.

The exact rig model opens at every spin (40 rad/s at mu_s = 0.55: 43 s), but
a run that has not opened within the integration horizon ``t_max`` has no
t_cr; its model value is replaced by ``t_max``, which pushes the optimiser
away from parameters that open too late.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..errors import InputError, SolverError, check_range
from ..fitting import (
    FIT_PARAMETERS,
    Estimate,
    FitParameter,
    LeastSquaresSettings,
    ParameterSet,
    central_jacobian,
    covariance_internal,
    minimize_least_squares,
    registered,
    wald,
)
from ..reference import TABLE1
from ..solve import SolverOptions
from .bootstrap import BootstrapResult, OpeningTimeTable, TableSettings, bootstrap_mu_s
from .data import CASE_COLUMNS, SpinRigData, load_spin_rig_csv, load_thesis_data
from .result import ExactFit
from .rig_model import model_opening_times, rig_model_case
from .thesis_fit import thesis_least_squares

__all__ = ["ExactFit", "calibrate_csv", "check_fit_names", "fit_exact", "select_runs"]

_DIFF_STEP = 1e-4  # relative FD step: t_cr noise ~1e-8 relative, curvature ~1
#: The optimiser's settings (scipy's trust-region reflective defaults otherwise).
_SETTINGS = LeastSquaresSettings("3-point", _DIFF_STEP, "jac", 1e-8, 1e-8, _DIFF_STEP)
#: The model's fixed inputs and their defaults (solver options and the keyword arguments
#: of rig_model_case).
_MODEL_DEFAULTS: dict[str, Any] = {
    "options": None,
    **{
        k: p.default
        for k, p in inspect.signature(rig_model_case).parameters.items()
        if p.kind is p.KEYWORD_ONLY and p.default is not p.empty
    },
}
#: Reported with every fit, fitted or not.
_ALWAYS = ("theta0_deg", "shear_constant")


def select_runs(data: SpinRigData, min_spin: float | None = None) -> SpinRigData:
    """Runs to fit: spin >= `min_spin` [rad/s] if given, else the starred runs, else all."""
    if min_spin is not None:
        out = data.fit_subset(min_spin)
    elif data.starred.any():
        out = data.fit_subset()
    else:
        out = data
    if len(out) < 2:
        raise InputError(
            "min_spin" if min_spin is not None else "data",
            f"{len(out)} runs selected from {data.source or 'data'}; need at least 2",
        )
    return out


def check_fit_names(fit: Sequence[str]) -> tuple[str, ...]:
    """The fitted names without repeats: registered fit parameters that are inputs of
    the rig model (:func:`~.rig_model.model_opening_times`), mu_s among them."""
    names = tuple(dict.fromkeys(fit))
    allowed = [k for k in FIT_PARAMETERS if k == "mu_s" or k in _MODEL_DEFAULTS]
    for k in names:
        if k not in allowed:
            raise InputError("fit", f"{k!r}; allowed: {', '.join(allowed)}")
    if "mu_s" not in names:
        raise InputError("fit", "mu_s must be among the fitted parameters")
    return names


@dataclass(frozen=True)
class _RigObjective:
    """The calibration's objective: residuals of the exact model's t_cr at the runs.

    A run the model has not opened by ``t_max`` counts as opening at ``t_max``
    (right-censored: the smallest model value consistent with it).
    """

    spin_rate: NDArray[np.float64]
    measured: NDArray[np.float64]
    t_max: float
    weight: float
    params: ParameterSet
    held: dict[str, float]
    model_kw: dict[str, Any]

    def values(self, x: NDArray[np.float64]) -> dict[str, float]:
        """Every reported parameter: held values, then the fitted ones at x."""
        return {**self.held, **self.params.values(x)}

    def model(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """Model t_cr [s] per run (NaN: not opened by ``t_max``)."""
        return model_opening_times(self.spin_rate, **self.values(x), **self.model_kw)

    def residuals_of(self, t_model: NDArray[np.float64]) -> NDArray[np.float64]:
        """weight (t_model - t_measured), censored runs taken at ``t_max``."""
        t = np.where(np.isfinite(t_model), t_model, self.t_max)
        return self.weight * (t - self.measured)

    def __call__(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        return self.residuals_of(self.model(x))


def _objective(
    runs: SpinRigData,
    names: tuple[str, ...],
    initial: Mapping[str, float] | None,
    bounds: Mapping[str, tuple[float, float]] | None,
    sigma: float | None,
    model: Mapping[str, Any],
) -> tuple[_RigObjective, dict[str, Any]]:
    """The objective and the model's inputs (defaults, then those given)."""
    unknown = sorted(set(model) - set(_MODEL_DEFAULTS))
    if unknown:
        raise InputError(unknown[0], "is not an input of the rig model (model_opening_times)")
    given = {**_MODEL_DEFAULTS, **model}
    # reported: mu_s, theta_0 and S always, then anything else fitted; started at
    # the value given, else the model's, else the registry's start
    start = {k: given.get(k, FIT_PARAMETERS[k].start) for k in ("mu_s", *_ALWAYS)}
    start.update({k: model[k] if k in model else FIT_PARAMETERS[k].start for k in names})
    start.update(initial or {})
    objective = _RigObjective(
        spin_rate=runs.spin_rate,
        measured=runs.opening_time,
        t_max=float(given["t_max"]),
        weight=1.0 if sigma is None else 1.0 / sigma,
        params=ParameterSet.of(names, {k: v for k, v in (bounds or {}).items() if k in names}),
        held=start,
        # each run's own settings (data-file columns) ride with the model's inputs
        model_kw={k: v for k, v in given.items() if k not in start}
        | {"run_settings": runs.run_settings()},
    )
    return objective, given


def _reported(
    objective: _RigObjective, values: dict[str, float], est: Estimate
) -> dict[str, FitParameter]:
    """Every reported parameter: fitted ones with their errors, the others held."""
    fitted = {
        p.name: replace(p, value=values[p.name], stderr=est.stderr[p.name], ci95=est.ci95[p.name])
        for p in objective.params
    }
    return {k: fitted.get(k) or registered(k, v, vary=False) for k, v in values.items()}


def _describe(
    runs: SpinRigData, data: SpinRigData, min_spin: float | None, given: dict[str, Any]
) -> dict[str, Any]:
    """The fit's settings as reported: data, selection, model, solver, Jacobian."""
    opts = given["options"] or SolverOptions()
    return {
        "source": runs.source or data.source,
        "selection": f"omega_p >= {min_spin:g} rad/s"
        if min_spin is not None
        else ("starred runs" if data.starred.any() else "all runs"),
        "weight": given["weight"],
        "torque_model": given["torque_model"],
        "t_max": given["t_max"],
        "solver": f"{opts.method} rtol={opts.rtol:g} atol={opts.atol:g} "
        f"friction_width={opts.friction_width:g} formulation={opts.formulation}",
        "jacobian": f"central differences, relative step {_DIFF_STEP:g}",
        # the data file's per-run columns the model used (theta_0, ball, load)
        "run_settings": sorted(
            k for k in runs.settings if k not in ("theta_measured_deg", "t_measured")
        ),
    }


def _bootstrap(
    objective: _RigObjective,
    values: dict[str, float],
    stderr_mu: float,
    t_best: NDArray[np.float64],
    n_resamples: int,
    seed: int,
    table: TableSettings | None,
) -> BootstrapResult:
    """Bootstrap of mu_s on a t_cr table around the best fit, the rest held at it."""
    tab = table or TableSettings()
    grid = tab.mu_grid(values["mu_s"], stderr_mu, objective.spin_rate, t_best)
    held = {k: v for k, v in values.items() if k != "mu_s"}
    t = OpeningTimeTable.build(
        objective.spin_rate, grid, verify=tab.verify, **held, **objective.model_kw
    )
    return bootstrap_mu_s(objective.measured, t, n_resamples=n_resamples, seed=seed)


def _check_identified(
    objective: _RigObjective,
    x: NDArray[np.float64],
    t_model: NDArray[np.float64],
    jac: NDArray[np.float64],
    runs: SpinRigData,
) -> None:
    """Refuse a fit the runs cannot identify, naming why.

    * Every run censored: the model opens none of them by ``t_max``, so every
      residual is ``t_max - t_measured`` whatever the parameters, and the optimiser
      stops at its start (reported before as success, with a NaN error).
    * A fitted parameter whose Jacobian column is zero: no run's t_cr moves with it
      at the optimum (every run censored, or the mechanism absent at these runs), so
      its covariance is undefined.
    """
    n = t_model.size
    values = objective.values(x)
    if not np.any(np.isfinite(t_model)):
        th = values.get("theta0_deg", math.nan)
        raise InputError(
            "data",
            f"the model opens none of the {n} fitted runs by t_max = {objective.t_max:g} s "
            f"(every run censored at theta0 = {th:g} deg, mu_s = {values['mu_s']:.4g}), so "
            f"the runs cannot identify {', '.join(p.name for p in objective.params)}; check "
            "theta0 (90 deg is the equilibrium with the hole square to the spin), each "
            "run's hole radius, and t_max",
        )
    for j, par in enumerate(objective.params):
        column = jac[:, j]
        if np.all(np.isfinite(column)) and np.any(column != 0.0):
            continue
        censored = int(np.sum(~np.isfinite(t_model)))
        raise InputError(
            "fit",
            f"{par.name}: the {n} fitted runs carry no information on it (no run's t_cr "
            f"changes with it at {values[par.name]:.6g}; {censored} of {n} runs censored at "
            f"t_max = {objective.t_max:g} s); hold it fixed or add runs where it acts",
        )


def fit_exact(
    data: SpinRigData | None = None,
    *,
    fit: Sequence[str] = ("mu_s",),
    initial: dict[str, float] | None = None,
    bounds: dict[str, tuple[float, float]] | None = None,
    min_spin: float | None = None,
    sigma: float | None = None,
    bootstrap: int = 200,
    bootstrap_seed: int = 0,
    table: TableSettings | None = None,
    **model: Any,
) -> ExactFit:
    """Fit mu_s (and optionally theta_0, S) of the exact rig model to measured t_cr.

    Parameters
    ----------
    data : SpinRigData, optional
        Runs (default: thesis Appendix B); selected by :func:`select_runs`.
    fit : sequence of str
        Parameters to fit (:data:`obturator.params.FIT_SPECS`): ``mu_s``
        (always), ``theta0_deg`` [deg], ``shear_constant`` [N m s], and the
        validation study's mechanisms; the others stay at the model's values.
    initial : dict, optional
        Starting values (defaults: the value given in `model`, else the registry's).
    bounds : dict, optional
        (low, high) per parameter (defaults: the registry's).
    min_spin : float, optional
        Fit runs with omega_p >= min_spin [rad/s] instead of the starred runs.
    sigma : float, optional
        Measurement standard deviation of t_cr [s]; weights 1/sigma. None:
        unit weights, covariance scaled by the reduced chi-square.
    bootstrap : int
        Resamples of the mu_s bootstrap (0: none).
    bootstrap_seed : int
    table : TableSettings, optional
        Resolution of the bootstrap's t_cr table (see :mod:`.bootstrap`).
    **model
        The model's fixed inputs, keyword arguments of
        :func:`~.rig_model.model_opening_times`: ``theta0_deg`` and
        ``shear_constant`` (Table 1 unless fitted), ``weight`` [N] (Table 1:
        0.07987), ``torque_model`` ("thesis" Eq. 61, or exact Coulomb at the
        bottom contact), ``t_max`` [s] (integration horizon, also the model
        value of a run that does not open), ``options`` (SolverOptions), and
        mechanisms such as ``speed_law="strengthening"``.

    Returns
    -------
    ExactFit

    Notes
    -----
    The exact t_cr(mu_s) at fixed spin is smooth but rippled: the gravity
    contact's moment arm varies twice per revolution, so theta(t) carries a
    ripple of period pi/omega_p in time, and t_cr a ripple of period about
    pi mu_s / (omega_p t_cr) in mu_s (0.011 at 446 rad/s). A cubic spline
    only interpolates it well with several points per period, hence the
    table spacing period / ``table.resolution``, over the data's fastest run.
    """
    data = load_thesis_data() if data is None else data
    runs = select_runs(data, min_spin)
    names = check_fit_names(fit)
    if sigma is not None:
        check_range("sigma", sigma, 0.0, math.inf, lo_open=True, hi_open=True, unit="s")
    objective, given = _objective(runs, names, initial, bounds, sigma, model)
    box = objective.params.internal_bounds()
    x0 = objective.params.start([objective.held[k] for k in names])
    best = minimize_least_squares(objective, x0, box, _SETTINGS)
    x = best.x
    jac = central_jacobian(objective, x, box, _SETTINGS.covariance_step)
    t_best = objective.model(x)
    r = objective.residuals_of(t_best)
    if not np.all(np.isfinite(r)):
        raise SolverError("exact-model fit: residuals are not all finite at the optimum")
    _check_identified(objective, x, t_best, jac, runs)
    n, p = r.size, len(names)
    dof = max(n - p, 1)
    chisqr = float(r @ r)
    redchi = chisqr / dof
    est = wald(objective.params, x, covariance_internal(jac, redchi if sigma is None else 1.0), dof)
    values = objective.values(x)
    boot = None
    if bootstrap > 0:
        boot = _bootstrap(
            objective, values, est.stderr["mu_s"], t_best, bootstrap, bootstrap_seed, table
        )
    return ExactFit(
        names=names,
        params=_reported(objective, values, est),
        covariance=est.covariance,
        correlation=est.correlation,
        chisqr=chisqr,
        redchi=redchi,
        ndata=n,
        nvarys=p,
        dof=dof,
        residuals=np.where(np.isfinite(t_best), t_best, objective.t_max) - objective.measured,
        spin_rate=np.asarray(objective.spin_rate),
        measured=np.asarray(objective.measured),
        model=t_best,
        run=np.asarray(runs.run),
        sigma=sigma,
        success=best.success,
        message=best.message,
        nfev=best.nfev,
        settings=_describe(runs, data, min_spin, given),
        bootstrap=boot,
        thesis=thesis_least_squares(runs, theta0=math.radians(values["theta0_deg"])),
        censored=~np.isfinite(t_best),
    )


def calibrate_csv(
    path: str | Path,
    *,
    theta0_deg: float = TABLE1["theta0_deg"],
    min_spin: float | None = None,
    **kwargs: Any,
) -> ExactFit:
    """Exact-model fit of mu_s to a user's spin-rig CSV (see :func:`load_spin_rig_csv`).

    Parameters
    ----------
    path : str or Path
        CSV with ``t_cr_s`` and ``readout_hz`` or ``spin_rate_rad_s``, optional
        ``starred`` and the runs' own settings of :data:`~.data.CASE_COLUMNS` (the fit
        does not use times to intermediate angles: a file with them is refused).
    theta0_deg : float
        theta_0 of the runs [deg].
    min_spin : float, optional
        Fit runs with omega_p >= min_spin [rad/s]; default the starred runs, or
        all runs if none is starred.
    **kwargs
        Passed to :func:`fit_exact`.
    """
    check_range("theta0_deg", theta0_deg, 0.0, 90.0, lo_open=True, unit="deg")
    data = load_spin_rig_csv(path, columns=CASE_COLUMNS)
    return fit_exact(data, theta0_deg=theta0_deg, min_spin=min_spin, **kwargs)
