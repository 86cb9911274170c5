"""``obturator sweep`` and ``obturator montecarlo``: parameter studies of t_cr.

Usage::

    obturator sweep --case spin-rig|flight [--spin-rate SPEC] [--mu-s SPEC]
        [--theta0-deg SPEC] [--density SPEC] [--hole-radius SPEC] [--gap SPEC]
        [--mach SPEC] [--altitude-m SPEC] [--torque-model thesis|coulomb]
        [--spin-mode constant|free|thesis-energy] [--rtol X] [--atol X]
        [--method rosenbrock|radau] [--t-max S] [--workers N]
        [--scheduler ADDRESS] [--chunk-size N] --out FILE.nc [--csv FILE.csv]
        [--no-csv] [--restart] [--no-progress] [--json]

    obturator montecarlo --case spin-rig|flight --samples N [--seed S]
        --vary NAME=KIND:ARGS [--vary ...] [--spin-rate X] [--mu-s X] ...
        [--quantiles 5,50,95] [--confidence 0.95] [--workers N]
        [--scheduler ADDRESS] [--out FILE.nc] [--csv FILE.csv] [--json]

A sweep SPEC is ``START:STOP:COUNT`` (COUNT evenly spaced values, both ends
included) or a comma list ``a,b,c``; a single value holds that parameter fixed
instead of adding a dimension. Values are SI (spin rate in rad/s, radii and gap
in m, density in kg/m^3, angles in degrees where the flag says ``-deg``).

The sweep writes NetCDF to ``--out``; a CSV table goes to ``--csv`` when
given, and otherwise automatically next to the NetCDF (same name, ``.csv``)
for sweeps of at most 10,000 points (``--no-csv`` turns that off). While it
runs, finished chunks are kept in ``FILE.nc.partial.jsonl``: re-running the
same command after an interruption computes only the missing points; a
different sweep with the same ``--out`` is refused unless ``--restart``.

Monte Carlo distributions (``--vary``): ``normal:MEAN,SD``, ``uniform:LO,HI``,
``lognormal:MEDIAN,SIGMA_LN``, ``truncnormal:MEAN,SD,LO,HI``. Quantile
confidence intervals are distribution-free order-statistic intervals.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

from . import _json
from ..model.cases import CASE_NAMES, TORQUE_MODELS
from ..errors import InputError, check_range
from ..io import check_output_path, parse_quantity, study_settings
from ..solve import FRICTION_FAMILIES, SolverOptions
from ..sweeps.spec import (
    PARAMETERS,
    MonteCarloSummary,
    SweepSpec,
    execute_sweep,
    monte_carlo,
    monte_carlo_summary,
    parse_axis,
    sweep_summary,
)

__all__ = ["register", "AUTO_CSV_MAX_POINTS"]

#: Sweeps up to this many points get a CSV next to the NetCDF automatically.
AUTO_CSV_MAX_POINTS = 10_000

_SPIN_MODES = ("constant", "free", "thesis-energy")
_METHODS = ("auto", "radau", "rosenbrock")  # as obturator.solve


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def _add_common(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--case", choices=CASE_NAMES, default=None, help="Table 1 column (default spin-rig)"
    )
    p.add_argument("--torque-model", choices=TORQUE_MODELS, default=None)
    p.add_argument("--spin-mode", choices=_SPIN_MODES, default=None)
    p.add_argument(
        "--config", metavar="FILE.toml", help="settings (schema in obturator.io; flags win)"
    )
    p.add_argument("--rtol", metavar="X", help="relative tolerance (default 1e-8)")
    p.add_argument("--atol", metavar="X", help="absolute tolerance (default rtol/100, or 1e-10)")
    p.add_argument("--method", choices=_METHODS, default=None, help="integrator")
    p.add_argument(
        "--friction-width", metavar="X", help="regularisation width / omega_p (default 1e-7)"
    )
    p.add_argument(
        "--friction-family",
        choices=tuple(FRICTION_FAMILIES),
        default=None,
        help="regularisation family (default algebraic)",
    )
    p.add_argument("--t-max", metavar="S", help="give up after this time [s]")
    p.add_argument(
        "--workers", metavar="N", help="local worker processes (default: all CPUs; 1: in-process)"
    )
    p.add_argument(
        "--scheduler", metavar="ADDRESS", help="dask.distributed scheduler, e.g. tcp://host:8786"
    )
    p.add_argument("--chunk-size", metavar="N", help="points per task (default: automatic)")
    p.add_argument(
        "--restart", action="store_true", help="discard partial results of a different study"
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print one JSON object")


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``sweep`` and ``montecarlo`` sub-commands."""
    p = subparsers.add_parser(
        "sweep",
        help="t_cr on a grid of parameters (parallel, resumable)",
        description="Evaluate the opening time t_cr on the Cartesian grid of the given "
        "parameters. SPEC is START:STOP:COUNT (both ends included) or a list a,b,c; "
        "a single value fixes the parameter. SI units.",
    )
    for name, par in PARAMETERS.items():
        extra = " (flight only)" if par.flight_only else ""
        p.add_argument(
            _flag(name), dest=name, metavar="SPEC", help=f"{par.long_name} [{par.unit}]{extra}"
        )
    _add_common(p)
    p.add_argument("--out", metavar="FILE.nc", required=True, help="NetCDF output")
    p.add_argument(
        "--check-convergence",
        action="store_true",
        help="re-run each opened point with tolerances / 10, friction width / 10 and another "
        "regularisation family and mark points whose t_cr moves by more than 1e-3 "
        "(status 2; 4x the cost)",
    )
    p.add_argument("--csv", metavar="FILE.csv", help="also write a CSV table")
    p.add_argument(
        "--no-csv",
        action="store_true",
        help=f"no automatic CSV next to the NetCDF (written for <= {AUTO_CSV_MAX_POINTS} points)",
    )
    p.set_defaults(func=_run_sweep)

    m = subparsers.add_parser(
        "montecarlo",
        help="t_cr quantiles under uncertain inputs",
        description="Sample uncertain inputs (--vary NAME=KIND:ARGS, KIND one of "
        "normal:MEAN,SD uniform:LO,HI lognormal:MEDIAN,SIGMA_LN truncnormal:MEAN,SD,LO,HI) "
        "and report t_cr quantiles with order-statistic confidence intervals.",
    )
    m.add_argument("--samples", metavar="N", required=True, help="number of samples")
    m.add_argument("--seed", metavar="S", default="0", help="root seed (default 0)")
    m.add_argument(
        "--vary",
        metavar="NAME=KIND:ARGS",
        action="append",
        required=True,
        help="uncertain input, e.g. mu_s=normal:0.5473,0.03 (repeatable)",
    )
    for name, par in PARAMETERS.items():
        extra = " (flight only)" if par.flight_only else ""
        m.add_argument(
            _flag(name), dest=name, metavar="X", help=f"fixed {par.long_name} [{par.unit}]{extra}"
        )
    m.add_argument(
        "--quantiles", metavar="P,P,...", default="5,50,95", help="percentiles (default 5,50,95)"
    )
    m.add_argument("--confidence", metavar="X", default="0.95", help="interval level (0.95)")
    _add_common(m)
    m.add_argument("--out", metavar="FILE.nc", help="write samples and summary as NetCDF")
    m.add_argument(
        "--no-check-convergence",
        action="store_true",
        help="skip the per-sample convergence check (4x faster; non-converged openings, "
        "status 2, are then not detected)",
    )
    m.add_argument("--csv", metavar="FILE.csv", help="write the samples as CSV")
    m.set_defaults(func=_run_montecarlo)


