"""Model discrimination against all spin-rig runs: candidates, fits, ranking.

Each candidate is a named set of fitted parameters of the exact rig model
(:func:`obturator.calibration.fit_exact`) plus fixed model options:

========================  ==================================================
``thesis``                mu_s; theta_0 = 87.25 deg (Table 1)
``theta0``                mu_s, theta_0 (the thesis says +-1 deg; its laser
                          alignment may be worse)
``release``               mu_s, theta_dot_0 (plunger/holding-jet kick)
``phase``                 mu_s, psi_0 (release azimuth; gravity breaks the
                          symmetry about Z)
``strengthening``         mu_s, r, v_s: mu(v) from r mu_s at rest to mu_s
``weakening``             mu_s, r, v_s: mu(v) from mu_s at rest to r mu_s
``coulomb-patch``         mu_s, patch radius: exact contact with pivoting
``theta0+strengthening``  the two strongest single mechanisms together
========================  ==================================================

Fits are least squares on t_cr with runs that do not open within the horizon
right-censored (residual at t_max). AIC = n ln(RSS/n) + 2k and
BIC = n ln(RSS/n) + k ln n (Gaussian errors of one variance). Out-of-band
prediction: fit on runs >= 200 rad/s and predict those below, and the reverse.
Spin-rate fluctuation (+-1.75 rad/s regulation) is not a fitted mechanism: its
effect is reported as the rms of (dt_cr/d omega_p) sigma_omega over the runs,
with sigma_omega = 1.75/sqrt(3) rad/s (uniform within the regulation).
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..calibration import SpinRigData, fit_exact, model_opening_times
from ..errors import InputError
from ..params import FIT_PARAMS
from .floor import BANDS, replicate_floor

__all__ = ["CANDIDATES", "Candidate", "ModelResult", "ValidationStudy", "run_validation"]

#: +-1.75 rad/s regulation as a uniform distribution: its standard deviation [rad/s].
SPIN_SD = 1.75 / math.sqrt(3.0)
#: Band split of the out-of-band prediction [rad/s].
SPLIT = 200.0


@dataclass(frozen=True)
class Candidate:
    """One model: fitted parameter names, fixed model options, starting values."""

    name: str
    fit: tuple[str, ...]
    options: dict[str, Any] = field(default_factory=dict)
    initial: dict[str, float] = field(default_factory=dict)


CANDIDATES: dict[str, Candidate] = {
    c.name: c
    for c in (
        Candidate("thesis", ("mu_s",)),
        Candidate("theta0", ("mu_s", "theta0_deg"), initial={"theta0_deg": 85.0}),
        Candidate("release", ("mu_s", "theta_dot0"), initial={"theta_dot0": 0.5}),
        Candidate("phase", ("mu_s", "release_phase"), initial={"release_phase": 1.0}),
        Candidate(
            "strengthening",
            ("mu_s", "speed_ratio", "slip_speed"),
            {"speed_law": "strengthening"},
        ),
        Candidate("weakening", ("mu_s", "speed_ratio", "slip_speed"), {"speed_law": "weakening"}),
        Candidate("coulomb-patch", ("mu_s", "patch_radius"), {"torque_model": "coulomb"}),
        Candidate(
            "theta0+strengthening",
            ("mu_s", "theta0_deg", "speed_ratio", "slip_speed"),
            {"speed_law": "strengthening"},
            {"theta0_deg": 85.0},
        ),
    )
}


@dataclass(frozen=True)
class ModelResult:
    """One candidate fitted to all runs, with its out-of-band predictions."""

    name: str
    params: dict[str, dict[str, float | None]]
    rms_all_s: float
    rms_by_band_s: dict[str, float | None]
    aic: float
    bic: float
    out_of_band_rms_s: dict[str, float | None]
    censored_runs: list[int]
    n_params: int

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready (the schema of ``obturator validate --json``)."""
        return {
            "name": self.name,
            "params": self.params,
            "rms_all_s": self.rms_all_s,
            "rms_by_band_s": self.rms_by_band_s,
            "aic": self.aic,
            "bic": self.bic,
            "out_of_band_rms_s": self.out_of_band_rms_s,
            "censored_runs": self.censored_runs,
            "n_params": self.n_params,
        }


@dataclass(frozen=True)
class ValidationStudy:
    """Floor, ranked model results and the spin-fluctuation contribution."""

    floor: dict[str, Any]
    models: list[ModelResult]
    spin_fluctuation_rms_s: float | None

    def to_dict(self) -> dict[str, Any]:
        return {
            "floor_rms_s": self.floor["floor_rms_s"],
            "floor_rms_by_band_s": self.floor["floor_rms_by_band_s"],
            "floor": self.floor,
            "spin_fluctuation_rms_s": self.spin_fluctuation_rms_s,
            "models": [m.to_dict() for m in self.models],
        }

    def table(self) -> str:
        """Ranked text table (by AIC)."""
        bands = [b[0] for b in BANDS]
        head = f"{'model':<22} {'k':>2} {'rms all':>8} " + " ".join(f"{b:>8}" for b in bands)
        head += f" {'AIC':>8} {'BIC':>8} {'fit>=200->lo':>12} {'fit<200->hi':>11}"
        lines = [head]

        def f(x: float | None) -> str:
            return "-" if x is None else f"{x:.4f}"

        for m in self.models:
            lines.append(
                f"{m.name:<22} {m.n_params:>2} {m.rms_all_s:>8.4f} "
                + " ".join(f"{f(m.rms_by_band_s[b]):>8}" for b in bands)
                + f" {m.aic:>8.1f} {m.bic:>8.1f} {f(m.out_of_band_rms_s['high_to_low']):>12}"
                + f" {f(m.out_of_band_rms_s['low_to_high']):>11}"
            )
        fl = self.floor
        lines.append(
            f"{'replicate floor':<22} {'':>2} {f(fl['floor_rms_s']):>8} "
            + " ".join(f"{f(fl['floor_rms_by_band_s'][b]):>8}" for b in bands)
            + f"   (pooled SD, df {fl['df']}, {fl['n_clusters']} clusters)"
        )
        return "\n".join(lines)


