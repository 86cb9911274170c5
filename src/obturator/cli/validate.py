"""``obturator validate``: fit candidate mechanisms to all spin-rig runs and rank them."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..errors import InputError, check_range
from ..io import check_output_path
from . import _json

__all__ = ["register"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``validate`` sub-command."""
    from ..validation.study import CANDIDATES

    p = subparsers.add_parser(
        "validate",
        help="fit candidate mechanisms to all spin-rig runs, rank them against the floor",
        description="Replicate-scatter floor of the runs, and every candidate model fitted "
        "to all runs (AIC/BIC, rms per spin band, out-of-band prediction across 200 rad/s). "
        f"Models: {', '.join(CANDIDATES)}.",
    )
    p.add_argument("--data", metavar="FILE.csv", help="runs in the calibrate format (default: "
                   "the thesis's Appendix B)")  # fmt: skip
    p.add_argument("--models", metavar="NAME,...", help="candidates (default: all)")
    p.add_argument("--workers", metavar="N", default="2", help="parallel fits (default 2)")
    p.add_argument("--t-max", metavar="S", default="10", help="censoring horizon [s] (10)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument("--plot", metavar="FILE.png", help="data, scatter, each model, the floor")
    p.add_argument("--out", metavar="DIR", help="write validation.json, .txt and .png there")
    p.set_defaults(func=_run)


def _run(args: argparse.Namespace) -> int:
    from ..calibration.data import load_spin_rig_csv, load_thesis_data
    from ..validation.plot import validation_figure
    from ..validation.study import CANDIDATES, run_validation

    models = (
        [m.strip() for m in args.models.split(",") if m.strip()]
        if args.models
        else list(CANDIDATES)
    )
    try:
        workers = int(args.workers)
    except ValueError:
        raise InputError("workers", f"expected a whole number, got {args.workers!r}") from None
    check_range("workers", workers, 1, 64)
    t_max = check_range("t_max", float(args.t_max), 0.0, 1e4, lo_open=True, unit="s")
    check_output_path("plot", args.plot, ("png", "pdf", "svg"))
    out = Path(args.out) if args.out else None
    if out is not None:
        if out.exists() and not out.is_dir():
            raise InputError("out", f"{args.out!r} exists and is not a directory")
        if not out.resolve().parent.is_dir():
            raise InputError("out", f"parent directory of {args.out!r} does not exist")
    data = load_spin_rig_csv(args.data) if args.data else load_thesis_data()
    tty = sys.stderr.isatty()
    study = run_validation(
        data,
        models,
        t_max=t_max,
        workers=workers,
        progress=(lambda n: print(f"fitting {n} ...", file=sys.stderr)) if tty else None,
    )
    text = study.table() + (
        f"\nspin regulation (+-1.75 rad/s) adds {study.spin_fluctuation_rms_s:.4f} s rms"
    )
    if args.json:
        print(_json.dumps(study.to_dict()))
    else:
        print(text)
    if args.plot or out is not None:
        from ..plotting import save

        fig = validation_figure(study, data, t_max)
        if args.plot:
            save(fig, args.plot)
        if out is not None:
            out.mkdir(parents=True, exist_ok=True)
            save(fig, out / "validation.png")
    if out is not None:
        (out / "validation.json").write_text(_json.dumps(study.to_dict(), indent=1))
        (out / "validation.txt").write_text(text + "\n")
    return 0
