"""The tasks of the validation study, one per chunk of the runner.

Module-level functions (a process pool pickles them, and the resume store keys each task
by its content, function included): one fit (:func:`fit_task`), one curve with its
convergence check (:func:`curve_task`), one side of a profile interval
(:func:`profile_task`), the release-phase scatter (:func:`phase_task`); and
:class:`Observations`, what every task of one study shares.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from ..solve import SolverOptions, convergence_checks, opening_times
from .candidates import CANDIDATES, Candidate
from .evaluate import ModelEvaluator
from .fit import Conditions, FitControls, fit_candidate, predict, profile_interval
from .floor import ReplicateFloor, lack_of_fit
from .goodness import goodness_summary
from .recommend import OUT_OF_BAND_SPLIT
from .results import CandidateFit, ModelResult
from .valley import valley_starts, with_flat_directions

__all__ = [
    "AllRuns",
    "Observations",
    "all_run_fit_task",
    "first_fit_task",
    "restart_fit_task",
    "settled_fit_task",
    "call",
    "cost_rank",
    "curve_task",
    "fit_task",
    "phase_task",
    "pick",
    "profile_task",
    "warm_up",
]

PHASES = 8

# --------------------------------------------------------------------------- tasks
# Module-level functions so that a process pool can run them.


def fit_task(
    name: str,
    selection: str,
    w: NDArray[np.float64],
    y: NDArray[np.float64],
    band: NDArray[np.str_],
    run: NDArray[np.int64],
    start: dict[str, float] | None,
    predict_w: NDArray[np.float64] | None,
    spin_sd: float,
    t_max: float,
    options: SolverOptions | None,
    noise: str = "band",
    conditions: list[Conditions] | None = None,
    predict_conditions: list[Conditions] | None = None,
) -> tuple[CandidateFit, NDArray[np.float64] | None]:
    cand = CANDIDATES[name]
    ev = ModelEvaluator(cand, t_max, options)
    fit = fit_candidate(
        cand,
        w,
        y,
        band=band,
        run=run,
        selection=selection,
        start=start,
        spin_sd=spin_sd,
        t_max=t_max,
        options=options,
        evaluator=ev,
        noise=noise,
        conditions=conditions,
    )
    pred = None
    if predict_w is not None:
        pred = predict(cand, fit.values, predict_w, evaluator=ev, conditions=predict_conditions)
    return fit, pred


class AllRuns(NamedTuple):
    """What the steps of one fit to all observations share: the observations
    (spins [rad/s], t_cr [s], bands, run numbers, per-observation settings) and the
    study's settings (spin SD [rad/s], t_max [s], solver options, noise model)."""

    w: NDArray[np.float64]
    y: NDArray[np.float64]
    band: NDArray[np.str_]
    run: NDArray[np.int64]
    spin_sd: float
    t_max: float
    options: SolverOptions | None
    noise: str = "band"
    conditions: list[Conditions] | None = None


def all_run_fit_task(name: str, data: AllRuns) -> tuple[CandidateFit, None]:
    """The fit of one candidate to all observations, the one both studies use: the fit
    from the default start (:func:`first_fit_task`), then the bounded multi-start along
    its flattest direction (:mod:`.valley`, :func:`restart_fit_task`), the lowest -log L
    kept, with its flat directions recorded (:func:`settled_fit_task`). The three steps
    in one task; a study with few fits runs them as tasks of their own (the same
    result: each step builds its own evaluator)."""
    best = first_fit_task(name, data)
    others = [restart_fit_task(name, start, data) for start in valley_starts(best)]
    return settled_fit_task(name, best, others, data)


def first_fit_task(name: str, data: AllRuns) -> CandidateFit:
    """Step 1 of :func:`all_run_fit_task`: the fit from the candidate's default start."""
    cand = CANDIDATES[name]
    return fit_candidate(cand, data.w, data.y, **_all_runs(cand, data))


