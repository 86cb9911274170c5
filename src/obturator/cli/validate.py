"""``obturator validate``: one model for all spin-rig runs (issue 9).

Runs :func:`obturator.validation.run_validation` on the 54 runs of thesis
Appendix B (or a user CSV in the ``calibrate`` format, see
:func:`obturator.calibration.data.load_spin_rig_csv`), prints the replicate floor and
the ranked table (``--json``: one object), and optionally draws the figure and
writes everything into a folder.
"""

from __future__ import annotations

import argparse
from functools import partial
from pathlib import Path

from ..errors import InputError
from ..params import Range
from ..vocab import NOISE_MODELS
from . import _json
from ._flags import (
    JSON,
    NO_PROGRESS,
    RESTART,
    RIG_DATA,
    RIG_HORIZON,
    alias,
    command,
    figure_flags,
    option,
    quantity_option,
    switch,
)
from ._kinds import Count, OutputDir, Text
from ._runner import runner_from_args

__all__ = ["register"]

_WORKERS = (
    option(
        "--workers",
        dest="jobs",
        metavar="N",
        default="2",
        type=Count(1, 64),
        help="worker processes (2; at most 64: one per candidate fit and data subset)",
    ),
)
_WORKERS += (alias(_WORKERS[0], "--jobs"),)


def _list_models(as_json: bool) -> int:
    from ..validation.candidates import CANDIDATES, DEFAULT_MODELS, PARAMETERS

    if as_json:
        models = [
            {
                "name": c.name,
                "parameters": {k: PARAMETERS[k].unit for k in c.params},
                "description": c.description,
                "default": c.name in DEFAULT_MODELS,
            }
            for c in CANDIDATES.values()
        ]
        print(_json.dumps({"models": models}))
        return 0
    for c in CANDIDATES.values():
        mark = "*" if c.name in DEFAULT_MODELS else " "
        params = ", ".join(f"{k} [{PARAMETERS[k].unit}]" for k in c.params) or "-"
        print(f"{mark} {c.name:<27} {params}\n    {c.description}")
    print("* in the default study")
    return 0


def _run(args: argparse.Namespace) -> int:
    if args.list_models:
        return _list_models(args.json)
    from ._runner import progress_from_args

    # piped, never silent for long: loading the code, the fits, the figure and the files
    with progress_from_args(args).heartbeat("validate", "loading the candidates"):
        return _validate(args)


def _validate(args: argparse.Namespace) -> int:
    from ..calibration.data import load_spin_rig_csv, load_thesis_data
    from ..validation import get_candidates, run_validation
    from ..validation.floor import DEFAULT_CLUSTER_GAP
    from ..validation.likelihood import SPIN_SD

    if args.no_profile and args.profile_all:
        raise InputError(
            "--profile-all", "profiles every candidate, which --no-profile turns off: give one"
        )
    jobs, t_max = args.jobs, args.t_max  # checked by their kinds
    spin_sd = SPIN_SD if args.spin_sd is None else args.spin_sd
    gap = DEFAULT_CLUSTER_GAP if args.cluster_gap is None else args.cluster_gap
    names = get_candidates(args.models)  # validates the names before any work
    plot = Path(args.figure) if args.figure else None
    out = Path(args.out) if args.out else None
    if out is not None:
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError("out", f"{out}: cannot create the folder ({exc})") from None
    try:
        data = load_spin_rig_csv(args.data) if args.data else load_thesis_data()
    except InputError as exc:
        if exc.field != "path":
            raise
        raise InputError("data", str(exc).split(": ", 1)[1]) from None
    runner = runner_from_args(args, workers=jobs, resume=False)
    if out is not None:
        runner.store = out / "validation"  # its sidecar: validation.partial.jsonl
    result = run_validation(
        data,
        models=[c.name for c in names],
        runner=runner,
        t_max=t_max,
        spin_sd=spin_sd,
        gap=gap,
        profile="none" if args.no_profile else "all" if args.profile_all else "recommended",
        noise=args.noise,
    )
    from ..runs.store import atomic_write_text
    from ..validation.textreport import format_report

    text = format_report(result)
    from ..validation.plotting import save_validation_figure

    if plot is not None:
        save_validation_figure(result, plot)
    if out is not None:  # then the resume store goes (kept if a write fails)
        as_json = _json.dumps(result.to_dict(), indent=1) + "\n"
        runner.write_outputs(
            [
                (out / "validation.png", partial(save_validation_figure, result)),
                (out / "validation.txt", lambda path: atomic_write_text(path, text + "\n")),
                (out / "validation.json", lambda path: atomic_write_text(path, as_json)),
            ]
        )
    if args.json:
        print(_json.dumps(result.to_dict()))
    else:
        print(text)
    return 0


register = command(
    "validate",
    _run,
    "Model discrimination against the spin-rig data: the replicate (pure-error) floor, "
    "a maximum-likelihood fit of every candidate to all runs, the starred runs and each "
    "half of the spin range, AIC/BIC and out-of-band rms.",
    RIG_DATA.but(
        help="runs in the calibrate CSV format, with each run's own theta0, hole radius, "
        "density, ball mass and measured angle if given (default: thesis Appendix B, "
        "54 runs)",
    ),
    option(
        "--models",
        metavar="NAME,...",
        type=Text(example="thesis"),
        help="candidates, comma-separated (default: the standard set; --list-models)",
    ),
    switch("--list-models", "list the candidates and exit"),
    JSON,
    *figure_flags("validation.png", "draw data, model curves and the floor"),
    option(
        "--out",
        metavar="DIR",
        type=OutputDir(),
        help="write validation.json, validation.txt, validation.png (finished fits are "
        "kept in validation.partial.jsonl there until then: a rerun resumes)",
    ),
    *_WORKERS,
    RIG_HORIZON.but(help="horizon [s]; later runs are censored (20)"),
    quantity_option(
        "--spin-sd",
        "rad/s",
        Range(0.0, 100.0),
        "1 rad/s",
        "spin error SD of the errors-in-variables term [rad/s] "
        "(default 1.01: uniform on the rig's +-1.75 rad/s; 0: off)",
        metavar="RAD_S",
        default=None,
    ),
    option(
        "--noise",
        choices=NOISE_MODELS,
        default="band",
        help="run-to-run noise of the likelihood: one sigma per spin band fitted with the "
        "model (band, the default: the replicate scatter differs tenfold between bands) "
        "or one pooled sigma (pooled)",
    ),
    quantity_option(
        "--cluster-gap",
        "rad/s",
        Range(0.0, 1e4),
        "3 rad/s",
        "single-linkage gap of the replicate clusters [rad/s] (default 3.49)",
        metavar="RAD_S",
        default=None,
    ),
    switch("--no-profile", "Wald intervals only (no profile likelihood)"),
    switch(
        "--profile-all",
        "profile-likelihood intervals for every candidate (default: the recommended one)",
    ),
    RESTART,
    NO_PROGRESS,
)
