"""``obturator probability``, ``obturator sensitivity``, ``obturator optimize``.

Usage::

    obturator probability [--mach SPEC] [--altitude-m SPEC] [--vary NAME=KIND:ARGS ...]
        [--requirement S] [--method is|mc|both] [--samples N] [--stage-samples N]
        [--final-samples N] [--seed S] [--confidence C] [model / execution options]

    obturator sensitivity [--case flight|spin-rig] [--vary NAME=KIND:ARGS ...]
        [--samples N] [--resamples N] [--seed S] [--figure FILE.png] [...]

    obturator optimize [--mach SPEC] [--altitude-m SPEC] [--objective max|quantile:Q]
        [--variables a,b,...] [--bound NAME=LO,HI ...] [--mass-budget KG]
        [--pareto N] [--figure FILE.png] [...]

Distributions: ``normal:MEAN,SD``, ``uniform:LO,HI``, ``lognormal:MEDIAN,SIGMA_LN``,
``truncnormal:MEAN,SD,LO,HI`` in SI units; ``spin_factor`` multiplies the
nominal muzzle spin. Without ``--vary`` the defaults printed by ``--help`` are
used. Every command runs on local processes (``--workers``) or a Dask cluster
(``--scheduler``) and, with ``--out``, resumes after an interruption.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from . import _json
from ._robust_args import (
    DEFAULT_RANGES,
    DEFAULT_RIG_RANGES,
    DEFAULT_UNCERTAINTY,
    IS_FLAGS,
    PROBABILITY_DEFAULTS,
    add_robust_commands,
)
from ._runner import study_runner, write_dataset
from .envelope import (
    model_from_args,
    quantity,
)

__all__ = ["register", "DEFAULT_UNCERTAINTY", "DEFAULT_RANGES", "DEFAULT_RIG_RANGES"]


def _int(name: str, text: Any, lo: int = 1) -> int:
    try:
        n = int(str(text))
    except ValueError:
        raise InputError(name, f"{text!r} is not a whole number") from None
    if n < lo:
        raise InputError(name, f"{n} is outside the allowed range >= {lo}")
    return n


def _dists(texts: list[str] | None, defaults: tuple[str, ...], allowed: tuple[str, ...]) -> dict:
    from ..envelope.uncertain import parse_input_distribution

    out = {}
    for text in texts or defaults:
        name, dist = parse_input_distribution(text, allowed)
        if name in out:
            raise InputError("vary", f"{name} given twice")
        out[name] = dist
    return out


def _check_support(model: Any, dists: dict) -> None:
    """Every distribution's support is made of points the model accepts (one line if not)."""
    from ..envelope.model import INPUTS
    from ..envelope.uncertain import check_point_support

    check_point_support(model, dists, {k: v.unit for k, v in INPUTS.items()})


def _check_out(args: argparse.Namespace) -> None:
    if getattr(args, "out", None) and not Path(args.out).resolve().parent.is_dir():
        raise InputError("--out", f"directory of {args.out!r} does not exist")


# --------------------------------------------------------------------------- probability