def restart_fit_task(name: str, start: dict[str, float], data: AllRuns) -> CandidateFit:
    """Step 2 of :func:`all_run_fit_task`: one fit of the multi-start from `start`, without
    the covariance (only a winner needs it)."""
    cand = CANDIDATES[name]
    controls = FitControls(covariance=False)
    return fit_candidate(
        cand, data.w, data.y, start=start, controls=controls, **_all_runs(cand, data)
    )


def settled_fit_task(
    name: str, best: CandidateFit, others: list[CandidateFit], data: AllRuns
) -> tuple[CandidateFit, None]:
    """Step 3 of :func:`all_run_fit_task`: of the first fit `best` and the restarts
    `others` (in the order of their starts), the lowest -log L, a restart winning only by
    more than 1e-6; a winning restart is fitted again from its optimum with the
    covariance. The flat directions recorded."""
    winner = None
    for other in others:
        if other.nll < (winner or best).nll - 1e-6:
            winner = other
    if winner is not None:
        cand = CANDIDATES[name]
        best = fit_candidate(cand, data.w, data.y, start=winner.values, **_all_runs(cand, data))
    return replace(with_flat_directions(best), n_restarts=len(others)), None


def _all_runs(cand: Candidate, data: AllRuns) -> dict[str, Any]:
    """The keywords of :func:`~.fit.fit_candidate` for a fit to all runs, with an
    evaluator of its own (its cache of t_cr never shared between steps, so that a step's
    counters do not depend on which steps ran in its process before)."""
    return {
        "band": data.band,
        "run": data.run,
        "selection": "all",
        "spin_sd": data.spin_sd,
        "t_max": data.t_max,
        "options": data.options,
        "evaluator": ModelEvaluator(cand, data.t_max, data.options),
        "noise": data.noise,
        "conditions": data.conditions,
    }


def curve_task(
    name: str,
    values: dict[str, float],
    grid: NDArray[np.float64],
    run_w: NDArray[np.float64],
    run_t: NDArray[np.float64],
    t_max: float,
    options: SolverOptions | None,
    conditions: list[Conditions] | None = None,
) -> tuple[NDArray[np.float64], dict[str, Any]]:
    cand = CANDIDATES[name]
    ev = ModelEvaluator(cand, t_max, options)
    curve = ev.opening_times([values[k] for k in cand.params], grid)
    tol = wid = fam = 0.0
    n_bad = 0
    worst_w = math.nan
    conds = conditions or [()] * len(run_w)
    at_runs = [replace(cand, conditions=c) if c else cand for c in conds]
    checks = convergence_checks(
        [at.build(float(w), values, t_max) for at, w in zip(at_runs, run_w, strict=True)],
        options,
        opening_times_s=run_t,
    )
    for w, chk in zip(run_w, checks, strict=True):
        change = chk.largest_change
        if change > max(tol, wid, fam):
            worst_w = float(w)
        tol = max(tol, chk.tolerance_change)
        wid = max(wid, chk.width_change)
        fam = max(fam, chk.family_change)
        n_bad += int(not chk.converged)
    conv = {
        "n_runs": int(run_w.size),
        "max_tolerance_rel_change": tol,
        "max_width_rel_change": wid,
        "max_family_rel_change": fam,
        "max_rel_change": max(tol, wid, fam),
        "worst_spin_rate_rad_s": worst_w,
        "n_not_converged": n_bad,
        "threshold": 1e-3,
        "other_family": "linear",
    }
    return curve, conv


def profile_task(
    fit: CandidateFit,
    name: str,
    param: str,
    side: int,
    spin_sd: float,
    options: SolverOptions | None,
) -> tuple[str, int, float]:
    lo, hi = profile_interval(
        fit, CANDIDATES[name], param, spin_sd=spin_sd, options=options, sides=(side,)
    )
    return param, side, lo if side < 0 else hi


