"""``obturator design-experiment``: which rig runs decide between the mechanisms (issue 29).

Runs :func:`obturator.design_experiment`: the candidates' Laplace posteriors from their
fits to the measured runs, a surrogate of t_cr from exact solves on the candidate grid,
the Box-Hill plan of each size N, and simulated campaigns of the designed and the naive
plans. Prints the recommended campaign, the decision table and what each setting tests
(``--json``: one object); ``--out FILE.nc`` keeps everything (and resumes an interrupted
study), ``--figure`` draws the predictions over each setting with the planned points.
"""

from __future__ import annotations

import argparse
import math
import time

from ..errors import InputError
from ..params import Range
from . import _json
from ._flags import (
    JSON,
    OUT_NETCDF,
    RIG_DATA,
    RIG_HORIZON,
    SEED_FLAG,
    Flag,
    command,
    count,
    execution_flags,
    option,
    quantity_option,
)
from ._kinds import Count, OutputFile, Text
from ._runner import study_runner, write_dataset

__all__ = ["register"]

_HOLE_MAX = 7.899e-3 / math.sqrt(2.0)  # r_s <= R_s / sqrt(2) [m]


def _pair(name: str, unit: str, rng: Range, what: str, ex: str) -> tuple[Flag, ...]:
    return tuple(
        quantity_option(
            f"--{name}-{end}",
            unit,
            rng,
            ex,
            f"{'lowest' if end == 'min' else 'highest'} {what} [{unit}]",
            metavar=unit.upper().replace("/", "_").replace("^", ""),
        )
        for end in ("min", "max")
    )


def _points(name: str, default: str, what: str) -> Flag:
    text = f"grid points of the {what} ({default}; the Table 1 value is added)"
    return count(f"--{name}-points", 1, 50, text, example=2, default=default)


def _sizes(text: str) -> list[int]:
    out = []
    for part in text.split(","):
        try:
            n = int(part.strip())
        except ValueError:
            raise InputError("--runs", f"{part.strip()!r} is not a whole number") from None
        if not 1 <= n <= 200:
            raise InputError("--runs", f"{n} is outside the allowed range [1, 200]")
        out.append(n)
    return sorted(set(out))


def _range(args: argparse.Namespace, name: str, default: tuple[float, float]) -> tuple:
    attr = name.replace("-", "_")
    lo, hi = getattr(args, f"{attr}_min"), getattr(args, f"{attr}_max")
    lo = default[0] if lo is None else lo
    hi = default[1] if hi is None else hi
    if lo > hi:
        raise InputError(f"--{name}-min", f"{lo:g} is above --{name}-max {hi:g}")
    return (lo, hi)


def _run(args: argparse.Namespace) -> int:
    from ..calibration.data import CASE_COLUMNS, load_spin_rig_csv, load_thesis_data
    from ..design import DEFAULT_DESIGN_MODELS, SettingRanges, design_experiment
    from ..validation.candidates import get_candidates

    names = [c.name for c in get_candidates(args.models or ",".join(DEFAULT_DESIGN_MODELS))]
    sizes = _sizes(args.runs)
    d = SettingRanges()
    ranges = SettingRanges(
        spin_rate=_range(args, "spin", d.spin_rate),
        theta0_deg=_range(args, "theta0", d.theta0_deg),
        hole_radius=_range(args, "hole-radius", d.hole_radius),
        density=_range(args, "density", d.density),
        n_spin=args.spin_points,
        n_theta0=args.theta0_points,
        n_hole=args.hole_radius_points,
        n_density=args.density_points,
    )
    data = load_spin_rig_csv(args.data, columns=CASE_COLUMNS) if args.data else load_thesis_data()
    identity = {
        "study": "design-experiment",
        "models": names,
        "ranges": ranges.to_dict(),
        "runs": sizes,
        "campaigns": args.campaigns,
        "seed": args.seed,
        "t_max_s": args.t_max,
        "data": data.source,
        "n_data": int(data.spin_rate.size),
        "release_sd_deg": args.release_sd,
    }
    runner = study_runner(args, identity)
    t0 = time.perf_counter()
    try:
        result = design_experiment(
            names,
            ranges=ranges,
            n_runs=sizes,
            campaigns=args.campaigns,
            seed=args.seed,
            data=data,
            runner=runner,
            t_max=args.t_max,
            release_sd_deg=args.release_sd,
        )
    finally:
        runner.close()
    wall = time.perf_counter() - t0
    if args.figure:
        from ..design.plotting import save_design_figure

        save_design_figure(result, args.figure)
    write_dataset(args, runner, result.to_dataset())
    if args.json:
        print(_json.dumps({**result.to_dict(), "wall_s": wall}))
    else:
        from ..design.textreport import format_design

        print(format_design(result))
    return 0


register = command(
    "design-experiment",
    _run,
    "Optimal experiment design for model discrimination on the spin rig: "
    "Box-Hill criterion over spin, release angle, hole radius and ball density, checked "
    "by simulated campaigns against a naive plan (spins spread as Appendix B).",
    option(
        "--models",
        metavar="NAME,...",
        type=Text(example="strengthening,theta0"),
        help="candidates, comma-separated (default strengthening,theta0; "
        "obturator validate --list-models)",
    ),
    option(
        "--runs",
        metavar="N,...",
        default="1,2,3,5,10,20",
        type=Text(example="5,10"),
        help="campaign sizes to plan and simulate (1,2,3,5,10,20; each 1-200)",
    ),
    count(
        "--campaigns",
        10,
        100_000,
        "simulated campaigns per generating model and plan (200; at least 10)",
        default="200",
    ),
    SEED_FLAG.but(default="1", type=Count(0, 2**32 - 1), help="random seed (1)"),
    *_pair("spin", "rad/s", Range(20.0, 2000.0), "spin rate (90, 450)", "200 rad/s"),
    *_pair("theta0", "deg", Range(45.0, 89.5), "release angle as set (70, 89)", "80 deg"),
    *_pair("hole-radius", "m", Range(1e-3, _HOLE_MAX), "hole radius (3.75, 5.58 mm)", "4 mm"),
    *_pair("density", "kg/m^3", Range(1000.0, 20000.0), "ball density (6000, 10000)", "8000"),
    _points("spin", "8", "spin rates (geometric)"),
    _points("theta0", "3", "release angles"),
    _points("hole-radius", "2", "hole radii"),
    _points("density", "2", "densities"),
    quantity_option(
        "--release-sd",
        "deg",
        Range(0.0, 10.0),
        "0.1 deg",
        "repeatability (SD) of the release angle, if measured [deg] (default: the "
        "largest the replicate scatter allows, about 0.9 deg on Appendix B)",
        metavar="DEG",
    ),
    RIG_DATA.but(
        help="measured runs in the calibrate CSV format (default: thesis Appendix B)",
    ),
    RIG_HORIZON.but(help="horizon [s] (20)"),
    option(
        "--figure",
        metavar="FILE.png",
        type=OutputFile(figure=True, example="design.png"),
        help="predictions over each setting with bands and the planned runs",
    ),
    JSON,
    OUT_NETCDF.but(type=OutputFile(suffixes=("nc",), example="design.nc")),
    *execution_flags(),
)