# --------------------------------------------------------------------------- helpers


def _number(field: str, text: str) -> float:
    try:
        x = float(text)
    except (TypeError, ValueError):
        raise InputError(field, f"expected a number, got {text!r}") from None
    if not math.isfinite(x):
        raise InputError(field, f"expected a finite number, got {text!r}")
    return x


def _integer(field: str, text: str | None, lo: int) -> int | None:
    if text is None:
        return None
    try:
        n = int(text)
    except ValueError:
        raise InputError(field, f"expected a whole number, got {text!r}") from None
    if n < lo:
        raise InputError(field, f"{n} is outside the allowed range >= {lo}")
    return n


_STUDY_KEYS = (*PARAMETERS, "case", "torque_model", "spin_mode", "t_max")


def _settings(args: argparse.Namespace, command: str) -> dict[str, Any]:
    """Config settings merged under the flags: case, models, t_max and fixed values."""
    conf = study_settings(args.config, command, _STUDY_KEYS)
    args.case = args.case or conf.get("case", "spin-rig")
    args.torque_model = args.torque_model or conf.get("torque_model", "thesis")
    args.spin_mode = args.spin_mode or conf.get("spin_mode", "constant")
    if args.t_max is None and "t_max" in conf:
        args.t_max = repr(conf["t_max"])
    for key, value in conf.get("solver", {}).items():
        if getattr(args, key, None) is None:
            setattr(args, key, value if isinstance(value, str) else repr(value))
    return {k: float(v) for k, v in conf.items() if k in PARAMETERS}