def phase_task(
    name: str,
    values: dict[str, float],
    spins: NDArray[np.float64],
    t_max: float,
    options: SolverOptions | None,
) -> dict[str, Any]:
    cand = CANDIDATES[name]
    phases = np.linspace(0.0, math.pi, PHASES, endpoint=False)
    cases = [
        cand.build(float(w), {**values, "release_phase": float(ph)}, t_max)
        for w in spins
        for ph in phases
    ]
    table = opening_times(cases, options)[0].reshape(len(spins), -1)
    sd = np.nanstd(table, axis=1, ddof=1)
    return {
        "model": name,
        "phases_rad": phases.tolist(),
        "spin_rate_rad_s": spins.tolist(),
        "t_cr_s": table.tolist(),
        "sd_over_phase_s": sd.tolist(),
        "note": "psi_0 uniform per run (switch thrown at an arbitrary instant): "
        "this SD is part of the replicate scatter the model itself predicts",
    }


# --------------------------------------------------------------------------- tasks


def cost_rank(cand: Candidate) -> tuple[bool, bool, int]:
    """Sort key of a candidate's fit cost: the exact Coulomb contact runs on the generic
    kernel (the slowest fit), then the slip-speed laws (long, curved likelihood valleys),
    then more parameters (fit times: ``docs/benchmarks.md``, history)."""
    return (cand.torque_model == "coulomb", cand.speed_law != "constant", cand.n_params)


def warm_up(options: SolverOptions | None = None) -> None:
    """Load the compiled integrators once in this process, so that the forked workers of
    both phases inherit them (instead of each loading them); also the experiment design's
    warm-up (its fits and surrogate run the same rig cases)."""
    from ..model.cases import rig_case

    # 100 rad/s: a short run "auto" gives the set-valued solver
    low = rig_case(spin_rate=100.0, mu_s=0.55, t_max=1e-2)
    opening_times([rig_case(spin_rate=300.0, mu_s=0.55), low], options)


def call(task: tuple[Any, ...]) -> Any:
    """Run one study task ``(function, *args)`` (module level: pools pickle it)."""
    fn, *args = task
    return fn(*args)


def _subset(mask: NDArray[np.bool_], *arrays: NDArray[Any]) -> list[NDArray[Any]]:
    return [a[mask] for a in arrays]


def _resid(pred: NDArray[np.float64], y: NDArray[np.float64], t_max: float) -> NDArray[np.float64]:
    return np.where(np.isfinite(pred), pred, t_max) - y


def _oob_rms(pred: NDArray[np.float64] | None, y: NDArray[np.float64], t_max: float) -> float:
    if pred is None or pred.size == 0:
        return math.nan
    r = np.where(np.isfinite(pred), pred, t_max) - y
    return float(np.sqrt(np.mean(r * r)))


