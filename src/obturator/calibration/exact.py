"""Friction calibration with the exact model (beyond the thesis's chapter IV).

mu_s (optionally also theta_0, the viscous constant S and the validation
study's mechanisms) chosen so that the integrated equations of motion
(:func:`~.rig_model.model_opening_times`) reproduce the measured t_cr, by
:func:`scipy.optimize.least_squares` with bounds. The result
(:class:`ExactFit`) is frozen and holds lmfit-style named parameters
(:class:`~.parameters.FitParameter`): best values, covariance from the
Jacobian at the optimum (central differences, scaled by the reduced
chi-square when no measurement sigma is given), standard errors, 95 %
Student-t intervals, chi-square, residuals; its text report is
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
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import stats
from scipy.optimize import least_squares

from ..errors import InputError, SolverError, check_range
from ..params import FIT_PARAMS
from ..reference import TABLE1
from ..solve import SolverOptions
from .bootstrap import BootstrapResult, OpeningTimeTable, TableSettings, bootstrap_mu_s
from .data import SpinRigData, load_spin_rig_csv, load_thesis_data
from .parameters import FitParameter, check_fit_names, fit_bounds
from .report import fit_to_dict, fit_to_json, format_fit
from .rig_model import model_opening_times, rig_model_case
from .thesis_fit import ThesisLeastSquares, thesis_least_squares

__all__ = ["ExactFit", "calibrate_csv", "fit_exact", "select_runs"]

_DIFF_STEP = 1e-4  # relative FD step: t_cr noise ~1e-8 relative, curvature ~1
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


@dataclass(frozen=True)
class ExactFit:
    """Result of :func:`fit_exact` (lmfit-style, frozen).

    Attributes
    ----------
    names : tuple of str
        Fitted parameters, in fit order (the order of the covariance rows).
    params : dict of str to FitParameter
        Every model parameter reported: mu_s, theta_0, S and anything fitted,
        each with its value, unit, and (fitted ones) bounds, stderr and ci95.
    covariance : ndarray
        Covariance of the fitted parameters (order of `names`).
    correlation : ndarray
    chisqr, redchi : float
        Sum of squared (weighted) residuals and chisqr / dof.
    ndata, nvarys, dof : int
    residuals : ndarray
        t_model - t_measured [s].
    spin_rate, measured, model : ndarray
        Per run: omega_p [rad/s], measured and model t_cr [s].
    run : ndarray
        Run numbers.
    sigma : float or None
        Assumed measurement standard deviation of t_cr [s] (None: unit
        weights, covariance scaled by redchi).
    success : bool
    message : str
    nfev : int
    settings : dict
        Fixed inputs, solver options and the data source.
    bootstrap : BootstrapResult or None
    thesis : ThesisLeastSquares or None
        The chapter IV fit on the same runs, for comparison.
    censored : ndarray of bool or None
        Runs whose model t_cr exceeds the horizon ``t_max`` (right-censored:
        the model only says t_cr > t_max). Their residual is taken at t_max,
        the smallest model value consistent with the censoring, so a model
        that opens too late is never rewarded; they are listed in the report.
    """

    names: tuple[str, ...]
    params: dict[str, FitParameter]
    covariance: NDArray[np.float64]
    correlation: NDArray[np.float64]
    chisqr: float
    redchi: float
    ndata: int
    nvarys: int
    dof: int
    residuals: NDArray[np.float64]
    spin_rate: NDArray[np.float64]
    measured: NDArray[np.float64]
    model: NDArray[np.float64]
    run: NDArray[np.int64]
    sigma: float | None
    success: bool
    message: str
    nfev: int
    settings: dict[str, Any]
    bootstrap: BootstrapResult | None = None
    thesis: ThesisLeastSquares | None = None
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
        Parameters to fit (:data:`obturator.params.FIT_PARAMS`): ``mu_s``
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
    unknown = sorted(set(model) - set(_MODEL_DEFAULTS))
    if unknown:
        raise InputError(unknown[0], "is not an input of the rig model (model_opening_times)")
    given = {**_MODEL_DEFAULTS, **model}
    # reported: mu_s, theta_0 and S always, then anything else fitted
    start = {k: given.get(k, FIT_PARAMS[k].fit.initial) for k in ("mu_s", *_ALWAYS)}
    start.update({k: model[k] if k in model else FIT_PARAMS[k].fit.initial for k in names})
    start.update(initial or {})
    model_kw = {k: v for k, v in given.items() if k not in start}
    t_max = float(given["t_max"])
    bnd = fit_bounds(names, bounds)
    scale = np.array([FIT_PARAMS[k].fit.scale for k in names])
    lo = np.array([bnd[k][0] for k in names]) / scale
    hi = np.array([bnd[k][1] for k in names]) / scale
    x0 = np.clip(np.array([start[k] for k in names]) / scale, lo, hi)
    w, t_meas = runs.spin_rate, runs.opening_time
    wt = 1.0 if sigma is None else 1.0 / sigma

    def params(x: NDArray[np.float64]) -> dict[str, float]:
        p = dict(start)
        p.update({k: float(v) for k, v in zip(names, x * scale, strict=True)})
        return p

    def model(x: NDArray[np.float64]) -> NDArray[np.float64]:
        return model_opening_times(w, **params(x), **model_kw)

    def resid(x: NDArray[np.float64]) -> NDArray[np.float64]:
        t = model(x)
        return wt * (np.where(np.isfinite(t), t, t_max) - t_meas)

    res = least_squares(
        resid, x0, bounds=(lo, hi), jac="3-point", diff_step=_DIFF_STEP, x_scale="jac"
    )
    x = res.x
    # Jacobian at the optimum by central differences in the internal variables,
    # steps kept inside the bounds.
    jac = np.empty((w.size, len(names)))
    for j in range(len(names)):
        h = _DIFF_STEP * max(abs(x[j]), 1.0)
        xp, xm = x.copy(), x.copy()
        xp[j] = min(x[j] + h, hi[j])
        xm[j] = max(x[j] - h, lo[j])
        jac[:, j] = (resid(xp) - resid(xm)) / (xp[j] - xm[j])
    t_best = model(x)
    r = resid(x)
    if not np.all(np.isfinite(r)):
        raise SolverError("exact-model fit: residuals are not all finite at the optimum")
    n, p = w.size, len(names)
    dof = max(n - p, 1)
    chisqr = float(r @ r)
    redchi = chisqr / dof
    try:
        cov_int = np.linalg.inv(jac.T @ jac)
    except np.linalg.LinAlgError:
        cov_int = np.full((p, p), np.nan)
    if sigma is None:
        cov_int = cov_int * redchi
    cov = cov_int * np.outer(scale, scale)
    se = np.sqrt(np.diag(cov))
    corr = cov / np.outer(se, se)
    tq = float(stats.t.ppf(0.975, dof))
    best = params(x)
    stderr = {k: float(s) for k, s in zip(names, se, strict=True)}
    fitted = {
        k: FitParameter(
            k,
            best[k],
            FIT_PARAMS[k].unit,
            True,
            bnd[k],
            stderr[k],
            (best[k] - tq * stderr[k], best[k] + tq * stderr[k]),
        )
        for k in names
    }
    params_out = {
        k: fitted.get(k) or FitParameter(k, v, FIT_PARAMS[k].unit, vary=False)
        for k, v in best.items()
    }
    opts = given["options"] or SolverOptions()
    settings = {
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
    }
    boot = None
    if bootstrap > 0:
        tab = table or TableSettings()
        mu = best["mu_s"]
        half = max(tab.halfwidth * mu, 6.0 * stderr["mu_s"])
        ok = np.isfinite(t_best)
        period = float(np.min(math.pi * mu / (w[ok] * t_best[ok]))) if ok.any() else half
        n_rows = int(
            np.clip(math.ceil(2.0 * half * tab.resolution / period) + 1, 4, tab.max_points)
        )
        grid = np.linspace(max(mu - half, 1e-3), mu + half, n_rows)
        held = {k: v for k, v in best.items() if k != "mu_s"}
        table_ = OpeningTimeTable.build(w, grid, verify=tab.verify, **held, **model_kw)
        boot = bootstrap_mu_s(t_meas, table_, n_resamples=bootstrap, seed=bootstrap_seed)
    thesis = thesis_least_squares(runs, theta0=math.radians(best["theta0_deg"]))
    return ExactFit(
        names=names,
        params=params_out,
        covariance=cov,
        correlation=corr,
        chisqr=chisqr,
        redchi=redchi,
        ndata=n,
        nvarys=p,
        dof=dof,
        residuals=np.where(np.isfinite(t_best), t_best, t_max) - t_meas,
        spin_rate=np.asarray(w),
        measured=np.asarray(t_meas),
        model=t_best,
        run=np.asarray(runs.run),
        sigma=sigma,
        success=bool(res.success),
        message=str(res.message),
        nfev=int(res.nfev),
        settings=settings,
        bootstrap=boot,
        thesis=thesis,
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
        ``starred``.
    theta0_deg : float
        theta_0 of the runs [deg].
    min_spin : float, optional
        Fit runs with omega_p >= min_spin [rad/s]; default the starred runs, or
        all runs if none is starred.
    **kwargs
        Passed to :func:`fit_exact`.
    """
    check_range("theta0_deg", theta0_deg, 0.0, 90.0, lo_open=True, unit="deg")
    return fit_exact(load_spin_rig_csv(path), theta0_deg=theta0_deg, min_spin=min_spin, **kwargs)
