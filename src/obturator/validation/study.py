"""The whole validation study: floor, fits, out-of-band prediction, ranking (issue 9).

:func:`run_validation` runs, for every candidate,

1. the fit to all runs (ranked by AIC; the one fit per model that
   ``design-experiment`` shares, :func:`all_run_fits`, with a bounded multi-start
   along its flat directions, :mod:`.valley`);
2. the fit to the starred runs (the thesis's selection) and its rms on all runs;
3. out-of-band prediction: a fit to the runs whose cluster-mean spin is
   >= 200 rad/s, predicting the runs below, and the reverse (the split is by
   cluster mean, as the bands of the floor, so the replicate cluster at
   199.4 rad/s is not cut in two);
4. the t_cr(omega_p) curve of the all-run fit and a convergence check
   (:func:`obturator.solve.convergence_check`: tolerances / 10, width / 10
   and another regularisation family) of its prediction at every run;
5. its predictive scores, leave one replicate cluster out and leave one spin band out
   (:mod:`.predictive`), by which the recommendation is made;

then profile-likelihood intervals for the recommended model's parameters and
the spread of its t_cr over the release phase psi_0.

Work is spread over the runner's processes (:class:`obturator.runs.Runner`; each task is one fit,
one curve or one profile side), each with its own t_cr cache; subset fits start
from the all-run fit. A runner with a store keeps every finished task (keyed by its
content, stored pickled) so that an interrupted study resumes where it stopped.

Recommendation rule: :mod:`obturator.validation.recommend`.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import replace
from functools import partial
from typing import Any

import numpy as np

from .. import __version__
from ..calibration.data import SpinRigData, load_thesis_data
from ..errors import InputError, check_range
from ..runs import Runner, study_digest
from ..runs.progress import PhasePlan
from ..solve import SolverOptions
from ..vocab import NOISE_MODELS, check_choice
from .candidates import Candidate, get_candidates
from .cost import phase_weights
from .evaluate import DEFAULT_T_MAX, VALIDATION_OPTIONS
from .floor import DEFAULT_CLUSTER_GAP, ReplicateFloor, band_of, replicate_floor
from .likelihood import SPIN_SD
from .predictive import cross_validation_task
from .recommend import OUT_OF_BAND_SPLIT, model_aic, recommend
from .results import CandidateFit, ModelResult, ValidationResult
from .tasks import (
    AllRuns,
    Observations,
    all_run_fit_task,
    call,
    cost_rank,
    first_fit_task,
    phase_task,
    profile_task,
    restart_fit_task,
    settled_fit_task,
    warm_up,
)
from .valley import valley_starts

__all__ = ["OUT_OF_BAND_SPLIT", "all_run_fits", "recommend", "run_validation"]

_CURVE_POINTS = 48


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
    common = (spin_sd, t_max, options, noise)
    floor, obs = _observations(data, gap, common, curve_points)
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
    # one display for both phases; until the recommended model is known, the profiles
    # are planned for the candidate with the most parameters
    weights = partial(_phase_weights, cands, obs, floor, curve_points)
    first = cands if profile_all else [max(cands, key=lambda c: c.n_params)] if profile else []
    with runner.reporter.phases("validate", weights(first)) as plan:
        plan.start("all-run fits")
        study = (data, cands, floor, obs, common, gap, jobs, profile, profile_all, t_start)
        return _phases(runner, plan, weights, *study)


def _phase_weights(
    cands: Sequence[Candidate],
    obs: Observations,
    floor: ReplicateFloor,
    curve_points: int,
    profiled: Sequence[Candidate],
) -> list[tuple[str, float]]:
    """The two phases' weights of this study (:func:`.cost.phase_weights`)."""
    high, n = obs.high, obs.w.size
    subsets = []
    if obs.starred.any() and not obs.same_split:
        subsets.append((int(obs.starred.sum()), n))
    if high.any() and (~high).any():
        subsets += [(int(high.sum()), int((~high).sum())), (int((~high).sum()), int(high.sum()))]
    n_centres = len({round(float(x), 6) for x in floor.cluster_mean_spin()})
    return phase_weights(cands, n, obs.n_runs, subsets, curve_points, n_centres, profiled)


