"""The design study: which N rig runs decide between the candidate mechanisms.

:func:`design_experiment` runs, on one :class:`obturator.runs.Runner` (its resume
store keeps every finished task, so an interrupted study resumes):

1. the Laplace posterior of every candidate's fit to the measured runs
   (:mod:`.posterior`): the fit ``validate`` makes
   (:func:`obturator.validation.study.all_run_fits`, one task per candidate, or taken from
   given fits), with a new ball's own copy of the ball-specific parameters;
2. the exact solves behind each candidate's surrogate at every candidate setting
   (:mod:`.surrogate`; the grid of :class:`.settings.SettingRanges` and the measured
   runs' spins on the Table 1 rig);
3. for each N, the plan of N runs maximising the Box-Hill criterion (:mod:`.criterion`)
   with the replicate SD of each spin band as the noise, over the settings the rig can
   hold (:mod:`.feasibility`; those outside the measured runs marked);
4. simulated campaigns (:mod:`.campaigns`): exact t_cr at posterior draws of each
   generating model at every planned setting and at the naive plans' spins, the
   decision rates of the designed and the naive plans, how often each exposes a truth
   outside the candidates, and the surrogate's error;
5. the plan of the recommended size without the feasibility check and on the as-built
   ball alone (plan search only).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..calibration.data import SpinRigData, load_thesis_data
from ..errors import InputError, check_range
from ..runs import Runner
from ..validation.candidates import get_candidates
from ..validation.evaluate import DEFAULT_T_MAX
from ..validation.floor import replicate_floor
from ..validation.results import CandidateFit
from ..validation.study import all_run_fits
from ..validation.tasks import warm_up
from .campaigns import (
    OUTSIDE,
    campaign_draws,
    decision_rates,
    discrepancy,
    discrepancy_at,
    surrogate_error,
)
from .criterion import EXCHANGE_PASSES, greedy_exchange, plan_values
from .feasibility import ValidatedRange, check_setting
from .noise import RELEASE_STEP_DEG, ReplicateNoise
from .posterior import Posterior, new_ball_prior_sd
from .results import DesignResult, PlanResult, recommended_plan
from .settings import NEW_BALL, Setting, SettingRanges, naive_plan
from .surrogate import Surrogate, assemble, opening_time_table, surrogate_tasks

__all__ = [
    "DEFAULT_DESIGN_MODELS",
    "DEFAULT_NAIVE_RUNS",
    "DEFAULT_RUNS",
    "design_experiment",
]

#: The recommended model of the validation study and the fitted-theta_0 model.
DEFAULT_DESIGN_MODELS: tuple[str, ...] = ("strengthening", "theta0")
#: Campaign sizes of the decision curve.
DEFAULT_RUNS: tuple[int, ...] = (1, 2, 3, 5, 10, 20)
#: Sizes of the naive plan simulated (to find the size that matches a design).
DEFAULT_NAIVE_RUNS: tuple[int, ...] = (5, 10, 20, 40, 54, 81, 108, 162, 216)
#: Relative weight of the simplicity preference in the plan search: a run that changes the
#: release angle, the hole and the ball material from the Table 1 rig must raise the
#: criterion by 2 % (one of them: 0.67 %) to be chosen over the rig as built; below that
#: the designs are near-ties (e.g. the density, which moves t_cr by < 0.1 % on the rig)
#: and the simpler one is planned.
SIMPLICITY = 0.02
_SETTINGS_PER_TASK = 24
_DRAWS_PER_TASK = 8


def _fits(
    names: Sequence[str],
    fits: Mapping[str, CandidateFit] | None,
    data: SpinRigData,
    runner: Runner,
    t_max: float,
) -> dict[str, CandidateFit]:
    """Each candidate's fit to all runs: given, or the one ``validate`` makes
    (:func:`obturator.validation.study.all_run_fits`: same observations, noise model and
    bounded multi-start, kept in this process by content)."""
    given = {k: f for k, f in (fits or {}).items() if k in names}
    todo = [n for n in names if n not in given]
    if todo:
        given.update(all_run_fits(todo, data, runner=runner, t_max=t_max))
    return {n: given[n] for n in names}


def _discrepancies(
    fits: Mapping[str, CandidateFit], data: SpinRigData
) -> dict[str, tuple[NDArray[np.float64], NDArray[np.float64]]]:
    """Each fit's mean residual per replicate cluster of the measured runs' t_cr
    (:func:`.campaigns.discrepancy`)."""
    n = data.spin_rate.size
    cluster = replicate_floor(data.spin_rate, data.opening_time).cluster
    return {
        k: discrepancy(data.spin_rate, f.measured[:n] - f.model[:n], cluster)
        for k, f in fits.items()
    }


def _exact_tables(
    tasks: list[dict[str, Any]], runner: Runner, label: str
) -> dict[str, list[list[list[float | None]]]]:
    """Solve the tasks in one batch; each model's (``task["model"]``) tables in task order."""
    done = runner.map(
        opening_time_table,
        tasks,
        label=label,
        unit="tasks",
        chunk_size=1,
        probe_first=False,
        warm=warm_up,
    )
    by_model: dict[str, list[list[list[float | None]]]] = {}
    for task, table in zip(tasks, done, strict=True):
        by_model.setdefault(task["model"], []).append(table)
    return by_model