def _run_probability(args: argparse.Namespace) -> int:
    import xarray as xr

    from ..envelope.model import INPUTS, TIMES
    from ..envelope.reliability import brute_force, importance_sampling
    from ..envelope.uncertain import performance
    from ..sweeps import parse_axis

    _check_out(args)
    _resolve_sampling_flags(args)
    model = model_from_args(args).with_(event=TIMES[args.event])
    dists = _dists(args.vary, DEFAULT_UNCERTAINTY, tuple(INPUTS))
    _check_support(model, dists)
    machs = parse_axis(args.grid_mach, "--mach", "")
    alts = parse_axis(args.grid_altitude, "--altitude-m", "m")
    req = quantity("--requirement", args.requirement, "s")
    conf = quantity("--confidence", args.confidence, "")
    seed = _int("--seed", args.seed, 0)
    methods = {"is": ["is"], "mc": ["mc"], "both": ["is", "mc"]}[args.method]
    kw_is = {
        "n_stage": _int("--stage-samples", args.stage_samples, 20),
        "n_final": _int("--final-samples", args.final_samples, 20),
        "rho": quantity("--rho", args.rho, ""),
        "seed": seed,
        "confidence": conf,
    }
    n_mc = _int("--samples", args.samples)
    identity = {
        "study": "probability",
        "model": model.identity(),
        "vary": {k: str(v) for k, v in dists.items()},
    }
    runner = study_runner(args, identity)
    t0 = time.perf_counter()
    rows: dict[str, dict[tuple[int, int], Any]] = {m: {} for m in methods}
    try:
        for i, m in enumerate(machs):
            for j, h in enumerate(alts):
                pm = model.with_(launch=_launch(model, m, h))
                perf = performance(pm, runner, f"M {m:g}, {h:g} m")
                if "is" in methods:
                    rows["is"][i, j] = importance_sampling(perf, dists, req, **kw_is)
                if "mc" in methods:
                    rows["mc"][i, j] = brute_force(
                        perf, dists, req, samples=n_mc, seed=seed, confidence=conf
                    )
    finally:
        runner.close()
    elapsed = time.perf_counter() - t0
    data = {}
    dims = ("mach", "altitude_m")
    for meth, est in rows.items():
        for key in ("probability", "ci_low", "ci_high", "std_error", "n_evaluations", "n_exceed"):
            arr = np.array(
                [[getattr(est[i, j], key) for j in range(alts.size)] for i in range(machs.size)]
            )
            data[f"{key}_{meth}"] = (dims, arr, {"method": est[0, 0].method})
        data[f"n_unconverged_{meth}"] = (
            dims,
            np.array(
                [[est[i, j].n_unconverged for j in range(alts.size)] for i in range(machs.size)]
            ),
            {},
        )
    ds = xr.Dataset(
        data,
        coords={"mach": ("mach", machs), "altitude_m": ("altitude_m", alts, {"units": "m"})},
        attrs={
            "title": f"P({args.event} > requirement)",
            "requirement_s": req,
            "confidence": conf,
            "distributions": "; ".join(f"{k}={v}" for k, v in dists.items()),
            "load": model.load,
            "seed": seed,
        },
    )
    write_dataset(args, runner, ds)
    out = {
        "requirement_s": req,
        "load": model.load,
        "distributions": {k: str(v) for k, v in dists.items()},
        "elapsed_s": elapsed,
        "points": [],
    }
    for i, m in enumerate(machs):
        for j, h in enumerate(alts):
            pt: dict[str, Any] = {"mach": float(m), "altitude_m": float(h)}
            for meth in methods:
                pt[meth] = rows[meth][i, j].to_dict()
            if len(methods) == 2:
                a, b = rows["is"][i, j], rows["mc"][i, j]
                pt["is_within_mc_interval"] = b.ci_low <= a.probability <= b.ci_high
                pt["difference_in_std_errors"] = (
                    (a.probability - b.probability) / math.hypot(a.std_error, b.std_error)
                    if (a.std_error or b.std_error)
                    else 0.0
                )
            out["points"].append(pt)
    if args.json:
        print(_json.dumps(out))
        return 0
    pc = int(100 * conf)
    print(f"P({args.event} > {req:g} s), {model.load} load; {pc} % intervals")
    for pt in out["points"]:
        head = f"M {pt['mach']:g}, {pt['altitude_m']:g} m:"
        for meth in methods:
            e = rows[meth][machs.tolist().index(pt["mach"]), alts.tolist().index(pt["altitude_m"])]
            label = "importance sampling" if meth == "is" else "brute force       "
            warn = "" if e.reliable else " (fewer than 10 exceedances: interval unreliable)"
            print(
                f"{head} {label} p = {e.probability:.4g} [{e.ci_low:.4g}, {e.ci_high:.4g}] "
                f"({e.n_evaluations} runs, {e.n_exceed} exceed, {e.n_unconverged} not converged)"
                f"{warn}"
            )
            head = " " * len(head)
        if "is_within_mc_interval" in pt:
            print(
                f"{' ' * len(head)} IS inside the brute-force interval: "
                f"{pt['is_within_mc_interval']}; difference {pt['difference_in_std_errors']:+.2f} "
                "standard errors"
            )
    print(f"{elapsed:.1f} s ({runner.n_computed} runs computed, {runner.n_resumed} resumed)")
    return 0


def _launch(model: Any, mach: float, altitude: float) -> Any:
    from dataclasses import replace

    return replace(model.launch, mach=float(mach), altitude_m=float(altitude))


def _resolve_sampling_flags(args: argparse.Namespace) -> None:
    """Refuse a sampling flag that the chosen ``--method`` does not use (one line naming
    both flags), then fill the unset ones with :data:`PROBABILITY_DEFAULTS`."""
    if args.method == "is" and args.samples is not None:
        raise InputError(
            "--samples",
            "applies to --method mc or both (brute force), not --method is (importance "
            "sampling draws --stage-samples and --final-samples)",
        )
    if args.method == "mc":
        for flag, dest in IS_FLAGS:
            if getattr(args, dest) is not None:
                raise InputError(
                    flag, "applies to --method is or both (importance sampling), not --method mc"
                )
    for dest, default in PROBABILITY_DEFAULTS.items():
        if getattr(args, dest) is None:
            setattr(args, dest, default)