def _phases(
    runner: Runner,
    ph: PhasePlan,
    weights: Callable[[Sequence[Candidate]], list[tuple[str, float]]],
    data: SpinRigData,
    cands: list[Candidate],
    floor: ReplicateFloor,
    obs: Observations,
    common: tuple[Any, ...],
    gap: float,
    jobs: int,
    profile: bool,
    profile_all: bool,
    t_start: float,
) -> ValidationResult:
    """The study's two phases (see :func:`run_validation`), reported as one run."""
    band = obs.band
    spin_sd, t_max, options, _ = common
    # phase 1: every all-run fit
    timings: dict[str, float] = {}
    run_tasks = partial(
        runner.map, call, chunk_size=1, probe_first=False, warm=partial(warm_up, options)
    )
    # computed here (or resumed from the store), never taken from the memo: the study
    # is its own record; the memo serves design-experiment after it in this process
    fits = _fits_of(cands, obs, gap, runner, data, memo=False)
    timings["all_run_fits"] = time.perf_counter() - t_start
    # the provisional choice by AIC (the all-run fits only): its profile intervals run
    # alongside phase 2, which computes the predictive scores of the final choice
    prelim = sorted((ModelResult(c.name, fits[c.name]) for c in cands), key=model_aic)
    rec_name, why = recommend(prelim)
    rec_fit = fits[rec_name]
    # phase 2: profile sides (longest first), subset fits, curves, checks
    tasks: list[tuple[Any, ...]] = []
    tags: list[tuple[Any, Any, Any]] = []
    profiled = [c.name for c in cands] if profile_all else [rec_name] if profile else []
    # its weight now that the profiled candidates are known
    name, weight = weights([c for c in cands if c.name in profiled])[1]
    ph.start(name, weight)
    for pname in profiled:
        for k in fits[pname].params:
            for side in (-1, 1):
                tasks.append((profile_task, fits[pname], pname, k, side, spin_sd, options))
                tags.append(("profile", (pname, k), side))
    centres = np.array(sorted({round(float(x), 6) for x in floor.cluster_mean_spin()}))
    tasks.append((phase_task, rec_name, dict(rec_fit.values), centres, t_max, options))
    tags.append(("phase", "", None))
    for c in sorted(cands, key=cost_rank, reverse=True):
        for task, tag in obs.candidate_tasks(c, fits[c.name]):
            tasks.append(task)
            tags.append(tag)
    folds = {
        "leave_one_cluster_out": obs.cluster,
        "leave_one_band_out": np.unique(band, return_inverse=True)[1].astype(np.int64),
    }
    for c in sorted(cands, key=cost_rank, reverse=True):
        tasks.append((cross_validation_task, c.name, fits[c.name], folds, spin_sd, options))
        tags.append(("predictive", c.name, None))
    done = run_tasks(
        tasks, label="validate: profiles, subset fits, curves", unit="tasks", pickled=True
    )
    sub, prof, phase, scores = _phase_two_results(tags, done, cands)
    timings["subset_fits_curves_checks_profiles_predictive"] = (
        time.perf_counter() - t_start - timings["all_run_fits"]
    )
    results = [
        replace(obs.model_result(c, fits[c.name], sub[c.name], floor), predictive=scores[c.name])
        for c in cands
    ]
    results.sort(key=model_aic)
    # the choice by the predictive scores; the provisional one (AIC, for the profiles that
    # ran alongside phase 2) may differ: then the chosen model's profiles run now
    final_name, why = recommend(results)
    if profile and final_name not in prof:
        more = [
            (profile_task, fits[final_name], final_name, k, side, spin_sd, options)
            for k in fits[final_name].params
            for side in (-1, 1)
        ]
        got = run_tasks(more, label="validate: profiles", unit="tasks", pickled=True)
        for task, res in zip(more, got, strict=True):
            prof.setdefault(final_name, {}).setdefault(task[3], {})[task[4]] = res[2]
    rec_name = final_name
    results = _with_profile_intervals(results, fits, prof)
    label = "all" if profile_all else "recommended" if profile else "none"
    settings = _settings_record(data, obs, gap, jobs, label, timings)
    return ValidationResult(
        floor=floor,
        models=results,
        recommended=rec_name,
        recommendation=why,
        settings=settings,
        elapsed_s=time.perf_counter() - t_start,
        phase_scatter=phase,
    )