def _release_slopes(
    posts: Mapping[str, Posterior],
    surrogates: Mapping[str, Surrogate],
    settings: Sequence[Setting],
    runner: Runner,
    t_max: float,
) -> NDArray[np.float64]:
    """|dt_cr/dtheta_0| [s/deg] at every setting, the models' mean at their best fits
    (one-sided, :data:`.noise.RELEASE_STEP_DEG` towards lower angles)."""
    lower = [replace(s, theta0_deg=s.theta0_deg - RELEASE_STEP_DEG) for s in settings]
    rows = [s.to_dict() for s in lower]
    tasks = [
        {
            "model": n,
            "values": [p.to_values(p.mean)],
            "settings": rows[i : i + 4 * _SETTINGS_PER_TASK],
            "t_max": t_max,
        }
        for n, p in posts.items()
        for i in range(0, len(rows), 4 * _SETTINGS_PER_TASK)
    ]
    done = _exact_tables(tasks, runner, "design: release-angle slopes")
    slopes = [
        np.abs(
            surrogates[n].t0 - np.array([np.nan if v is None else v for t in done[n] for v in t[0]])
        )
        / RELEASE_STEP_DEG
        for n in posts
    ]
    return np.nanmean(slopes, axis=0)


def _campaign_tasks(
    posts: Mapping[str, Posterior],
    draws: Mapping[str, NDArray[np.float64]],
    settings: list[dict[str, float]],
    t_max: float,
) -> list[dict[str, Any]]:
    """Runner tasks of the simulated campaigns' exact solves: each model's posterior
    draws (rows of ``draws[model]``), in chunks, at the `settings` of the plans."""
    return [
        {
            "model": n,
            "values": [post.to_values(x) for x in draws[n][a : a + _DRAWS_PER_TASK]],
            "settings": settings,
            "t_max": t_max,
        }
        for n, post in posts.items()
        for a in range(0, len(draws[n]), _DRAWS_PER_TASK)
    ]


def _model_names(models: Sequence[str] | str | None) -> list[str]:
    """The candidates to discriminate: at least two, each fitting a parameter."""
    cands = get_candidates(models if models is not None else DEFAULT_DESIGN_MODELS)
    if len(cands) < 2:
        raise InputError("models", "needs at least two candidates to discriminate")
    for c in cands:
        if not c.params:
            raise InputError("models", f"{c.name!r} fits no parameter; choose fitted candidates")
    return [c.name for c in cands]


def _best_plans(
    sizes: Sequence[int],
    candidates: list[int],
    value: Callable[[NDArray[np.intp]], NDArray[np.float64]],
    settings: Sequence[Setting],
    runner: Runner,
) -> dict[int, tuple[list[int], float]]:
    """The best plan of each size among the `candidates` (indices into `settings`), and its
    value (`value(plans)`: of each row, as :func:`.criterion.greedy_exchange` asks);
    near-ties go to the simpler experiment (fewer changes from the Table 1 rig)."""
    changes = np.array([s.n_changes for s in settings], dtype=float)

    def preferred(plans: NDArray[np.intp]) -> NDArray[np.float64]:
        return value(plans) * (1.0 - SIMPLICITY * changes[plans].mean(axis=-1) / 3.0)

    plans = {}
    steps = sum(sizes) * (1 + EXCHANGE_PASSES)
    with runner.reporter.track("design: plan search", steps, unit="steps") as advance:
        for n in sizes:
            advance.describe(f"the best {n}-run plan")
            plan, _ = greedy_exchange(n, candidates, preferred, EXCHANGE_PASSES, advance)
            plans[n] = (plan, float(value(np.asarray([plan], dtype=np.intp))[0]))
    return plans


#: Closest approach to 90 deg [deg] a new ball's release may make at two prior SDs of its
#: own offset: at 90 deg the ball never leaves (t_cr grows as ln 1/(90 deg - theta_0)),
#: and a run there tells only the offset the run cannot measure.
EQUILIBRIUM_MARGIN_DEG = 0.5