# --------------------------------------------------------------------------- sensitivity


def _run_sensitivity(args: argparse.Namespace) -> int:
    from ..envelope.figures import plot_sobol
    from ..envelope.model import INPUTS, TIMES
    from ..envelope.sensitivity import sobol_indices
    from ..envelope.uncertain import RIG_INPUTS, RigModel, performance

    _check_out(args)
    rig = args.case == "spin-rig"
    if rig and args.event in ("t_start", "t_start_late"):
        raise InputError(
            "--event", f"{args.event} applies to --case flight only (the rig has no inlet)"
        )
    for flag, value in (("--mach", args.mach_point), ("--altitude-m", args.altitude_point)):
        if rig and value is not None:
            raise InputError(flag, "applies to --case flight only (the rig has no flight)")
    if rig:
        dists = _dists(args.vary, DEFAULT_RIG_RANGES, RIG_INPUTS)
        flight = model_from_args(args)
        model: Any = RigModel(
            tuple(dists), options=flight.options, check_convergence=flight.check_convergence
        )
        _check_support(model, dists)
    else:
        dists = _dists(args.vary, DEFAULT_RANGES, tuple(INPUTS))
        model = model_from_args(args).with_(event=TIMES[args.event])
        if args.mach_point is not None or args.altitude_point is not None:
            model = model.with_(
                launch=_launch(
                    model,
                    quantity("--mach", args.mach_point or model.launch.mach, ""),
                    quantity("--altitude-m", args.altitude_point or model.launch.altitude_m, "m"),
                )
            )
        _check_support(model, dists)
    n = _int("--samples", args.samples, 8)
    seed = _int("--seed", args.seed, 0)
    identity = {
        "study": "sensitivity",
        "model": model.identity(),
        "vary": {k: str(v) for k, v in dists.items()},
        "n": n,
        "seed": seed,
    }
    runner = study_runner(args, identity)
    t0 = time.perf_counter()
    try:
        ds = sobol_indices(
            performance(model, runner, "sobol"),
            dists,
            n,
            seed=seed,
            confidence=quantity("--confidence", args.confidence, ""),
            resamples=_int("--resamples", args.resamples, 10),
        )
    finally:
        runner.close()
    elapsed = time.perf_counter() - t0
    ds.attrs["title"] = f"Sobol indices of {args.event}, {args.case}" + (
        "" if rig else f" (M {model.launch.mach:g}, {model.launch.altitude_m:g} m, {model.load})"
    )
    write_dataset(args, runner, ds)
    if args.figure:
        plot_sobol(ds, args.figure)
    if args.json:
        out = {k: ds[k].values.tolist() for k in ("S1", "S1_conf", "ST", "ST_conf")}
        out["input"] = [str(x) for x in ds["input"].values]
        out.update({k: v for k, v in ds.attrs.items() if isinstance(v, int | float | str)})
        out["elapsed_s"] = elapsed
        print(_json.dumps(out))
        return 0
    print(ds.attrs["title"])
    pc = int(100 * float(ds.attrs["confidence"]))
    print(f"{'input':>14} {'S1':>8} {'+-' + str(pc) + '%':>8} {'ST':>8} {'+-':>8}")
    for k, name in enumerate(ds["input"].values):
        # + 0.0 after rounding: an index of -3e-6 prints as 0.0000, not -0.0000
        cells = (ds.S1, ds.S1_conf, ds.ST, ds.ST_conf)
        print(
            f"{name!s:>14} " + " ".join(f"{round(float(c.values[k]), 4) + 0.0:8.4f}" for c in cells)
        )
    print(
        f"{ds.attrs['n_evaluations']} runs ({runner.n_computed} computed, {runner.n_resumed} "
        f"resumed), {ds.attrs['n_censored']} not opened, {ds.attrs['n_unconverged']} not "
        f"converged; mean {args.event} {ds.attrs['mean']:.5g} s, "
        f"sd {math.sqrt(ds.attrs['variance']):.3g} s; {elapsed:.1f} s"
    )
    from ..envelope.sensitivity import sobol_warnings

    for line in sobol_warnings(ds):  # the indices are printed; say when they are noise
        print(f"obturator: warning: Sobol indices: {line}", file=sys.stderr)
    return 0


# --------------------------------------------------------------------------- optimize


