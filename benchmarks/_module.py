"""The command line of a benchmark module run on its own (``python -m benchmarks.X``)."""

from __future__ import annotations

import argparse
import json
from collections.abc import Callable, Sequence
from typing import Any


def run_module(
    prog: str,
    quick_help: str,
    rows_of: Callable[[bool], list[dict[str, Any]]],
    print_table: Callable[[list[dict[str, Any]]], None],
    argv: Sequence[str] | None = None,
) -> int:
    """Parse ``--quick`` and ``--json PATH``, compute ``rows_of(quick)``, print the CPU
    and the table, write the rows as JSON when asked; returns the exit code."""
    ap = argparse.ArgumentParser(prog=prog)
    ap.add_argument("--quick", action="store_true", help=quick_help)
    ap.add_argument("--json", metavar="PATH", help="write the rows as JSON")
    args = ap.parse_args(argv)
    from benchmarks.run import _meta

    rows = rows_of(args.quick)
    print(f"CPU: {_meta()['cpu']}")
    print_table(rows)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=2)
    return 0
