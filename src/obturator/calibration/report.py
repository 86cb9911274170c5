"""Reporting an exact-model fit: a JSON-ready dict and a readable text report.

The fit result (:class:`~.exact.ExactFit`) holds numbers only; its text forms
are made here (as lmfit keeps ``fit_report`` apart from ``ModelResult``).
"""

from __future__ import annotations

import json
import math
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from .exact import ExactFit

__all__ = ["fit_to_dict", "fit_to_json", "format_fit"]


def fit_to_dict(fit: ExactFit) -> dict[str, Any]:
    """JSON-ready summary of an :class:`~.exact.ExactFit`."""
    out: dict[str, Any] = {
        "parameters": {k: p.to_dict() for k, p in fit.params.items()},
        "covariance": fit.covariance.tolist(),
        "correlation": fit.correlation.tolist(),
        "chisqr": fit.chisqr,
        "redchi": fit.redchi,
        "ndata": fit.ndata,
        "nvarys": fit.nvarys,
        "rms_residual_s": fit.rms,
        "censored_runs": fit.censored_runs,
        "sigma_s": fit.sigma,
        "success": fit.success,
        "message": fit.message,
        "nfev": fit.nfev,
        "runs": [
            {
                "run": int(r),
                "spin_rate_rad_s": float(w),
                "t_measured_s": float(tm),
                "t_model_s": None if not math.isfinite(tc) else float(tc),
            }
            for r, w, tm, tc in zip(fit.run, fit.spin_rate, fit.measured, fit.model, strict=True)
        ],
        "settings": fit.settings,
    }
    if fit.bootstrap is not None:
        b = fit.bootstrap
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
    if fit.thesis is not None:
        out["thesis_method"] = {
            "T2": fit.thesis.t2,
            "mu_bar": fit.thesis.mu_bar,
            "mu_s": fit.thesis.mu_s,
            "T2_direct": fit.thesis.t2_direct,
            "mu_s_direct": fit.thesis.mu_s_direct,
        }
    return out


def fit_to_json(fit: ExactFit) -> str:
    """:func:`fit_to_dict` as JSON (NaN written as null)."""

    def clean(x: Any) -> Any:
        if isinstance(x, float) and not math.isfinite(x):
            return None
        if isinstance(x, dict):
            return {k: clean(v) for k, v in x.items()}
        if isinstance(x, list | tuple):
            return [clean(v) for v in x]
        return x

    return json.dumps(clean(fit_to_dict(fit)), indent=2)


def format_fit(fit: ExactFit) -> str:
    """Readable text report of an :class:`~.exact.ExactFit` (lmfit's ``fit_report``):
    parameters, statistics, correlations, covariance, bootstrap, runs."""
    lines = [
        "[[Exact-model fit of the spin-rig opening times]]",
        f"    data        = {fit.settings.get('source', '')}",
        f"    runs        = {fit.ndata} ({fit.settings.get('selection', '')})",
        f"    model       = rig, {fit.settings.get('torque_model')} friction, "
        f"W = {fit.settings.get('weight')} N, constant spin"
        + (
            f" (runs' own {', '.join(fit.settings['run_settings'])} from the data file)"
            if fit.settings.get("run_settings")
            else ""
        ),
        f"    solver      = {fit.settings.get('solver')}",
        "[[Fit statistics]]",
        f"    # function evals   = {fit.nfev}",
        f"    # data points      = {fit.ndata}",
        f"    # variables        = {fit.nvarys}",
        f"    chi-square         = {fit.chisqr:.6g}"
        + ("  [s^2]" if fit.sigma is None else f"  (sigma = {fit.sigma:g} s)"),
        f"    reduced chi-square = {fit.redchi:.6g}",
        f"    rms residual       = {fit.rms:.4g} s",
        f"    success            = {fit.success} ({fit.message})",
    ]
    if fit.censored_runs:
        lines.append(
            f"    censored runs      = {fit.censored_runs} (model does not open within "
            f"t_max = {fit.settings.get('t_max')} s; residual taken at t_max)"
        )
    lines.append("[[Variables]]")
    for k, par in fit.params.items():
        v, u = par.value, ("" if par.unit == "1" else f" {par.unit}")  # "1": a pure number
        if par.vary:
            lo, hi = par.ci95
            lines.append(
                f"    {k:<15} = {v:.6g} +/- {par.stderr:.3g}{u} (95% CI [{lo:.5g}, {hi:.5g}])"
            )
        else:
            lines.append(f"    {k:<15} = {v:.6g}{u} (fixed)")
    if fit.nvarys > 1:
        lines.append("[[Correlations]]")
        for i in range(fit.nvarys):
            for j in range(i + 1, fit.nvarys):
                lines.append(
                    f"    C({fit.names[i]}, {fit.names[j]}) = {fit.correlation[i, j]:+.4f}"
                )
    lines.append("[[Covariance]]")
    for i, k in enumerate(fit.names):
        row = "  ".join(f"{c:.4e}" for c in fit.covariance[i])
        lines.append(f"    {k:<15} {row}")
    if fit.bootstrap is not None:
        b = fit.bootstrap
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
    if fit.thesis is not None:
        th = fit.thesis
        lines += [
            "[[Chapter IV method on the same runs (Eqs. 95-96, linearised model)]]",
            f"    T2 = {th.t2:.6g} s^2  mu_bar = {th.mu_bar:.4f}  mu_s = {th.mu_s:.4f}",
            f"    direct fit t = T2 omega: T2 = {th.t2_direct:.6g}  mu_s = {th.mu_s_direct:.4f}",
        ]
    lines.append("[[Runs]]")
    lines.append(f"    {'run':>4} {'omega_p':>9} {'t_meas':>8} {'t_model':>8} {'resid':>9}")
    for r, w, tm, tc in zip(fit.run, fit.spin_rate, fit.measured, fit.model, strict=True):
        lines.append(f"    {r:>4d} {w:>9.2f} {tm:>8.4f} {tc:>8.4f} {tc - tm:>+9.4f}")
    return "\n".join(lines)