def _phase_two_results(
    tags: list[tuple[Any, Any, Any]], done: list[Any], cands: Sequence[Candidate]
) -> tuple[
    dict[str, dict[str, Any]],
    dict[str, dict[str, dict[int, float]]],
    dict[str, Any],
    dict[str, dict[str, Any]],
]:
    """Phase 2's results by kind: per candidate its subset fits and curve, per profiled
    candidate and parameter the two profile bounds (by side), the phase scatter, and per
    candidate its predictive scores."""
    sub: dict[str, dict[str, Any]] = {c.name: {} for c in cands}
    prof: dict[str, dict[str, dict[int, float]]] = {}
    phase: dict[str, Any] = {}
    scores: dict[str, dict[str, Any]] = {}
    for (name, label, m_pred), res in zip(tags, done, strict=True):
        if name == "profile":
            pname, k = label
            prof.setdefault(pname, {}).setdefault(k, {})[int(m_pred)] = res[2]
        elif name == "phase":
            phase = res
        elif name == "predictive":
            scores[label] = res
        else:
            sub[name][label] = (res, m_pred)
    return sub, prof, phase, scores


#: The all-run fits of this process, by content (data, candidate, settings): a study
#: that asks again (``design-experiment`` after ``validate`` in ``reproduce``, or any
#: caller of :func:`all_run_fits`) gets the same fit, not a second one.
_FIT_MEMO: dict[str, CandidateFit] = {}
_FIT_MEMO_SIZE = 64


def _fits_of(
    cands: Sequence[Candidate],
    obs: Observations,
    gap: float,
    runner: Runner,
    data: SpinRigData,
    memo: bool = True,
) -> dict[str, CandidateFit]:
    """Every candidate's all-run fit (:func:`.tasks.all_run_fit_task`), from this process's
    memo (with `memo`) or computed on the runner (costliest first, one task per chunk, kept
    in its store by content); computed fits go into the memo either way."""
    w, y, run, band, conds = obs.w, obs.y, obs.run, obs.band, obs.conds
    keys = {
        c.name: study_digest(
            {
                "fit": "all runs",
                "version": __version__,
                "data": data,
                "model": c.name,
                "settings": [*obs.common, gap],
            }
        )  # fmt: skip
        for c in cands
    }
    todo = [c for c in cands if not memo or keys[c.name] not in _FIT_MEMO]
    # costliest first, so that the last fit to end is not a long one started late
    todo.sort(key=cost_rank, reverse=True)
    data_of = AllRuns(w, y, band, run, *obs.common, conds)
    fit_map = partial(
        runner.map,
        call,
        unit="fits",
        chunk_size=1,
        probe_first=False,
        warm=partial(warm_up, obs.common[2]),
        pickled=True,
    )
    if not todo:
        done = []
    elif len(todo) < STAGED_BELOW * runner.n_workers:
        done = _staged_fits(todo, data_of, fit_map)
    else:
        done = fit_map(
            [(all_run_fit_task, c.name, data_of) for c in todo], label="validate: all-run fits"
        )
    for c, res in zip(todo, done, strict=True):
        if len(_FIT_MEMO) >= _FIT_MEMO_SIZE:
            _FIT_MEMO.pop(next(iter(_FIT_MEMO)))
        _FIT_MEMO[keys[c.name]] = res[0]
    return {c.name: _FIT_MEMO[keys[c.name]] for c in cands}


#: Fewer all-run fits than this many per worker run their three steps as tasks of their
#: own (:func:`_staged_fits`): with two candidates on two workers (``design-experiment``)
#: one fit with its restarts would hold one worker while the other idles. With more
#: fits than that, one task per fit keeps the pool balanced without the two barriers.
STAGED_BELOW = 2


def _staged_fits(
    todo: Sequence[Candidate], data_of: AllRuns, fit_map: Callable[..., list[Any]]
) -> list[tuple[CandidateFit, None]]:
    """:func:`.tasks.all_run_fit_task` of each candidate in `todo` as three runner maps:
    the first fits, every restart of every candidate, the settled fits (the same results
    as one task per fit: each step builds its own evaluator)."""
    firsts = fit_map(
        [(first_fit_task, c.name, data_of) for c in todo], label="validate: all-run fits"
    )
    starts = [valley_starts(f) for f in firsts]
    flat = [(k, s) for k, ss in enumerate(starts) for s in ss]
    others = fit_map(
        [(restart_fit_task, todo[k].name, s, data_of) for k, s in flat],
        label="validate: all-run fits, restarts",
    ) if flat else []  # fmt: skip
    of = [[o for (k, _), o in zip(flat, others, strict=True) if k == j] for j in range(len(todo))]
    return fit_map(
        [
            (settled_fit_task, c.name, f, o, data_of)
            for c, f, o in zip(todo, firsts, of, strict=True)
        ],
        label="validate: all-run fits, settled",
    )