def _run_optimize(args: argparse.Namespace) -> int:
    import xarray as xr

    from ..envelope.model import TIMES
    from ..envelope.optimize import (
        DEFAULT_BOUNDS,
        DESIGN_VARIABLES,
        DesignProblem,
        optimise,
        split_objective,
    )
    from ..envelope.pareto import pareto_front
    from ..sweeps import parse_axis
    from ..sweeps.distributions import split_assignment

    _check_out(args)
    if args.figure and not args.pareto:
        raise InputError("--figure", "draws the Pareto front: give --pareto N with it")
    event, aggregate = split_objective(args.objective)
    model = model_from_args(args).with_(event=TIMES[event])
    names = [v.strip() for v in args.variables.split(",") if v.strip()]
    bounds: dict[str, tuple[float, float]] = {}
    for name in names:
        if name not in DESIGN_VARIABLES:
            raise InputError("--variables", f"{name!r}; allowed: {', '.join(DESIGN_VARIABLES)}")
        bounds[name] = DEFAULT_BOUNDS[name]
    for text in args.bound or []:
        name, lo, hi = split_assignment(text, "--bound", "NAME=LO,HI", ",")
        name = name.strip().replace("-", "_")
        if name not in bounds:
            raise InputError("--bound", f"{name!r} is not among --variables")
        bounds[name] = _bound(name, lo, hi, DESIGN_VARIABLES[name])
    machs = parse_axis(args.grid_mach, "--mach", "")
    alts = parse_axis(args.grid_altitude, "--altitude-m", "m")
    conditions = tuple({"mach": float(m), "altitude_m": float(h)} for m in machs for h in alts)
    problem = DesignProblem(
        model,
        conditions,
        bounds,
        objective=aggregate,
        mass_budget=None
        if args.mass_budget is None
        else quantity("--mass-budget", args.mass_budget, "kg"),
        wall=None if args.wall is None else quantity("--wall", args.wall, "m"),
        block_margin_deg=quantity("--block-margin-deg", args.block_margin_deg, "deg"),
    )
    seed = _int("--seed", args.seed, 0)
    identity = {"study": "optimize", "problem": problem.identity(), "seed": seed}
    runner = study_runner(args, identity)
    t0 = time.perf_counter()
    try:
        res = optimise(
            problem,
            runner,
            seed=seed,
            popsize=_int("--popsize", args.popsize, 2),
            maxiter=_int("--maxiter", args.maxiter),
            polish=not args.no_polish,
        )
        front = (
            pareto_front(res, runner, points=_int("--pareto", args.pareto, 2))
            if args.pareto
            else None
        )
    finally:
        runner.close()
    elapsed = time.perf_counter() - t0
    summary = res.to_dict()
    cond = ("condition",)
    data: dict[str, Any] = {
        "mach": (cond, machs.repeat(alts.size)),
        "altitude_m": (cond, np.tile(alts, machs.size), {"units": "m"}),
        "t_cr_optimum": (cond, np.array(res.optimum["t_cr"]), {"units": "s"}),
        "status_optimum": (cond, np.array(res.optimum["status"], dtype=np.int8)),
        "t_cr_baseline": (cond, np.array(res.baseline["t_cr"]), {"units": "s"}),
        "status_baseline": (cond, np.array(res.baseline["status"], dtype=np.int8)),
    }
    for k, name in enumerate(problem.names):
        data[f"optimum_{name}"] = ((), float(res.x[k]), {"units": DESIGN_VARIABLES[name]})
    attrs = {
        "title": "robust obturator design",
        "objective": problem.objective,
        "event": problem.model.event,
        "optimum_objective_s": res.optimum["objective"],
        "baseline_objective_s": res.baseline["objective"],
        "improvement": res.improvement,
        "optimum_mass_kg": res.mass,
        "baseline_mass_kg": res.baseline_mass,
        "mass_budget_kg": float(problem.mass_budget),  # type: ignore[arg-type]
        "load": model.load,
        "sensitivity": json.dumps(res.sensitivity),
    }
    ds = xr.Dataset(data, attrs=attrs)
    if front is not None:
        for k in front.data_vars:
            ds[f"pareto_{k}"] = front[k].rename(point="pareto_point")
        ds.attrs["pareto_degenerate"] = int(front.attrs["degenerate"])
    write_dataset(args, runner, ds)
    if args.figure and front is not None:
        from ..envelope.figures import plot_pareto

        plot_pareto(front, args.figure)
    if front is not None:
        from ..envelope.figures import pareto_collapse

        summary["pareto"] = {
            "mass_kg": front["mass"].values.tolist(),
            "objective_s": front["objective"].values.tolist(),
            "feasible": front["feasible"].values.tolist(),
            "degenerate": bool(front.attrs["degenerate"]),
            "collapsed": pareto_collapse(front),
        }
    summary["elapsed_s"] = elapsed
    if args.json:
        print(_json.dumps(summary))
        return 0
    _print_optimum(problem, res, summary, elapsed, runner)
    return 0