def _options(args: argparse.Namespace) -> SolverOptions:
    kw: dict[str, Any] = {}
    if args.rtol is not None:
        kw["rtol"] = _number("rtol", args.rtol)
        kw["atol"] = kw["rtol"] * 1e-2
    if args.atol is not None:
        kw["atol"] = _number("atol", args.atol)
    if args.method is not None:
        kw["method"] = args.method
    if args.friction_width is not None:
        kw["friction_width"] = _number("friction_width", args.friction_width)
    if args.friction_family is not None:
        kw["friction_family"] = args.friction_family
    if getattr(args, "formulation", None) is not None:
        kw["formulation"] = args.formulation
    return SolverOptions(**kw)


def _t_max(args: argparse.Namespace) -> float | None:
    if args.t_max is None:
        return None
    return check_range("t_max", _number("t_max", args.t_max), 0.0, lo_open=True, unit="s")


def _check_dir(field: str, path: str | None) -> None:
    check_output_path(field, path)


def _progress(args: argparse.Namespace) -> bool:
    return not args.no_progress and sys.stderr.isatty()


def _fmt_s(x: float, infinite: str = "-") -> str:
    """Seconds; NaN and -inf as "-", +inf as `infinite`."""
    if math.isfinite(x):
        return f"{x:.6g}"
    return infinite if x > 0 else "-"


# --------------------------------------------------------------------------- sweep


def _run_sweep(args: argparse.Namespace) -> int:
    axes: dict[str, Any] = {}
    fixed: dict[str, float] = _settings(args, "sweep")
    for name in PARAMETERS:
        text = getattr(args, name)
        if text is None:
            continue
        values = parse_axis(text, name, PARAMETERS[name].unit)
        fixed.pop(name, None)  # the flag wins over the config
        if values.size == 1:
            fixed[name] = float(values[0])
        else:
            axes[name] = values
    spec = SweepSpec(
        args.case,
        axes,
        fixed,
        torque_model=args.torque_model,
        spin_mode=args.spin_mode,
        options=_options(args),
        t_max=_t_max(args),
        check_convergence=args.check_convergence,
    )
    workers = _integer("workers", args.workers, 1)
    chunk = _integer("chunk_size", args.chunk_size, 1)
    _check_dir("out", args.out)
    csv_path = args.csv
    if csv_path is None and not args.no_csv and spec.n_points <= AUTO_CSV_MAX_POINTS:
        csv_path = str(Path(args.out).with_suffix(".csv"))
    _check_dir("csv", csv_path)
    t0 = time.perf_counter()
    run = execute_sweep(
        spec,
        workers=workers,
        scheduler=args.scheduler,
        store=args.out,
        restart=args.restart,
        chunk_size=chunk,
        progress=_progress(args),
        csv=csv_path,
    )
    wall = time.perf_counter() - t0
    summ = sweep_summary(run.dataset)
    rate = run.n_computed / run.elapsed_s if run.elapsed_s > 0 else math.inf
    if args.json:
        print(
            _json.dumps(
                {
                    **summ,
                    "out": args.out,
                    "csv": csv_path,
                    "n_computed": run.n_computed,
                    "n_resumed": run.n_resumed,
                    "workers": run.workers,
                    "backend": run.backend,
                    "compute_s": run.elapsed_s,
                    "wall_s": wall,
                    "points_per_s": rate,
                    "settings": spec.identity(),  # every input used, and the version
                }
            )
        )
        return 0
    dims = ", ".join(f"{d} x{n}" for d, n in zip(spec.dims, spec.shape, strict=True))
    where = (
        "dask"
        if run.backend != "local"
        else f"{run.workers} worker" + ("s" if run.workers != 1 else "")
    )
    resumed = f", {run.n_resumed} resumed" if run.n_resumed else ""
    if summ["t_cr_min_s"] is None:
        trange = "no point opened"
    else:
        at = ", ".join(f"{k}={v:g}" for k, v in summ["argmin"].items())
        trange = f"t_cr {summ['t_cr_min_s']:.6g}..{summ['t_cr_max_s']:.6g} s" + (
            f" (min at {at})" if at else ""
        )
    files = args.out + (f", {csv_path}" if csv_path else "")
    print(
        f"sweep {spec.case}: {summ['n_points']} points ({dims or 'single point'}{resumed}) "
        f"in {run.elapsed_s:.3g} s on {where} ({rate:.3g} points/s); "
        f"{summ['n_opened'] + summ['n_unconverged']} opened"
        + (f" ({summ['n_unconverged']} not converged)" if spec.check_convergence else "")
        + f", {summ['n_not_opened']} not opened by t_max, "
        f"{summ['n_failed'] + summ['n_invalid']} failed; {trange}; wrote {files}"
    )
    return 0


