"""The whole validation study: floor, fits, out-of-band prediction, ranking (issue 9).

:func:`run_validation` runs, for every candidate,

1. the fit to all runs (ranked by AIC);
2. the fit to the starred runs (the thesis's selection) and its rms on all runs;
3. out-of-band prediction: a fit to the runs whose cluster-mean spin is
   >= 200 rad/s, predicting the runs below, and the reverse (the split is by
   cluster mean, as the bands of the floor, so the replicate cluster at
   199.4 rad/s is not cut in two);
4. the t_cr(omega_p) curve of the all-run fit and a convergence check
   (:func:`obturator.solve.convergence_check`: tolerances / 10, width / 10
   and another regularisation family) of its prediction at every run;

then profile-likelihood intervals for the recommended model's parameters and
the spread of its t_cr over the release phase psi_0.

Work is spread over the runner's processes (:class:`obturator.runs.Runner`; each task is one fit,
one curve or one profile side), each with its own t_cr cache; subset fits start
from the all-run fit. A runner with a store keeps every finished task (keyed by its
content, stored pickled) so that an interrupted study resumes where it stopped.

Recommendation rule: :mod:`obturator.validation.recommend`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import replace
from functools import partial
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .. import __version__
from ..calibration.data import SpinRigData, load_thesis_data
from ..errors import InputError, check_range
from ..runs import Runner, study_digest
from ..solve import SolverOptions, convergence_checks, opening_times
from ..vocab import NOISE_MODELS, check_choice
from .candidates import CANDIDATES, Candidate, get_candidates
from .evaluate import DEFAULT_T_MAX, VALIDATION_OPTIONS, ModelEvaluator
from .fit import Conditions, fit_candidate, predict, profile_interval
from .floor import DEFAULT_CLUSTER_GAP, ReplicateFloor, band_of, lack_of_fit, replicate_floor
from .goodness import goodness_summary
from .likelihood import SPIN_SD
from .recommend import OUT_OF_BAND_SPLIT, model_aic, recommend
from .results import CandidateFit, ModelResult, ValidationResult

__all__ = ["OUT_OF_BAND_SPLIT", "recommend", "run_validation"]

_CURVE_POINTS = 48
_PHASES = 8


# --------------------------------------------------------------------------- tasks
# Module-level functions so that a process pool can run them.


def _fit_task(
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


def _curve_task(
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
        change = max(chk.tolerance_change, chk.width_change, chk.family_change)
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


def _profile_task(
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


def _phase_task(
    name: str,
    values: dict[str, float],
    spins: NDArray[np.float64],
    t_max: float,
    options: SolverOptions | None,
) -> dict[str, Any]:
    cand = CANDIDATES[name]
    phases = np.linspace(0.0, math.pi, _PHASES, endpoint=False)
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


def _cost_rank(cand: Candidate) -> tuple[bool, bool, int]:
    """Sort key of a candidate's fit cost: the exact Coulomb contact and the slip-speed
    laws run on the generic kernel (no Radau IIA lanes; measured on the thesis data the
    Coulomb fits took 4-10 times a thesis-kernel fit), then more parameters."""
    return (cand.torque_model == "coulomb", cand.speed_law != "constant", cand.n_params)


def _warm(options: SolverOptions) -> None:
    """Load the compiled integrators once in this process, so that the forked workers of
    both phases inherit them (instead of each loading them)."""
    from ..model.cases import rig_case

    opening_times([rig_case(spin_rate=300.0, mu_s=0.55)], options)


def _call(task: tuple[Any, ...]) -> Any:
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


def run_validation(
    data: SpinRigData | None = None,
    *,
    models: Sequence[str] | str | None = None,
    runner: Runner | None = None,
    t_max: float = DEFAULT_T_MAX,
    spin_sd: float = SPIN_SD,
    gap: float = DEFAULT_CLUSTER_GAP,
    options: SolverOptions | None = None,
    profile: bool | str = True,
    curve_points: int = _CURVE_POINTS,
    noise: str = "band",
) -> ValidationResult:
    """Run the validation study (see the module notes).

    Parameters
    ----------
    data : SpinRigData, optional
        Runs (default: the 54 runs of thesis Appendix B).
    models : sequence of str or str, optional
        Candidate names (default :data:`~.candidates.DEFAULT_MODELS`).
    runner : Runner, optional
        Where the fits, profiles and curves run (:class:`obturator.runs.Runner`; default
        two worker processes, no progress display). Each task (one fit, one curve or
        one profile side) is one chunk. With a ``store``, the study opens it under its
        digest and finished tasks are kept there (the caller removes it with
        :meth:`~obturator.runs.Runner.write_outputs` once its outputs are written).
    t_max : float
        Horizon [s]; runs not opened by then are censored.
    spin_sd : float
        Spin error SD [rad/s] of the error-in-variables term (0: off).
    gap : float
        Clustering gap of the replicate floor [rad/s].
    options : SolverOptions, optional
        Solver settings (default :data:`~.evaluate.VALIDATION_OPTIONS`).
    profile : bool or {"recommended", "all", "none"}
        Profile-likelihood intervals for the recommended model (True, the default),
        for every candidate (``"all"``: two one-sided profile searches per parameter,
        about 2-3 times the study's time), or none (False: Wald intervals).
    curve_points : int
        Points of each model's t_cr(omega_p) curve.
    noise : {"band", "pooled"}
        Run-to-run noise of the likelihood: one sigma per spin band, fitted with
        the model (default), or one pooled sigma (:mod:`.likelihood`).

    Returns
    -------
    ValidationResult
    """
    t_start = time.perf_counter()
    options = options or VALIDATION_OPTIONS
    data = load_thesis_data() if data is None else data
    cands = get_candidates(models)
    runner = runner or Runner(workers=2)
    jobs = runner.n_workers
    if isinstance(profile, str):
        if profile not in ("recommended", "all", "none"):
            raise InputError("profile", f"{profile!r}; allowed: recommended, all, none")
        profile_all, profile = profile == "all", profile != "none"
    else:
        profile_all = False
    check_range("curve_points", curve_points, 2, 10_000)
    check_choice("noise", noise, NOISE_MODELS)
    w, y, run = data.spin_rate, data.opening_time, data.run
    # runs with another ball or load (a data file's columns) are no replicates; a
    # theta_0 read per run varies like the spin within its band and does not split
    settings = [
        tuple(kv for kv in r if kv[0] in ("hole_radius", "density", "ball_mass"))
        for r in data.run_settings()
    ]
    floor: ReplicateFloor = replicate_floor(
        w, y, gap=gap, groups=settings if any(settings) else None
    )
    mean_w = floor.cluster_mean_spin()
    band = band_of(mean_w)
    high = mean_w >= OUT_OF_BAND_SPLIT
    n_runs = len(w)
    starred = data.starred
    # a data file's own settings per run, and its times to intermediate angles as
    # further observations of the same runs (the floor and its clusters stay t_cr's)
    w, y, run, band, high, starred, conds = _observations(data, band, high)
    if len(w) < 5:
        raise InputError("data", f"{len(w)} runs; the study needs at least 5")
    common = (spin_sd, t_max, options, noise)
    if runner.sidecar is None:  # else a study that holds this one (reproduce) keeps the fits
        runner.open(
            study_digest(
                {
                    "study": "validate",
                    "version": __version__,
                    "data": data,
                    "models": [c.name for c in cands],
                    "settings": [*common, gap, profile, profile_all, curve_points],
                }
            )
        )
    grid = np.geomspace(0.9 * float(w.min()), 1.05 * float(w.max()), int(curve_points))

    # on the thesis data the starred runs are exactly the high half: fit once
    same_split = bool(np.array_equal(starred, high))
    # phase 1: every all-run fit
    timings: dict[str, float] = {}
    # costliest first, so that the last fit to end is not a long one started late
    order = sorted(range(len(cands)), key=lambda i: _cost_rank(cands[i]), reverse=True)
    fitted_ordered = runner.map(
        _call,
        [
            (_fit_task, cands[i].name, "all", w, y, band, run, None, None, *common, conds)
            for i in order
        ],
        label="validate: all-run fits",
        unit="fits",
        chunk_size=1,
        probe_first=False,
        warm=partial(_warm, options),
        pickled=True,
    )
    fits = {cands[i].name: res[0] for i, res in zip(order, fitted_ordered, strict=True)}
    timings["all_run_fits"] = time.perf_counter() - t_start
    # the ranking needs the all-run fits only: the recommended model is known now, and
    # its profile intervals run alongside phase 2
    prelim = sorted((ModelResult(c.name, fits[c.name]) for c in cands), key=model_aic)
    rec_name, why = recommend(prelim)
    rec_fit = fits[rec_name]
    # phase 2: profile sides (longest first), subset fits, curves, checks
    tasks: list[tuple[Any, ...]] = []
    tags: list[tuple[Any, Any, Any]] = []
    profiled = [c.name for c in cands] if profile_all else [rec_name] if profile else []
    for pname in profiled:
        for k in fits[pname].params:
            for side in (-1, 1):
                tasks.append((_profile_task, fits[pname], pname, k, side, spin_sd, options))
                tags.append(("profile", (pname, k), side))
    centres = np.array(sorted({round(float(x), 6) for x in mean_w}))
    tasks.append((_phase_task, rec_name, dict(rec_fit.values), centres, t_max, options))
    tags.append(("phase", "", None))
    for c in sorted(cands, key=_cost_rank, reverse=True):
        f = fits[c.name]
        start = dict(f.values)
        subsets = []
        if starred.any() and not same_split:
            subsets.append(("starred", starred, np.ones_like(high)))
        if high.any() and (~high).any():
            subsets.append((f"omega_p >= {OUT_OF_BAND_SPLIT:g}", high, ~high))
            subsets.append((f"omega_p < {OUT_OF_BAND_SPLIT:g}", ~high, high))
        for label, m_fit, m_pred in subsets:
            if int(m_fit.sum()) < c.n_params + 2:
                continue
            ws, ys, bs, rs = _subset(m_fit, w, y, band, run)
            c_fit, c_pred = _pick(conds, m_fit), _pick(conds, m_pred)
            tasks.append(
                (_fit_task, c.name, label, ws, ys, bs, rs, start, w[m_pred], *common, c_fit, c_pred)
            )
            tags.append((c.name, label, m_pred))
        model_t = np.where(np.isfinite(f.model), f.model, np.nan)
        ok = np.isfinite(model_t) & (np.arange(w.size) < n_runs)  # the t_cr observations
        tasks.append(
            (_curve_task, c.name, start, grid, w[ok], model_t[ok], t_max, options, _pick(conds, ok))
        )
        tags.append((c.name, "curve", None))
    done = runner.map(
        _call,
        tasks,
        label="validate: profiles, subset fits, curves",
        unit="tasks",
        chunk_size=1,
        probe_first=False,
        warm=partial(_warm, options),
        pickled=True,
    )
    sub: dict[str, dict[str, Any]] = {c.name: {} for c in cands}
    prof: dict[str, dict[str, dict[int, float]]] = {}
    phase: dict[str, Any] = {}
    for (name, label, m_pred), res in zip(tags, done, strict=True):
        if name == "profile":
            pname, k = label
            prof.setdefault(pname, {}).setdefault(k, {})[int(m_pred)] = res[2]
        elif name == "phase":
            phase = res
        else:
            sub[name][label] = (res, m_pred)
    timings["subset_fits_curves_checks_profiles"] = (
        time.perf_counter() - t_start - timings["all_run_fits"]
    )
    results = []
    for c in cands:
        s = sub[c.name]
        curve, conv = s.pop("curve")[0]
        kw: dict[str, Any] = {"out_of_band_rms": {}}
        for label, ((fit, pred), m_pred) in s.items():
            if label == "starred":
                kw["starred"] = fit
                kw["out_of_band_rms"]["starred->all"] = _oob_rms(pred, y[m_pred], t_max)
            elif label.startswith("omega_p >="):
                kw["high"] = fit
                kw["out_of_band_rms"]["high->low"] = _oob_rms(pred, y[m_pred], t_max)
                if same_split:  # the starred fit; its rms on all runs
                    kw["starred"] = fit
                    r_all = np.concatenate([fit.residuals, _resid(pred, y[m_pred], t_max)])
                    kw["out_of_band_rms"]["starred->all"] = float(np.sqrt(np.mean(r_all**2)))
            else:
                kw["low"] = fit
                kw["out_of_band_rms"]["low->high"] = _oob_rms(pred, y[m_pred], t_max)
        results.append(
            ModelResult(
                c.name,
                fits[c.name],
                curve_spin=grid,
                curve_t=curve,
                convergence=conv,
                lack_of_fit=lack_of_fit(floor, fits[c.name].residuals[:n_runs], c.n_params),
                goodness=goodness_summary(floor, _first_runs(fits[c.name], n_runs)),
                **kw,
            )
        )
    results.sort(key=model_aic)
    rec_name, why = recommend(results)  # same choice, now with out-of-band numbers
    for pname, pk in prof.items():
        f = fits[pname]
        ci = {**f.ci95, **{k: (v[-1], v[1]) for k, v in pk.items()}}
        method = {**f.ci_method, **{k: "profile" for k in pk}}
        new_fit = _replace_ci(f, ci, method)
        results = [_replace_model_fit(m, new_fit) if m.name == pname else m for m in results]
    opts = options
    settings = {
        "source": data.source,
        "n_runs": n_runs,
        "n_angle_observations": int(len(w) - n_runs),
        "t_max_s": t_max,
        "spin_sd_rad_s": spin_sd,
        "cluster_gap_rad_s": gap,
        "out_of_band_split_rad_s": OUT_OF_BAND_SPLIT,
        "jobs": jobs,
        "profile": "all" if profile_all else "recommended" if profile else "none",
        "solver": f"{opts.method} rtol={opts.rtol:g} atol={opts.atol:g} "
        f"friction_width={opts.friction_width:g} family={opts.friction_family}",
        "noise": noise,
        "likelihood": (
            "Gaussian, one sigma per spin band fitted"
            if noise == "band"
            else "Gaussian, one pooled sigma fitted"
        )
        + ", + (dt/domega sigma_w)^2 error-in-variables; "
        "runs not opened by t_max censored (survival term)",
        "ranking": "AIC of the all-run fit",
        "starred_runs_are_high_half": same_split,
        "timings_s": timings,
    }
    return ValidationResult(
        floor=floor,
        models=results,
        recommended=rec_name,
        recommendation=why,
        settings=settings,
        elapsed_s=time.perf_counter() - t_start,
        phase_scatter=phase,
    )


def _pick(conds: list[Conditions] | None, mask: NDArray[np.bool_]) -> list[Conditions] | None:
    return None if conds is None else [c for c, m in zip(conds, mask, strict=True) if m]


def _observations(
    data: SpinRigData, band: NDArray[np.str_], high: NDArray[np.bool_]
) -> tuple[Any, ...]:
    """Spins, times, runs, bands, halves, starred flags and per-run settings of every
    observation: the runs' t_cr, then each time to an intermediate angle (event at
    theta_measured; same run, band and half). Settings None where all are Table 1."""
    w, y, run, starred = data.spin_rate, data.opening_time, data.run, data.starred
    settings = data.run_settings()
    measured = ("t_measured", "theta_measured_deg")
    conds = [tuple(kv for kv in s if kv[0] not in measured) for s in settings]
    angle = data.settings.get("theta_measured_deg")
    extra = np.zeros(w.size, dtype=bool) if angle is None else np.isfinite(angle)
    if extra.any():
        t_angle = data.settings["t_measured"]
        conds += [
            tuple(sorted((*conds[i], ("theta_cr_deg", float(angle[i])))))
            for i in np.flatnonzero(extra)
        ]
        w = np.concatenate([w, w[extra]])
        y = np.concatenate([y, t_angle[extra]])
        run, band = np.concatenate([run, run[extra]]), np.concatenate([band, band[extra]])
        high = np.concatenate([high, high[extra]])
        starred = np.concatenate([starred, starred[extra]])
    return w, y, run, band, high, starred, (conds if any(conds) else None)


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


def _replace_ci(
    f: CandidateFit, ci: dict[str, tuple[float, float]], method: dict[str, str]
) -> CandidateFit:
    from dataclasses import replace

    return replace(f, ci95=ci, ci_method=method)


def _replace_model_fit(m: ModelResult, fit: CandidateFit) -> ModelResult:
    from dataclasses import replace

    return replace(m, fit=fit)
