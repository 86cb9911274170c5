"""``obturator montecarlo``: t_cr quantiles under uncertain inputs.

Usage::

    obturator montecarlo --case spin-rig|flight --samples N [--seed S]
        --vary NAME=KIND:ARGS [--vary ...] [--spin-rate X] [--mu-s X] ...
        [--quantiles 5,50,95] [--confidence 0.95] [--workers N]
        [--scheduler ADDRESS] [--out FILE.nc] [--csv FILE.csv] [--json]

Monte Carlo distributions (``--vary``): ``normal:MEAN,SD``, ``uniform:LO,HI``,
``lognormal:MEDIAN,SIGMA_LN``, ``truncnormal:MEAN,SD,LO,HI``. Quantile
confidence intervals are distribution-free order-statistic intervals. Every
opening is checked for convergence by default; non-converged openings (status
4) are kept but excluded from the quantiles and the mean.
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from ..errors import InputError, check_range
from ..io import check_output_path
from ..params import SWEEP_PARAMS
from ..sweeps import MAX_SAMPLES, MonteCarloSummary, monte_carlo_summary, monte_carlo_table
from ..units import parse_quantity
from . import _json
from ._args import (
    fmt_seconds,
    parse_integer,
    parse_number,
    study_config,
    study_options,
    study_t_max,
    warn_far_from_data,
    warn_outside_data,
)
from ._flags import (
    CONFIDENCE,
    CSV,
    OUT_NETCDF,
    SEED_FLAG,
    VARY,
    command,
    convergence_flags,
    count,
    option,
    parameter_flags,
    study_flags,
)
from ._kinds import Text
from ._runner import runner_from_args

__all__ = ["register"]


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
                fmt_seconds(q.value, ">t_max"),
                f"[{fmt_seconds(q.lower)}, {fmt_seconds(q.upper)}]",
                f"{q.coverage:.3f}",
            )
        )
    widths = [max(len(r[i]) for r in rows) for i in range(4)]
    for r in rows:
        print("  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)))


def _lowest(text: str) -> float:
    """A low end of a ``--vary`` distribution's draws (its lower bound, or 3 SD below)."""
    from ..sweeps.distributions import parse_distribution

    d = parse_distribution(text)[1]
    p = d.params
    if d.kind == "uniform":
        return p[0]
    if d.kind == "lognormal":
        return p[0] * math.exp(-3.0 * p[1])
    low = p[0] - 3.0 * p[1]
    return max(low, p[2]) if d.kind == "truncnormal" else low


def _warn_far_from_data(args: argparse.Namespace, fixed: dict[str, float]) -> None:
    """The far-from-data warning of ``simulate`` for the study's lowest likely spin."""
    from ..sweeps import SweepSpec

    low = None
    for text in args.vary:
        if text.split("=", 1)[0].strip().lstrip("-").replace("-", "_") == "spin_rate":
            low = max(_lowest(text), 1e-6)
    spec = SweepSpec(
        args.case,
        {},
        {k: v for k, v in fixed.items() if low is None or k != "spin_rate"},
        torque_model=args.torque_model,
        spin_mode=args.spin_mode,
        speed_law=args.speed_law,
        base=args.base,
    )
    warn_far_from_data(spec, low)


def _run_montecarlo(args: argparse.Namespace) -> int:
    varied = {v.split("=", 1)[0].strip().lstrip("-").replace("-", "_") for v in args.vary}
    from_config = {k: v for k, v in study_config(args, "montecarlo").items() if k not in varied}
    fixed = from_config | {
        name: parse_quantity(name, getattr(args, name), par.pint_unit)
        for name, par in SWEEP_PARAMS.items()
        if getattr(args, name) is not None
    }
    quantiles = [
        parse_number("quantiles", q) / 100.0 for q in str(args.quantiles).split(",") if q.strip()
    ]
    if not quantiles:
        raise InputError("quantiles", "give at least one percentile")
    for q in quantiles:
        check_range("quantiles", 100 * q, 0.0, 100.0, lo_open=True, hi_open=True, unit="%")
    confidence = parse_number("confidence", args.confidence)
    samples = parse_integer("samples", args.samples, 1)
    seed = parse_integer("seed", args.seed, 0)
    _warn_far_from_data(args, fixed)
    runner = runner_from_args(args)
    check_output_path("out", args.out)
    check_output_path("csv", args.csv)
    t0 = time.perf_counter()
    ds = monte_carlo_table(
        args.case,
        args.vary,
        samples=samples,  # type: ignore[arg-type]
        seed=seed,  # type: ignore[arg-type]
        fixed=fixed,
        torque_model=args.torque_model,
        spin_mode=args.spin_mode,
        speed_law=args.speed_law,
        base=args.base,
        options=study_options(args),
        t_max=study_t_max(args),
        quantiles=quantiles,
        confidence=confidence,
        runner=runner,
        csv=args.csv,
        check_convergence=args.convergence_check,
    )
    wall = time.perf_counter() - t0
    warn_outside_data(ds)
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


register = command(
    "montecarlo",
    _run_montecarlo,
    "Sample uncertain inputs (--vary NAME=KIND:ARGS, KIND one of normal:MEAN,SD "
    "uniform:LO,HI lognormal:MEDIAN,SIGMA_LN truncnormal:MEAN,SD,LO,HI) and report t_cr "
    "quantiles with order-statistic confidence intervals.",
    count(
        "--samples",
        1,
        MAX_SAMPLES,
        f"number of samples (at most {MAX_SAMPLES}: see obturator.sweeps.MAX_SAMPLES)",
        example=2,
        required=True,
    ),
    SEED_FLAG.but(help="root seed (default 0)"),
    VARY.but(
        required=True,
        type=Text(example="mu_s=uniform:0.5,0.6"),
        help="uncertain input, e.g. mu_s=normal:0.5473,0.03 (repeatable)",
    ),
    *parameter_flags(grid=False),
    option(
        "--quantiles",
        metavar="P,P,...",
        default="5,50,95",
        type=Text(example="50"),
        help="percentiles (default 5,50,95)",
    ),
    CONFIDENCE.but(metavar="X", help="interval level (0.95)"),
    *study_flags(),
    OUT_NETCDF.but(help="write samples and summary as NetCDF"),
    *convergence_flags(
        True,
        "the per-sample reruns with tolerances / 10, friction width / 10 and another "
        "regularisation family; skipping them is 4x faster, and non-converged openings "
        "(status 4) are then not detected",
    ),
    CSV.but(help="write the samples as CSV"),
)