# --------------------------------------------------------------------------- Monte Carlo


def _print_mc(s: MonteCarloSummary, header: str) -> None:
    pct = f"{100 * s.confidence:g}%"
    print(header)
    lo, hi = s.fraction_not_opened_ci
    print(
        f"opened {s.n_opened}, not opened by t_max = {s.t_max:g} s: {s.n_not_opened} "
        f"({100 * s.fraction_not_opened:.3g} %, {pct} CI {100 * lo:.3g}-{100 * hi:.3g} %), "
        f"failed {s.n_failed + s.n_invalid}, opened but not converged (excluded) "
        f"{s.n_unconverged}"
    )
    if math.isfinite(s.mean_s):
        sd = f", sd {s.std_s:.4g} s" if math.isfinite(s.std_s) else ""
        print(f"mean t_cr of opened samples {s.mean_s:.6g} s{sd}")
    rows = [("quantile", "t_cr [s]", f"{pct} CI [s]", "coverage")]
    for q in s.quantiles:
        rows.append(
            (
                f"{100 * q.probability:g} %",
                _fmt_s(q.value, ">t_max"),
                f"[{_fmt_s(q.lower)}, {_fmt_s(q.upper)}]",
                f"{q.coverage:.3f}",
            )
        )
    widths = [max(len(r[i]) for r in rows) for i in range(4)]
    for r in rows:
        print("  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)))


def _run_montecarlo(args: argparse.Namespace) -> int:
    varied = {v.split("=", 1)[0].strip().lstrip("-").replace("-", "_") for v in args.vary}
    from_config = {k: v for k, v in _settings(args, "montecarlo").items() if k not in varied}
    fixed = from_config | {
        name: parse_quantity(name, getattr(args, name), "" if par.unit == "1" else par.unit)
        for name, par in PARAMETERS.items()
        if getattr(args, name) is not None
    }
    quantiles = [
        _number("quantiles", q) / 100.0 for q in str(args.quantiles).split(",") if q.strip()
    ]
    if not quantiles:
        raise InputError("quantiles", "give at least one percentile")
    for q in quantiles:
        check_range("quantiles", 100 * q, 0.0, 100.0, lo_open=True, hi_open=True, unit="%")
    confidence = _number("confidence", args.confidence)
    samples = _integer("samples", args.samples, 1)
    seed = _integer("seed", args.seed, 0)
    workers = _integer("workers", args.workers, 1)
    chunk = _integer("chunk_size", args.chunk_size, 1)
    _check_dir("out", args.out)
    _check_dir("csv", args.csv)
    t0 = time.perf_counter()
    ds = monte_carlo(
        args.case,
        args.vary,
        samples=samples,  # type: ignore[arg-type]
        seed=seed,  # type: ignore[arg-type]
        fixed=fixed,
        torque_model=args.torque_model,
        spin_mode=args.spin_mode,
        options=_options(args),
        t_max=_t_max(args),
        quantiles=quantiles,
        confidence=confidence,
        workers=workers,
        scheduler=args.scheduler,
        store=args.out,
        restart=args.restart,
        chunk_size=chunk,
        progress=_progress(args),
        csv=args.csv,
        check_convergence=not args.no_check_convergence,
    )
    wall = time.perf_counter() - t0
    summ = monte_carlo_summary(ds)
    if args.json:
        d = summ.to_dict()
        d.update(
            {
                "case": args.case,
                "distributions": ds.attrs["distributions"],
                "seed": seed,
                "wall_s": wall,
                "out": args.out,
                "settings": {
                    k: v.item() if hasattr(v, "item") else v
                    for k, v in ds.attrs.items()
                    if np.ndim(v) == 0
                },
            }
        )
        print(_json.dumps(d))
        return 0
    header = (
        f"montecarlo {args.case}: {samples} samples, seed {seed}, {ds.attrs['distributions']}"
        f" ({wall:.3g} s)"
    )
    _print_mc(summ, header)
    return 0