def _rms(r: np.ndarray) -> float | None:
    return float(np.sqrt(np.mean(r**2))) if r.size else None


def _predict(fit: Any, spins: np.ndarray, cand: Candidate, t_max: float) -> np.ndarray:
    names = set(FIT_PARAMS)
    kw = {k: v for k, v in fit.values.items() if k in names}
    t = model_opening_times(spins, **kw, t_max=t_max, **cand.options)
    return np.where(np.isfinite(t), t, t_max)


def _fit(cand: Candidate, data: SpinRigData, t_max: float) -> Any:
    return fit_exact(
        data,
        fit=cand.fit,
        initial=cand.initial,
        min_spin=0.0,
        t_max=t_max,
        bootstrap=0,
        **cand.options,
    )


def _fit_candidate(cand: Candidate, data: SpinRigData, t_max: float) -> ModelResult:
    """Fit one candidate to all runs and predict across the 200 rad/s split."""
    w, t = data.spin_rate, data.opening_time
    hi_mask = w >= SPLIT
    fit = _fit(cand, data, t_max)
    r = fit.residuals
    n, k = r.size, len(cand.fit)
    rss = float(r @ r)
    by_band = {}
    for band, lo, hi in BANDS:
        sel = (fit.spin_rate >= lo) & (fit.spin_rate < hi)
        by_band[band] = _rms(r[sel])
    oob: dict[str, float | None] = {"high_to_low": None, "low_to_high": None}
    if hi_mask.sum() >= 2 and (~hi_mask).sum() >= 2:
        f_hi = _fit(cand, data.select(hi_mask), t_max)
        oob["high_to_low"] = _rms(_predict(f_hi, w[~hi_mask], cand, t_max) - t[~hi_mask])
        f_lo = _fit(cand, data.select(~hi_mask), t_max)
        oob["low_to_high"] = _rms(_predict(f_lo, w[hi_mask], cand, t_max) - t[hi_mask])
    params = {
        p: {
            "value": fit.values[p],
            "stderr": fit.stderr.get(p),
            "ci95": list(fit.ci95[p]),
            "unit": FIT_PARAMS[p].unit,
        }
        for p in cand.fit
    }
    return ModelResult(
        cand.name,
        params,
        float(np.sqrt(rss / n)),
        by_band,
        n * math.log(rss / n) + 2 * k,
        n * math.log(rss / n) + k * math.log(n),
        oob,
        fit.censored_runs,
        k,
    )


def run_validation(
    data: SpinRigData,
    models: Sequence[str] = tuple(CANDIDATES),
    *,
    t_max: float = 10.0,
    progress: Callable[[str], None] | None = None,
    workers: int = 1,
) -> ValidationStudy:
    """Fit every candidate to all runs, predict across the 200 rad/s split, rank by AIC.

    Parameters
    ----------
    data : SpinRigData
        The runs (all are used; none is dropped).
    models : sequence of str
        Names from :data:`CANDIDATES`.
    t_max : float
        Horizon [s]; a run not opened by then is right-censored.
    progress : callable, optional
        Called with each candidate's name (before its fit, or as it is collected).
    workers : int
        Candidates fitted in parallel processes (1: in this process).
    """
    unknown = [m for m in models if m not in CANDIDATES]
    if unknown or not models:
        raise InputError("models", f"{unknown or '[]'}; allowed: {', '.join(CANDIDATES)}")
    w = data.spin_rate
    floor = replicate_floor(w, data.opening_time)
    jobs = [(CANDIDATES[name], data, t_max) for name in models]
    if workers > 1 and len(jobs) > 1:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        ctx = multiprocessing.get_context("spawn")
        from ..sweeps.spec import _die_with_parent

        with ProcessPoolExecutor(
            min(workers, len(jobs)),
            mp_context=ctx,
            initializer=_die_with_parent,
            initargs=(os.getpid(),),
        ) as pool:
            futures = [pool.submit(_fit_candidate, *job) for job in jobs]
            results = []
            for name, fut in zip(models, futures, strict=True):
                if progress:
                    progress(name)
                results.append(fut.result())
    else:
        results = []
        for job in jobs:
            if progress:
                progress(job[0].name)
            results.append(_fit_candidate(*job))
    results.sort(key=lambda m: m.aic)
    best = CANDIDATES[results[0].name]
    spin_sd = _spin_fluctuation(results[0], best, w, t_max)
    return ValidationStudy(floor.to_dict(), results, spin_sd)


def _spin_fluctuation(res: ModelResult, cand: Candidate, w: np.ndarray, t_max: float) -> float:
    """rms over the runs of (dt_cr/d omega_p) SPIN_SD for the best model [s]."""
    kw = {p: v["value"] for p, v in res.params.items()}
    h = 0.5
    up = model_opening_times(w + h, **kw, t_max=t_max, **cand.options)
    dn = model_opening_times(w - h, **kw, t_max=t_max, **cand.options)
    slope = (up - dn) / (2 * h)
    ok = np.isfinite(slope)
    return float(np.sqrt(np.mean((slope[ok] * SPIN_SD) ** 2))) if ok.any() else math.nan