def all_run_fits(
    models: Sequence[str] | str | None = None,
    data: SpinRigData | None = None,
    *,
    runner: Runner | None = None,
    t_max: float = DEFAULT_T_MAX,
    spin_sd: float = SPIN_SD,
    gap: float = DEFAULT_CLUSTER_GAP,
    options: SolverOptions | None = None,
    noise: str = "band",
) -> dict[str, CandidateFit]:
    """The fit of each candidate to all runs, exactly as :func:`run_validation` makes it.

    The one fit per model and data: the same observations, bands, noise model and
    bounded multi-start (:func:`.tasks.all_run_fit_task`), kept in this process by
    content, so that ``design-experiment`` and ``validate`` report the same parameters.
    Arguments as :func:`run_validation`'s.
    """
    options = options or VALIDATION_OPTIONS
    data = load_thesis_data() if data is None else data
    cands = get_candidates(models)
    check_choice("noise", noise, NOISE_MODELS)
    _, obs = _observations(data, gap, (spin_sd, t_max, options, noise), 2)
    return _fits_of(cands, obs, gap, runner or Runner(workers=2), data)


def _with_profile_intervals(
    results: list[ModelResult],
    fits: dict[str, CandidateFit],
    prof: dict[str, dict[str, dict[int, float]]],
) -> list[ModelResult]:
    """The results with each profiled parameter's 95 % interval from its profile."""
    for pname, pk in prof.items():
        f = fits[pname]
        ci = {**f.ci95, **{k: (v[-1], v[1]) for k, v in pk.items()}}
        method = {**f.ci_method, **{k: "profile" for k in pk}}
        new_fit = _replace_ci(f, ci, method)
        results = [_replace_model_fit(m, new_fit) if m.name == pname else m for m in results]
    return results


def _settings_record(
    data: SpinRigData,
    obs: Observations,
    gap: float,
    jobs: int,
    profile: str,
    timings: dict[str, float],
) -> dict[str, Any]:
    """The study's settings as the result reports them."""
    spin_sd, t_max, opts, noise = obs.common
    return {
        "source": data.source,
        "n_runs": obs.n_runs,
        "n_angle_observations": int(len(obs.w) - obs.n_runs),
        "t_max_s": t_max,
        "spin_sd_rad_s": spin_sd,
        "cluster_gap_rad_s": gap,
        "out_of_band_split_rad_s": OUT_OF_BAND_SPLIT,
        "jobs": jobs,
        "profile": profile,
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
        "ranking": "AIC of the all-run fit (table order); recommendation by the "
        "leave-one-cluster-out deviance among plausible candidates",
        "starred_runs_are_high_half": obs.same_split,
        "timings_s": timings,
    }


def _observations(
    data: SpinRigData, gap: float, common: tuple[Any, ...], curve_points: int
) -> tuple[ReplicateFloor, Observations]:
    """The replicate floor of the runs' t_cr, and every observation: the runs' t_cr, then
    each time to an intermediate angle (event at theta_measured; same run, band and half),
    with per-run settings (None where all are Table 1)."""
    # runs with another ball or load (a data file's columns) are no replicates; a
    # theta_0 read per run varies like the spin within its band and does not split
    groups = [
        tuple(kv for kv in r if kv[0] in ("hole_radius", "density", "ball_mass"))
        for r in data.run_settings()
    ]
    floor = replicate_floor(
        data.spin_rate, data.opening_time, gap=gap, groups=groups if any(groups) else None
    )
    band = band_of(floor.cluster_mean_spin())
    high = floor.cluster_mean_spin() >= OUT_OF_BAND_SPLIT
    cluster = np.asarray(floor.cluster, dtype=np.int64)
    n_runs = len(data.spin_rate)
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
        cluster = np.concatenate([cluster, cluster[extra]])
        high = np.concatenate([high, high[extra]])
        starred = np.concatenate([starred, starred[extra]])
    if len(w) < 5:
        raise InputError("data", f"{len(w)} runs; the study needs at least 5")
    grid = np.geomspace(0.9 * float(w.min()), 1.05 * float(w.max()), int(curve_points))
    # on the thesis data the starred runs are exactly the high half: fit once
    same_split = bool(np.array_equal(starred, high))
    obs = Observations(
        w, y, run, band, high, starred, conds if any(conds) else None, n_runs, common, grid,
        same_split, cluster,
    )  # fmt: skip
    return floor, obs


def _replace_ci(
    f: CandidateFit, ci: dict[str, tuple[float, float]], method: dict[str, str]
) -> CandidateFit:

    return replace(f, ci95=ci, ci_method=method)


def _replace_model_fit(m: ModelResult, fit: CandidateFit) -> ModelResult:

    return replace(m, fit=fit)
