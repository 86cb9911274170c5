"""Friction calibration against spin-rig opening times (thesis chapter IV and beyond).

Two calibrations live here:

* **The thesis's** (re-exported from :mod:`obturator.experiment`): the
  large-spin line t = T2 omega_p (Eq. 96) fitted to the starred runs, then
  mu_bar = 3.03e-4 / T2 (Eq. 95) and mu_s = mu_bar / ((2/pi) E(theta_0)).
  It rests on the linearised solution, which underestimates the exact t_cr by
  3.4-4.8 % at 300-700 rad/s (mu_s = 0.5473).
* **The exact-model fit** (:func:`fit_exact`): mu_s (optionally also theta_0
  and the viscous constant S) chosen so that the integrated equations of motion
  (:func:`obturator.solve.opening_time`) reproduce the measured t_cr, by
  :func:`scipy.optimize.least_squares` with bounds. The result is frozen and
  reported in the style of lmfit: best values, covariance from the Jacobian at
  the optimum (central differences, scaled by the reduced chi-square when no
  measurement sigma is given), standard errors, 95 % Student-t intervals,
  chi-square, residuals.

Bootstrap
---------
Refitting the exact model 200 times would cost 200 x ~15 x N integrations.
Instead a table of exact t_cr(mu_s, omega_i) is computed once on a small mu_s
grid at the data's own spin rates (so no interpolation in omega is needed) and
interpolated in mu_s by a cubic spline per run. Each bootstrap resample (runs
drawn with replacement) refits mu_s alone, theta_0 and S held at their best
values, by a bounded scalar minimisation of the resampled sum of squares. The
interpolation error is measured against fresh exact runs at the midpoints of
the mu_s grid and reported (``BootstrapResult.interpolation_error``). On
the thesis data (28 starred runs, 88 mu_s rows) it is 2e-5 s, 1500 times
below the 0.033 s rms scatter of the data. The grid must be fine: t_cr(mu_s)
ripples (see :func:`fit_exact`, Notes), and 9 rows gave 6e-4 s.

Convergence: on the thesis data the fitted mu_s moves by < 1e-5 when rtol is
divided by 100, the friction regularisation width by 10, or the integrator
is switched to Rosenbrock.

The exact rig model opens at every spin (40 rad/s at mu_s = 0.55: 43 s), but
a run that has not opened within the integration horizon ``t_max`` has no
t_cr; its model value is replaced by ``t_max``, which pushes the optimiser
away from parameters that open too late.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import stats
from scipy.interpolate import CubicSpline
from scipy.optimize import least_squares, minimize_scalar

from ..model.cases import TABLE1, rig_case
from ..errors import InputError, SolverError, check_range
from .data import (
    PRINTED_SUMS_OMITTED_RUNS,
    SpinRigData,
    ThesisComparison,
    ThesisLeastSquares,
    compare_with_thesis,
    format_comparison,
    load_spin_rig_csv,
    load_thesis_data,
    printed_thesis_sums,
    thesis_least_squares,
)
from ..solve import SolverOptions, opening_time

__all__ = [
    "PARAMETERS",
    "PRINTED_SUMS_OMITTED_RUNS",
    "BootstrapResult",
    "ExactFit",
    "OpeningTimeTable",
    "ThesisComparison",
    "ThesisLeastSquares",
    "bootstrap_mu_s",
    "calibrate_csv",
    "compare_with_thesis",
    "fit_exact",
    "format_comparison",
    "model_opening_times",
    "printed_subset",
    "printed_thesis_sums",
    "select_runs",
    "thesis_fit",
    "thesis_least_squares",
]

#: Fittable parameters: (unit, default initial value, default bounds, internal scale).
#: The scale makes every internal variable O(1) for the optimiser.
PARAMETERS: dict[str, tuple[str, float, tuple[float, float], float]] = {
    "mu_s": ("1", 0.55, (0.02, 1.2), 1.0),
    "theta0_deg": ("deg", TABLE1["theta0_deg"], (70.0, 89.9), 10.0),
    "shear_constant": ("N m s", 12.38e-9, (0.0, 2e-7), 1e-8),
    # mechanisms for the validation study (obturator.validation): release transient
    # theta_dot_0 (a plunger/jet kick of a few rad/s at most), slip-speed law of mu
    # (ratio r, speed v_s around the rig's slip speeds 0-1.6 m/s), release phase psi_0,
    # Coulomb contact patch radius (around the 0.28 mm Hertz value)
    "theta_dot0": ("rad/s", 0.0, (-3.0, 3.0), 1.0),
    "speed_ratio": ("1", 0.5, (0.05, 1.0), 1.0),
    "slip_speed": ("m/s", 0.05, (0.002, 2.0), 0.1),
    "release_phase": ("rad", 0.0, (0.0, 2.0 * math.pi), 1.0),
    "patch_radius": ("m", 2.79e-4, (1e-5, 1e-3), 1e-4),
}
_S_TABLE1 = rig_case().torque.viscous.coefficient  # Eq. (42) with Table 1 inputs
_DIFF_STEP = 1e-4  # relative FD step: t_cr noise ~1e-8 relative, curvature ~1


# ---------------------------------------------------------------------------
# the thesis's calibration


def printed_subset(data: SpinRigData | None = None) -> SpinRigData:
    """The 24 runs that reproduce the thesis's printed sums.

    Starred runs without runs 40, 41, 45 and 51, with the printed omega_p
    column (see :mod:`obturator.experiment`).
    """
    data = load_thesis_data() if data is None else data
    return data.fit_subset().exclude_runs(PRINTED_SUMS_OMITTED_RUNS).with_printed_spin_rate()


def thesis_fit(
    data: SpinRigData | None = None,
    *,
    subset: str = "printed",
    theta0_deg: float = TABLE1["theta0_deg"],
) -> ThesisLeastSquares:
    """Chapter IV least squares (Eqs. 95-96) on the thesis data or a user's runs.

    Parameters
    ----------
    data : SpinRigData, optional
        Default: Appendix B.
    subset : {"printed", "starred"}
        For the thesis data: the 24-run subset that reproduces the printed
        sums, or all 28 starred runs with omega_p = f pi / 9. User data: starred.
    theta0_deg : float
        theta_0 [deg] for the mean moment arm (2/pi) E(theta_0).
    """
    if subset not in ("printed", "starred"):
        raise InputError("subset", f"{subset!r}; allowed: printed, starred")
    if data is None and subset == "printed":
        runs = printed_subset()
    else:
        runs = (load_thesis_data() if data is None else data).fit_subset()
    return thesis_least_squares(runs, theta0=math.radians(theta0_deg))


# ---------------------------------------------------------------------------
# the exact model


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


def model_opening_times(
    spin_rates: NDArray[np.float64],
    *,
    mu_s: float,
    theta0_deg: float = TABLE1["theta0_deg"],
    shear_constant: float = _S_TABLE1,
    weight: float = TABLE1["rig_weight"],
    torque_model: str = "thesis",
    t_max: float = 5.0,
    options: SolverOptions | None = None,
    theta_dot0: float = 0.0,
    speed_law: str = "constant",
    speed_ratio: float = 1.0,
    slip_speed: float = 0.05,
    release_phase: float = 0.0,
    patch_radius: float | None = None,
) -> NDArray[np.float64]:
    """Exact rig t_cr [s] at each spin rate [rad/s] (NaN where the ball does not open).

    The viscous constant is set through the gap-fluid viscosity, to which the
    Eq. (42) constant S is proportional. `theta_dot0` [rad/s] and
    `release_phase` [rad] set the release state, `speed_law` with `speed_ratio`
    and `slip_speed` [m/s] the slip-speed dependence of mu
    (:class:`obturator.torques.SlipSpeedLaw`), `patch_radius` [m] the Coulomb
    contact patch.
    """
    from ..model.torques import SlipSpeedLaw

    law = None if speed_law == "constant" else SlipSpeedLaw(speed_law, speed_ratio, slip_speed)
    extra: dict[str, Any] = {
        "speed_law": law,
        "release_rate": (theta_dot0, 0.0, 0.0),
        "release_phase": release_phase,
    }
    if torque_model == "coulomb":
        extra["patch_radius"] = patch_radius
    visc = TABLE1["viscosity"] * shear_constant / _S_TABLE1
    return np.array(
        [
            opening_time(
                rig_case(
                    float(w),
                    mu_s,
                    theta0_deg=theta0_deg,
                    weight=weight,
                    torque_model=torque_model,
                    viscosity=visc,
                    t_max=t_max,
                    **extra,
                ),
                options,
            )
            for w in spin_rates
        ]
    )


@dataclass(frozen=True)
class OpeningTimeTable:
    """Exact t_cr on a mu_s grid at fixed spin rates, cubic-spline interpolated in mu_s.

    Attributes
    ----------
    mu_s : ndarray
        Grid of mu_s [-] (increasing).
    spin_rate : ndarray
        Spin rates [rad/s] (the data's own).
    t_cr : ndarray, shape (n_mu, n_spin)
        Exact opening times [s].
    interpolation_error : float
        Largest |spline - exact| [s] at the grid midpoints (NaN if unchecked).
    interpolation_rel_error : float
        The same relative to t_cr [-].
    """

    mu_s: NDArray[np.float64]
    spin_rate: NDArray[np.float64]
    t_cr: NDArray[np.float64]
    interpolation_error: float = math.nan
    interpolation_rel_error: float = math.nan
    _spline: CubicSpline = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_spline", CubicSpline(self.mu_s, self.t_cr, axis=0))

    def __call__(self, mu_s: float) -> NDArray[np.float64]:
        """Interpolated t_cr [s] at every tabulated spin rate."""
        return self._spline(mu_s)

    @classmethod
    def build(
        cls,
        spin_rates: NDArray[np.float64],
        mu_grid: NDArray[np.float64],
        *,
        verify: int = 12,
        **model: Any,
    ) -> OpeningTimeTable:
        """Compute the table (and, with `verify`, its midpoint interpolation error).

        Parameters
        ----------
        spin_rates : ndarray
            Spin rates [rad/s].
        mu_grid : ndarray
            Increasing mu_s values [-]; rows with a non-opening run are dropped
            from the ends until the block around the grid centre opens everywhere.
        verify : int
            Number of grid midpoints (spread evenly) at which the exact model
            is run to measure the interpolation error; 0 skips the check.
        **model
            Keyword arguments of :func:`model_opening_times` other than mu_s.
        """
        mu_grid = np.asarray(mu_grid, dtype=float)
        rows = np.array([model_opening_times(spin_rates, mu_s=m, **model) for m in mu_grid])
        ok = np.isfinite(rows).all(axis=1)
        centre = len(mu_grid) // 2
        if not ok[centre]:
            raise SolverError("exact model does not open at the centre of the mu_s grid")
        lo = centre
        while lo > 0 and ok[lo - 1]:
            lo -= 1
        hi = centre
        while hi + 1 < len(mu_grid) and ok[hi + 1]:
            hi += 1
        if hi - lo < 3:
            raise SolverError("fewer than 4 mu_s grid rows open at every spin rate")
        table = cls(mu_grid[lo : hi + 1], np.asarray(spin_rates, float), rows[lo : hi + 1])
        if not verify:
            return table
        mids = 0.5 * (table.mu_s[1:] + table.mu_s[:-1])
        pick = np.unique(np.linspace(0, mids.size - 1, min(int(verify), mids.size)).round())
        mids = mids[pick.astype(int)]
        exact = np.array([model_opening_times(spin_rates, mu_s=m, **model) for m in mids])
        err = np.abs(np.array([table(m) for m in mids]) - exact)
        return cls(
            table.mu_s,
            table.spin_rate,
            table.t_cr,
            float(np.max(err)),
            float(np.max(err / exact)),
        )


@dataclass(frozen=True)
class BootstrapResult:
    """Bootstrap of the exact-model mu_s over resampled runs.

    Attributes
    ----------
    samples : ndarray
        Refitted mu_s per resample [-].
    interval : (float, float)
        Percentile interval [-] at `confidence`.
    confidence : float
    std : float
        Standard deviation of the samples [-].
    n_resamples : int
    seed : int
    at_grid_edge : int
        Resamples whose optimum hit the table's mu_s range (interval unreliable if > 0).
    table : OpeningTimeTable
    """

    samples: NDArray[np.float64]
    interval: tuple[float, float]
    confidence: float
    std: float
    n_resamples: int
    seed: int
    at_grid_edge: int
    table: OpeningTimeTable = field(repr=False)

    @property
    def interpolation_error(self) -> float:
        """Largest midpoint interpolation error of the t_cr table [s]."""
        return self.table.interpolation_error


def bootstrap_mu_s(
    measured: NDArray[np.float64],
    table: OpeningTimeTable,
    *,
    n_resamples: int = 200,
    seed: int = 0,
    confidence: float = 0.95,
) -> BootstrapResult:
    """Percentile bootstrap of mu_s: resample runs, refit mu_s on the interpolated table.

    Parameters
    ----------
    measured : ndarray
        Measured t_cr [s], one per column of `table`.
    table : OpeningTimeTable
    n_resamples : int
    seed : int
        Seed of :func:`numpy.random.default_rng`.
    confidence : float
        Two-sided level of the percentile interval.
    """
    rng = np.random.default_rng(seed)
    n = measured.size
    lo, hi = float(table.mu_s[0]), float(table.mu_s[-1])
    tol = 1e-3 * (hi - lo)
    samples = np.empty(n_resamples)
    edge = 0
    for b in range(n_resamples):
        idx = rng.integers(0, n, n)
        t_b = measured[idx]

        def ss(mu: float, idx: NDArray[np.int64] = idx, t_b: NDArray[np.float64] = t_b) -> float:
            return float(np.sum((table(mu)[idx] - t_b) ** 2))

        res = minimize_scalar(ss, bounds=(lo, hi), method="bounded", options={"xatol": 1e-6})
        samples[b] = res.x
        edge += int(res.x - lo < tol or hi - res.x < tol)
    alpha = 0.5 * (1.0 - confidence)
    q = np.quantile(samples, [alpha, 1.0 - alpha])
    return BootstrapResult(
        samples=samples,
        interval=(float(q[0]), float(q[1])),
        confidence=confidence,
        std=float(np.std(samples, ddof=1)),
        n_resamples=n_resamples,
        seed=seed,
        at_grid_edge=edge,
        table=table,
    )


@dataclass(frozen=True)
class ExactFit:
    """Result of :func:`fit_exact` (lmfit-style, frozen).

    Attributes
    ----------
    names : tuple of str
        Fitted parameters, in order.
    values : dict
        Best values of every model parameter (fitted and fixed).
    units : dict
    stderr : dict
        Standard errors of the fitted parameters.
    ci95 : dict
        95 % Student-t intervals (best +- t_{0.975, dof} stderr).
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
    values: dict[str, float]
    units: dict[str, str]
    stderr: dict[str, float]
    ci95: dict[str, tuple[float, float]]
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
        return self.values["mu_s"]

    @property
    def rms(self) -> float:
        """Root-mean-square residual [s]."""
        return float(np.sqrt(np.mean(self.residuals**2)))

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary."""
        out: dict[str, Any] = {
            "parameters": {
                k: {
                    "value": self.values[k],
                    "unit": self.units[k],
                    "stderr": self.stderr.get(k),
                    "ci95": list(self.ci95[k]) if k in self.ci95 else None,
                    "fitted": k in self.names,
                }
                for k in self.values
            },
            "covariance": self.covariance.tolist(),
            "correlation": self.correlation.tolist(),
            "chisqr": self.chisqr,
            "redchi": self.redchi,
            "ndata": self.ndata,
            "nvarys": self.nvarys,
            "rms_residual_s": self.rms,
            "censored_runs": self.censored_runs,
            "sigma_s": self.sigma,
            "success": self.success,
            "message": self.message,
            "nfev": self.nfev,
            "runs": [
                {
                    "run": int(r),
                    "spin_rate_rad_s": float(w),
                    "t_measured_s": float(tm),
                    "t_model_s": None if not math.isfinite(tc) else float(tc),
                }
                for r, w, tm, tc in zip(
                    self.run, self.spin_rate, self.measured, self.model, strict=True
                )
            ],
            "settings": self.settings,
        }
        if self.bootstrap is not None:
            b = self.bootstrap
            out["bootstrap"] = {
                "interval": list(b.interval),
                "confidence": b.confidence,
                "std": b.std,
                "n_resamples": b.n_resamples,
                "seed": b.seed,
                "at_grid_edge": b.at_grid_edge,
                "table_mu_s": [float(b.table.mu_s[0]), float(b.table.mu_s[-1])],
                "table_rows": int(b.table.mu_s.size),
                "interpolation_error_s": b.table.interpolation_error,
                "interpolation_rel_error": b.table.interpolation_rel_error,
            }
        if self.thesis is not None:
            out["thesis_method"] = {
                "T2": self.thesis.t2,
                "mu_bar": self.thesis.mu_bar,
                "mu_s": self.thesis.mu_s,
                "T2_direct": self.thesis.t2_direct,
                "mu_s_direct": self.thesis.mu_s_direct,
            }
        return out

    def to_json(self) -> str:
        """:meth:`to_dict` as JSON (NaN written as null)."""

        def clean(x: Any) -> Any:
            if isinstance(x, float) and not math.isfinite(x):
                return None
            if isinstance(x, dict):
                return {k: clean(v) for k, v in x.items()}
            if isinstance(x, list | tuple):
                return [clean(v) for v in x]
            return x

        return json.dumps(clean(self.to_dict()), indent=2)

    def report(self) -> str:
        """Readable text report (parameters, statistics, correlations, bootstrap)."""
        lines = [
            "[[Exact-model fit of the spin-rig opening times]]",
            f"    data        = {self.settings.get('source', '')}",
            f"    runs        = {self.ndata} ({self.settings.get('selection', '')})",
            f"    model       = rig, {self.settings.get('torque_model')} friction, "
            f"W = {self.settings.get('weight')} N, constant spin",
            f"    solver      = {self.settings.get('solver')}",
            "[[Fit statistics]]",
            f"    # function evals   = {self.nfev}",
            f"    # data points      = {self.ndata}",
            f"    # variables        = {self.nvarys}",
            f"    chi-square         = {self.chisqr:.6g}"
            + ("  [s^2]" if self.sigma is None else f"  (sigma = {self.sigma:g} s)"),
            f"    reduced chi-square = {self.redchi:.6g}",
            f"    rms residual       = {self.rms:.4g} s",
            f"    success            = {self.success} ({self.message})",
        ]
        if self.censored_runs:
            lines.append(
                f"    censored runs      = {self.censored_runs} (model does not open within "
                f"t_max = {self.settings.get('t_max')} s; residual taken at t_max)"
            )
        lines.append("[[Variables]]")
        for k, v in self.values.items():
            u = self.units[k]
            if k in self.names:
                lo, hi = self.ci95[k]
                lines.append(
                    f"    {k:<15} = {v:.6g} +/- {self.stderr[k]:.3g} {u} "
                    f"(95% CI [{lo:.5g}, {hi:.5g}])"
                )
            else:
                lines.append(f"    {k:<15} = {v:.6g} {u} (fixed)")
        if self.nvarys > 1:
            lines.append("[[Correlations]]")
            for i in range(self.nvarys):
                for j in range(i + 1, self.nvarys):
                    lines.append(
                        f"    C({self.names[i]}, {self.names[j]}) = {self.correlation[i, j]:+.4f}"
                    )
        lines.append("[[Covariance]]")
        for i, k in enumerate(self.names):
            row = "  ".join(f"{c:.4e}" for c in self.covariance[i])
            lines.append(f"    {k:<15} {row}")
        if self.bootstrap is not None:
            b = self.bootstrap
            lines += [
                "[[Bootstrap (mu_s only; interpolated exact t_cr table)]]",
                f"    resamples          = {b.n_resamples} (seed {b.seed})",
                f"    {100 * b.confidence:.0f}% percentile CI = "
                f"[{b.interval[0]:.5g}, {b.interval[1]:.5g}]",
                f"    bootstrap std      = {b.std:.3g}",
                f"    table              = {b.table.mu_s.size} mu_s rows in "
                f"[{b.table.mu_s[0]:.4g}, {b.table.mu_s[-1]:.4g}] x {b.table.spin_rate.size} spins",
                f"    interpolation err  = {b.table.interpolation_error:.2e} s "
                f"({b.table.interpolation_rel_error:.1e} relative, at grid midpoints)",
            ]
            if b.at_grid_edge:
                lines.append(f"    WARNING: {b.at_grid_edge} resamples hit the table range")
        if self.thesis is not None:
            th = self.thesis
            lines += [
                "[[Chapter IV method on the same runs (Eqs. 95-96, linearised model)]]",
                f"    T2 = {th.t2:.6g} s^2  mu_bar = {th.mu_bar:.4f}  mu_s = {th.mu_s:.4f}",
                f"    direct fit t = T2 omega: T2 = {th.t2_direct:.6g}  "
                f"mu_s = {th.mu_s_direct:.4f}",
            ]
        lines.append("[[Runs]]")
        lines.append(f"    {'run':>4} {'omega_p':>9} {'t_meas':>8} {'t_model':>8} {'resid':>9}")
        for r, w, tm, tc in zip(self.run, self.spin_rate, self.measured, self.model, strict=True):
            lines.append(f"    {r:>4d} {w:>9.2f} {tm:>8.4f} {tc:>8.4f} {tc - tm:>+9.4f}")
        return "\n".join(lines)


def fit_exact(
    data: SpinRigData | None = None,
    *,
    fit: Sequence[str] = ("mu_s",),
    initial: dict[str, float] | None = None,
    bounds: dict[str, tuple[float, float]] | None = None,
    min_spin: float | None = None,
    theta0_deg: float = TABLE1["theta0_deg"],
    shear_constant: float = _S_TABLE1,
    weight: float = TABLE1["rig_weight"],
    torque_model: str = "thesis",
    sigma: float | None = None,
    t_max: float = 5.0,
    options: SolverOptions | None = None,
    bootstrap: int = 200,
    bootstrap_seed: int = 0,
    table_resolution: float = 6.0,
    table_halfwidth: float = 0.05,
    table_max_points: int = 121,
    table_verify: int = 12,
    model_options: dict[str, Any] | None = None,
) -> ExactFit:
    """Fit mu_s (and optionally theta_0, S) of the exact rig model to measured t_cr.

    Parameters
    ----------
    data : SpinRigData, optional
        Runs (default: thesis Appendix B); selected by :func:`select_runs`.
    fit : sequence of str
        Parameters to fit, from ``mu_s``, ``theta0_deg`` [deg], ``shear_constant``
        [N m s]; the others stay at the values given below.
    initial : dict, optional
        Starting values (defaults: :data:`PARAMETERS`).
    bounds : dict, optional
        (low, high) per parameter (defaults: :data:`PARAMETERS`).
    min_spin : float, optional
        Fit runs with omega_p >= min_spin [rad/s] instead of the starred runs.
    theta0_deg, shear_constant : float
        Fixed theta_0 [deg] and S [N m s] when not fitted (Table 1).
    weight : float
        Ball weight W [N] (Table 1: 0.07987).
    torque_model : {"thesis", "coulomb"}
        Friction law (Eq. 61, or exact Coulomb at the bottom contact).
    sigma : float, optional
        Measurement standard deviation of t_cr [s]; weights 1/sigma. None:
        unit weights, covariance scaled by the reduced chi-square.
    t_max : float
        Integration horizon [s]; also the model value of a run that does not open.
    options : SolverOptions, optional
    bootstrap : int
        Resamples of the mu_s bootstrap (0: none).
    bootstrap_seed : int
    table_resolution : float
        Grid points of the bootstrap t_cr table per ripple period (see notes).
    table_halfwidth : float
        The table spans mu_s (1 +- halfwidth) around the best value, or +- 6
        standard errors if that is wider.
    table_max_points : int
        Cap on the table's mu_s rows (>= 4).
    table_verify : int
        Grid midpoints at which the table is checked against exact runs.
    model_options : dict, optional
        Further fixed arguments of :func:`model_opening_times` (e.g.
        ``{"speed_law": "strengthening"}``).

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
    table spacing period / `table_resolution`, over the data's fastest run.
    """
    data = load_thesis_data() if data is None else data
    runs = select_runs(data, min_spin)
    names = tuple(dict.fromkeys(fit))
    for k in names:
        if k not in PARAMETERS:
            raise InputError("fit", f"{k!r}; allowed: {', '.join(PARAMETERS)}")
    if "mu_s" not in names:
        raise InputError("fit", "mu_s must be among the fitted parameters")
    if sigma is not None:
        check_range("sigma", sigma, 0.0, math.inf, lo_open=True, hi_open=True, unit="s")
    fixed = {
        "mu_s": PARAMETERS["mu_s"][1],
        "theta0_deg": theta0_deg,
        "shear_constant": shear_constant,
    }
    start = dict(fixed)
    start.update({k: PARAMETERS[k][1] for k in names if k != "theta0_deg"})
    if "theta0_deg" in names:
        start["theta0_deg"] = theta0_deg
    start.update(initial or {})
    bnd = {k: PARAMETERS[k][2] for k in names}
    bnd.update({k: v for k, v in (bounds or {}).items() if k in names})
    scale = np.array([PARAMETERS[k][3] for k in names])
    lo = np.array([bnd[k][0] for k in names]) / scale
    hi = np.array([bnd[k][1] for k in names]) / scale
    x0 = np.clip(np.array([start[k] for k in names]) / scale, lo, hi)
    w, t_meas = runs.spin_rate, runs.opening_time
    wt = 1.0 if sigma is None else 1.0 / sigma
    model_kw = {"weight": weight, "torque_model": torque_model, "t_max": t_max, "options": options}
    model_kw.update(model_options or {})

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
    ci95 = {k: (best[k] - tq * stderr[k], best[k] + tq * stderr[k]) for k in names}
    opts = options or SolverOptions()
    settings = {
        "source": runs.source or data.source,
        "selection": f"omega_p >= {min_spin:g} rad/s"
        if min_spin is not None
        else ("starred runs" if data.starred.any() else "all runs"),
        "weight": weight,
        "torque_model": torque_model,
        "t_max": t_max,
        "solver": f"{opts.method} rtol={opts.rtol:g} atol={opts.atol:g} "
        f"friction_width={opts.friction_width:g} formulation={opts.formulation}",
        "jacobian": f"central differences, relative step {_DIFF_STEP:g}",
    }
    boot = None
    if bootstrap > 0:
        mu = best["mu_s"]
        half = max(table_halfwidth * mu, 6.0 * stderr["mu_s"])
        ok = np.isfinite(t_best)
        period = float(np.min(math.pi * mu / (w[ok] * t_best[ok]))) if ok.any() else half
        n_rows = int(
            np.clip(math.ceil(2.0 * half * table_resolution / period) + 1, 4, table_max_points)
        )
        grid = np.linspace(max(mu - half, 1e-3), mu + half, n_rows)
        table = OpeningTimeTable.build(
            w,
            grid,
            theta0_deg=best["theta0_deg"],
            shear_constant=best["shear_constant"],
            verify=table_verify,
            **model_kw,
        )
        boot = bootstrap_mu_s(t_meas, table, n_resamples=bootstrap, seed=bootstrap_seed)
    thesis = thesis_least_squares(runs, theta0=math.radians(best["theta0_deg"]))
    return ExactFit(
        names=names,
        values=best,
        units={k: PARAMETERS[k][0] for k in best},
        stderr=stderr,
        ci95=ci95,
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