def _time_name(event: str) -> str:
    """The command line's name of a model event (t_cr, t_start, t_start_late)."""
    from ..envelope.model import TIMES

    return next(name for name, ev in TIMES.items() if ev == event)


def _bound(name: str, lo: str, hi: str, unit: str) -> tuple[float, float]:
    """LO, HI of ``--bound``, read as a sweep axis reads a list: a unit after HI applies to
    both (``gap=40,60 um``), a unit on LO alone is refused; inside the registry's range
    where it does not depend on the ball (mu_s, density, ball radius)."""
    from ..params import PARAMS
    from ..sweeps.distributions import parse_distribution_args

    pint_unit = "" if unit == "1" else unit.replace(" ", "*")
    try:
        d = parse_distribution_args(name, "uniform", f"{lo},{hi}", pint_unit)
    except InputError as exc:
        if "LO < HI" not in str(exc):
            raise
        raise InputError(name, f"bounds {lo.strip()}, {hi.strip()} are empty (LO < HI)") from None
    par = PARAMS.get(name)
    if par is not None and par.range is not None and name in ("mu_s", "density", "ball_radius"):
        for x in d.params:
            if not par.range.contains(x):
                u = "" if unit == "1" else f" {unit}"
                raise InputError(
                    name, f"bound {x:g}{u} is outside the allowed range {par.range}{u}"
                )
    return d.params[0], d.params[1]


def _print_optimum(problem: Any, res: Any, s: dict[str, Any], elapsed: float, runner: Any) -> None:
    from ..envelope.optimize import DESIGN_VARIABLES

    base = problem.values(problem.baseline())
    print(
        f"objective: {problem.objective} of "
        f"{_time_name(problem.model.event)} over "
        f"{len(problem.conditions)} conditions "
        f"({problem.model.load} load)"
    )
    print(f"{'variable':>12} {'Table 1':>11} {'optimum':>11} {'unit':>7} {'dJ/dx*x/J':>10} active")
    for k, name in enumerate(problem.names):
        sens = res.sensitivity[name]
        print(
            f"{name:>12} {base[name]:11.5g} {res.x[k]:11.5g} {DESIGN_VARIABLES[name]:>7} "
            f"{sens['elasticity']:10.3f} {sens['active'] or '-'}"
        )
    from ..envelope.optimize import CONSTRAINT_NAMES

    active = [n for n, g in zip(CONSTRAINT_NAMES, res.constraints, strict=True) if g < 1e-6]
    print(
        f"ball mass {1e3 * res.baseline_mass:.3f} g -> {1e3 * res.mass:.3f} g "
        f"(budget {1e3 * float(problem.mass_budget):.3f} g); active constraints: "
        + ("; ".join(active) or "none")
    )
    t = _time_name(problem.model.event)
    print(f"condition         {t:>7} Table 1 [s] {t:>7} optimum [s]")
    for c, tb, to, sb, so in zip(
        problem.conditions,
        res.baseline["t_cr"],
        res.optimum["t_cr"],
        res.baseline["status"],
        res.optimum["status"],
        strict=True,
    ):
        print(f"M {c['mach']:<5g} {c['altitude_m']:>7g} m   {tb:12.6g} ({sb})   {to:12.6g} ({so})")
    print(
        f"{problem.objective}: {res.baseline['objective']:.6g} s -> "
        f"{res.optimum['objective']:.6g} s "
        f"({100 * res.improvement:.1f} % better); status 1 = opened and converged"
    )
    if "pareto" in s:
        p = s["pareto"]
        pts = ", ".join(
            f"{1e3 * m:.3f} g: {o:.5g} s"
            for m, o in zip(p["mass_kg"], p["objective_s"], strict=True)
        )
        print(f"Pareto front (mass: objective){' (degenerate)' if p['degenerate'] else ''}: {pts}")
        if p.get("collapsed"):
            print(f"Pareto front: {p['collapsed']}")
    print(f"{res.n_evaluations} designs evaluated in {elapsed:.1f} s ({res.message})")


# --------------------------------------------------------------------------- register


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``probability``, ``sensitivity`` and ``optimize`` sub-commands."""
    add_robust_commands(subparsers, _run_probability, _run_sensitivity, _run_optimize)