@dataclass(frozen=True)
class Observations:
    """What every task of one study shares: the observations (spins w [rad/s], times y
    [s], run numbers, spin bands, the high half, the starred flags, per-run settings),
    the number of t_cr observations (the first `n_runs`; the rest are times to
    intermediate angles), the fit settings ``(spin_sd, t_max, options, noise)``, the
    curve's spin grid [rad/s], whether the starred runs are the high half, and each
    observation's replicate cluster."""

    w: NDArray[np.float64]
    y: NDArray[np.float64]
    run: NDArray[np.int64]
    band: NDArray[np.str_]
    high: NDArray[np.bool_]
    starred: NDArray[np.bool_]
    conds: list[Conditions] | None
    n_runs: int
    common: tuple[Any, ...]
    grid: NDArray[np.float64]
    same_split: bool
    cluster: NDArray[np.int64]

    def candidate_tasks(
        self, c: Candidate, fit: CandidateFit
    ) -> list[tuple[tuple[Any, ...], tuple[Any, Any, Any]]]:
        """Phase 2 of one candidate: its subset fits (starred runs, each half predicting
        the other) and its curve with the convergence check, as ``(task, tag)`` pairs."""
        w, high, starred, conds = self.w, self.high, self.starred, self.conds
        start = dict(fit.values)
        subsets = []
        if starred.any() and not self.same_split:
            subsets.append(("starred", starred, np.ones_like(high)))
        if high.any() and (~high).any():
            subsets.append((f"omega_p >= {OUT_OF_BAND_SPLIT:g}", high, ~high))
            subsets.append((f"omega_p < {OUT_OF_BAND_SPLIT:g}", ~high, high))
        out: list[tuple[tuple[Any, ...], tuple[Any, Any, Any]]] = []
        for label, m_fit, m_pred in subsets:
            if int(m_fit.sum()) < c.n_params + 2:
                continue
            ws, ys, bs, rs = _subset(m_fit, w, self.y, self.band, self.run)
            task = (fit_task, c.name, label, ws, ys, bs, rs, start, w[m_pred], *self.common)
            out.append(((*task, pick(conds, m_fit), pick(conds, m_pred)), (c.name, label, m_pred)))
        model_t = np.where(np.isfinite(fit.model), fit.model, np.nan)
        ok = np.isfinite(model_t) & (np.arange(w.size) < self.n_runs)  # the t_cr observations
        _, t_max, options, _ = self.common
        curve = (curve_task, c.name, start, self.grid, w[ok], model_t[ok], t_max, options)
        out.append(((*curve, pick(conds, ok)), (c.name, "curve", None)))
        return out

    def model_result(
        self, c: Candidate, fit: CandidateFit, sub: dict[str, Any], floor: ReplicateFloor
    ) -> ModelResult:
        """One candidate's result from its all-run `fit` and its phase-2 results `sub`
        (label -> ((fit, prediction), prediction mask))."""
        y, t_max = self.y, self.common[1]
        sub = dict(sub)
        curve, conv = sub.pop("curve")[0]
        kw: dict[str, Any] = {"out_of_band_rms": {}}
        for label, ((part, pred), m_pred) in sub.items():
            if label == "starred":
                kw["starred"] = part
                kw["out_of_band_rms"]["starred->all"] = _oob_rms(pred, y[m_pred], t_max)
            elif label.startswith("omega_p >="):
                kw["high"] = part
                kw["out_of_band_rms"]["high->low"] = _oob_rms(pred, y[m_pred], t_max)
                if self.same_split:  # the starred fit; its rms on all runs
                    kw["starred"] = part
                    r_all = np.concatenate([part.residuals, _resid(pred, y[m_pred], t_max)])
                    kw["out_of_band_rms"]["starred->all"] = float(np.sqrt(np.mean(r_all**2)))
            else:
                kw["low"] = part
                kw["out_of_band_rms"]["low->high"] = _oob_rms(pred, y[m_pred], t_max)
        return ModelResult(
            c.name,
            fit,
            curve_spin=self.grid,
            curve_t=curve,
            convergence=conv,
            lack_of_fit=lack_of_fit(floor, fit.residuals[: self.n_runs], c.n_params),
            goodness=goodness_summary(floor, _first_runs(fit, self.n_runs)),
            **kw,
        )


def pick(conds: list[Conditions] | None, mask: NDArray[np.bool_]) -> list[Conditions] | None:
    return None if conds is None else [c for c, m in zip(conds, mask, strict=True) if m]


def _first_runs(fit: CandidateFit, n: int) -> CandidateFit:
    """The fit restricted to its first `n` observations (the runs' t_cr)."""
    if fit.ndata == n:
        return fit
    cut = {
        k: getattr(fit, k)[:n]
        for k in ("spin_rate", "measured", "model", "slope", "sd", "band", "run")
    }
    group = None if fit.noise_group is None else fit.noise_group[:n]
    return replace(fit, noise_group=group, **cut)