def _testable(s: Setting, posts: Mapping[str, Posterior]) -> bool:
    """A new ball's set angle stays :data:`EQUILIBRIUM_MARGIN_DEG` below 90 deg with two
    prior SDs of its own theta_0 offset (the as-built ball's offset is fitted)."""
    if s.is_as_built_ball or not any("theta0_deg" + NEW_BALL in p.params for p in posts.values()):
        return True
    return s.theta0_deg + 2.0 * new_ball_prior_sd("theta0_deg") <= 90.0 - EQUILIBRIUM_MARGIN_DEG


def _recommended_size(plans: Sequence[PlanResult]) -> int:
    return recommended_plan(plans).n_runs


def design_experiment(
    models: Sequence[str] | str | None = None,
    *,
    ranges: SettingRanges | None = None,
    n_runs: Sequence[int] = DEFAULT_RUNS,
    campaigns: int = 200,
    seed: int = 1,
    data: SpinRigData | None = None,
    fits: Mapping[str, CandidateFit] | None = None,
    runner: Runner | None = None,
    t_max: float = DEFAULT_T_MAX,
    naive_runs: Sequence[int] = DEFAULT_NAIVE_RUNS,
    release_sd_deg: float | None = None,
) -> DesignResult:
    """Plan the rig runs that best discriminate between candidate mechanisms.

    Parameters
    ----------
    models : sequence of str or str, optional
        Candidates of :mod:`obturator.validation.candidates` (at least two, each with
        fitted parameters); default :data:`DEFAULT_DESIGN_MODELS`.
    ranges : SettingRanges, optional
        Controllable settings and the candidate grid (default :class:`SettingRanges`).
    n_runs : sequence of int
        Campaign sizes N to plan and simulate.
    campaigns : int
        Simulated campaigns per generating model and plan (seeded).
    seed : int
        Seed of the posterior draws and the replicate noise.
    data : SpinRigData, optional
        Measured runs (default: the 54 runs of thesis Appendix B): the fits, the replicate
        floor (the noise) and the naive plan's spins.
    fits : mapping of str to CandidateFit, optional
        Fits to `data` already made (e.g. by ``obturator validate``); the others are fitted.
    runner : Runner, optional
        Workers, progress, resume store (default: two workers).
    t_max : float
        Horizon [s].
    naive_runs : sequence of int
        Sizes of the naive plan simulated (with every N of `n_runs`).
    release_sd_deg : float, optional
        Repeatability (SD) of the release angle [deg], if measured; default: the largest
        the replicate floor allows (:class:`.noise.ReplicateNoise`).

    Returns
    -------
    DesignResult
    """
    t_start = time.perf_counter()
    names = _model_names(models)
    sizes = sorted({int(n) for n in n_runs})
    for n in sizes:
        check_range("n_runs", n, 1, 200)
    check_range("campaigns", campaigns, 10, 100_000)
    check_range("seed", seed, 0, 2**32 - 1)
    check_range("t_max", t_max, 0.0, 1e4, lo_open=True, unit="s")
    if release_sd_deg is not None:
        check_range("release_sd_deg", release_sd_deg, 0.0, 10.0, unit="deg")
    ranges = ranges or SettingRanges()
    data = load_thesis_data() if data is None else data
    runner = runner or Runner(workers=2)
    naive_sizes = sorted({*sizes, *(int(n) for n in naive_runs)})

    validated = ValidatedRange.of(data)
    grid = ranges.grid()
    # the rig must hold the ball at the set angle while it spins: a grid it cannot hold
    # anywhere is refused before any solve
    if not any(check_setting(s, validated).feasible for s in grid):
        raise InputError(
            "ranges",
            "no candidate setting the rig can hold: every one needs a holding moment above "
            "the rig's bound (the largest of the seat's friction plus the holding jet and "
            f"the {validated.holding_moment_max:.3g} N m the measured runs needed)",
        )
    noise_model = ReplicateNoise.of(data)
    fitted = _fits(names, fits, data, runner, t_max)
    posts = {n: Posterior.from_fit(f) for n, f in fitted.items()}
    misfit = _discrepancies(fitted, data)

    measured_spins = sorted({float(w) for w in data.spin_rate})
    settings: list[Setting] = list(dict.fromkeys([*grid, *(Setting(w) for w in measured_spins)]))
    index = {s: i for i, s in enumerate(settings)}
    feasibility = [check_setting(s, validated) for s in settings]
    feasible = np.array([f.feasible for f in feasibility])

    tasks = [
        t for n in names for t in surrogate_tasks(posts[n], settings, t_max, _SETTINGS_PER_TASK)
    ]
    done = _exact_tables(tasks, runner, "design: surrogate solves")
    surrogates = {n: assemble(n, done[n]) for n in names}
    valid = np.all([s.valid for s in surrogates.values()], axis=0)
    t_typical = np.nanmean([s.t0 for s in surrogates.values()], axis=0)
    slope = _release_slopes(posts, surrogates, settings, runner, t_max)
    noise_model = noise_model.with_release_bound(
        data, slope[[index[Setting(float(w))] for w in data.spin_rate]]
    )
    if release_sd_deg is not None:
        noise_model = replace(
            noise_model, release_sd_deg=float(release_sd_deg), release_source="given"
        )
    noise = noise_model.at(np.array([s.spin_rate for s in settings]), t_typical, slope)
    on_grid = set(grid)
    solvable = [i for i in range(len(settings)) if valid[i] and settings[i] in on_grid]
    if not solvable:
        raise InputError("ranges", "no candidate setting where every model opens by t_max")
    # never plan a setting the rig cannot hold, nor one on a new ball released so near
    # 90 deg that the ball's own unknown offset may put it at the equilibrium
    candidates = [i for i in solvable if feasible[i] and _testable(settings[i], posts)]
    if not candidates:
        raise InputError("ranges", "no setting the rig can hold where every model opens by t_max")

    def value(plans: NDArray[np.intp]) -> NDArray[np.float64]:
        return plan_values(surrogates.values(), noise, plans)

    plans = _best_plans(sizes, candidates, value, settings, runner)

    naive = {n: [index[s] for s in naive_plan(n, data.spin_rate)] for n in naive_sizes}
    columns = sorted(
        {i for p, _ in plans.values() for i in p} | {i for p in naive.values() for i in p}
    )
    col_settings = [settings[i].to_dict() for i in columns]
    draws = {n: campaign_draws(posts[n], campaigns, seed, k) for k, n in enumerate(names)}
    gen_tasks = _campaign_tasks(posts, draws, col_settings, t_max)
    gen = _exact_tables(gen_tasks, runner, "design: simulated campaigns (exact solves)")
    exact: dict[str, NDArray[np.float64]] = {}
    errors: dict[str, dict[str, float]] = {}
    spins = np.array([s.spin_rate for s in settings])
    for n in names:
        tab = np.array([[np.nan if v is None else v for v in row] for r in gen[n] for row in r])
        errors[n] = surrogate_error(tab, draws[n], posts[n], surrogates[n], columns, noise)
        full = np.full((campaigns, len(settings)), np.nan)
        full[:, columns] = np.where(np.isfinite(tab), tab, t_max)  # not opened: at the horizon
        exact[n] = full
    for n in names:  # the truths outside the candidates (.campaigns module notes)
        exact[OUTSIDE.format(n)] = exact[n] + discrepancy_at(misfit[n], spins)

    designed, naive_rates = {}, {}
    total = len(plans) + len(naive)
    with runner.reporter.track("design: decision rates", total, unit="plans") as advance:
        for n, (p, _) in plans.items():
            rng = np.random.default_rng([seed, 2, 0, n])
            designed[n] = decision_rates(exact, p, surrogates, noise, rng)
            advance(1)
        for n, p in naive.items():
            rng = np.random.default_rng([seed, 2, 1, n])
            naive_rates[n] = decision_rates(exact, p, surrogates, noise, rng)
            advance(1)
    plan_results = [
        PlanResult(
            n, plans[n][0], plans[n][1], value(naive[n]), designed[n], naive_rates[n], naive[n]
        )
        for n in sizes
    ]
    n_solves = sum(len(t["values"]) * len(t["settings"]) for t in [*tasks, *gen_tasks])
    # the plan of the recommended size before the feasibility check, and on the as-built
    # ball alone (plan search only: the campaigns simulate the plans that may be run)
    n_rec = _recommended_size(plan_results)
    alternatives = {}
    for label, pool in (
        ("without the feasibility check", solvable),
        ("on the as-built ball alone", [i for i in candidates if settings[i].is_as_built_ball]),
    ):
        if pool and pool != candidates:
            runner.reporter.note(f"design: the best {n_rec}-run plan {label}")
            alt = _best_plans([n_rec], pool, value, settings, runner)[n_rec]
            alternatives[label] = (n_rec, alt[0], alt[1])
    return DesignResult(
        models=tuple(names),
        posteriors=posts,
        settings=settings,
        candidate_mask=np.isin(np.arange(len(settings)), candidates),
        surrogates=surrogates,
        noise_sd=noise,
        noise_model=noise_model,
        release_slope=slope,
        plans=plan_results,
        naive_rates=naive_rates,
        surrogate_error=errors,
        ranges=ranges,
        campaigns=campaigns,
        seed=seed,
        n_solves=n_solves,
        data_source=data.source,
        elapsed_s=time.perf_counter() - t_start,
        feasibility=feasibility,
        validated=validated,
        alternative_plans=alternatives,
        flat_directions={n: list(f.flat_directions) for n, f in fitted.items()},
    )
