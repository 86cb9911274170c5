"""``obturator reproduce``: every thesis figure (PNG) and a report (Markdown, HTML)."""

from __future__ import annotations

import argparse
from pathlib import Path

from ._flags import NO_PROGRESS, RESTART, command, option, switch
from ._kinds import OutputDir

__all__ = ["register"]


def _reproduce(args: argparse.Namespace) -> int:
    from ._runner import progress_from_args

    # the heartbeat covers the loading of the studies' code too (seconds on a busy machine)
    with progress_from_args(args).heartbeat("reproduce", "loading the studies"):
        from .._provenance import command_line
        from ..thesis.reproduce import reproduce
        from ._runner import runner_from_args

        runner = runner_from_args(args, resume=False)
        runner.store = Path(args.out) / "report"  # its sidecar: report.partial.jsonl
        res = reproduce(
            args.out,
            quick=args.quick,
            runner=runner,
            command=command_line(),
            envelope=args.envelope,
            validation=not args.no_validation,
            design=args.design,
        )
    flagged = sum(1 for r in res.rows if r.difference is not None and abs(r.difference) > 2.0)
    print(
        f"wrote {len(res.figures)} figures, {res.report_md} and {res.report_html} "
        f"in {res.elapsed_s:.1f} s ({flagged} rows differ from the thesis by > 2 %)"
    )
    return 0


register = command(
    "reproduce",
    _reproduce,
    "Run the studies of Bloomer (1980) Figs. 9-43, the chapter IV and exact-model "
    "friction calibrations, and write PNG figures plus report.md and report.html "
    "comparing every checkable printed number with the computed one.",
    option(
        "--out",
        metavar="DIR",
        required=True,
        type=OutputDir(),
        help="output directory (created; finished studies are kept in "
        "report.partial.jsonl there until the report is written: a rerun resumes)",
    ),
    switch("--quick", "fewer points and a smaller bootstrap (seconds)"),
    RESTART,
    NO_PROGRESS,
    switch(
        "--no-validation",
        "leave out the validation section (fits to all 54 runs; ~1 min quick)",
    ),
    switch(
        "--envelope",
        "add the firing-envelope section (t_cr map over Mach x altitude, Sobol indices)",
    ),
    switch(
        "--design",
        "add the experiment-design section (which runs decide between the leading "
        "mechanisms, simulated campaigns)",
    ),
)
