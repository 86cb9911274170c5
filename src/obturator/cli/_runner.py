"""The one place where command-line flags become a :class:`~obturator.runs.Runner`.

``--workers``, ``--scheduler``, ``--chunk-size``, ``--out`` (the resume store's
output), ``--restart`` and ``--no-progress`` (a bar on a terminal, plain lines with an
ETA on stderr otherwise) mean the same on every command that has them.
"""

from __future__ import annotations

import argparse
from collections.abc import Mapping
from functools import partial
from typing import Any

from ..runs import Progress, Runner, study_digest
from ._args import parse_integer

__all__ = ["progress_from_args", "runner_from_args", "study_runner", "write_dataset"]


def progress_from_args(args: argparse.Namespace) -> Progress:
    """The progress reporter: nothing with ``--no-progress``, else a bar on a terminal
    and plain lines elsewhere."""
    return Progress.auto(not getattr(args, "no_progress", False))


def runner_from_args(
    args: argparse.Namespace, *, workers: int | None = None, resume: bool = True
) -> Runner:
    """The :class:`Runner` the flags describe (flags a command lacks take their defaults).

    Parameters
    ----------
    args : argparse.Namespace
    workers : int, optional
        The worker count where the command parses ``--workers`` itself (default: the
        flag, else all CPUs).
    resume : bool
        Whether ``--out`` (where the command has it) keeps a resume store beside it.
    """
    if workers is None:
        workers = parse_integer("workers", getattr(args, "workers", None), 1)
    return Runner(
        workers=workers,
        scheduler=getattr(args, "scheduler", None),
        chunk_size=parse_integer("chunk_size", getattr(args, "chunk_size", None), 1),
        store=(getattr(args, "out", None) or None) if resume else None,
        restart=bool(getattr(args, "restart", False)),
        progress=progress_from_args(args),
    )


def study_runner(args: argparse.Namespace, identity: Mapping[str, Any]) -> Runner:
    """The runner of a study described by `identity` (its resume store opened beside
    ``--out``, if given, for the study digest of `identity`)."""
    runner = runner_from_args(args)
    runner.open(study_digest(identity))
    return runner


def write_dataset(args: argparse.Namespace, runner: Runner, ds: Any) -> None:
    """Write `ds` to ``--out`` (if given) and remove the resume store; a full disk is one
    error that keeps the finished work (:meth:`Runner.write_outputs`)."""
    from ..sweeps import write_netcdf

    runner.write_outputs([(getattr(args, "out", None), partial(write_netcdf, ds))])
