"""Command-line entry point ``obturator``.

Each sub-command lives in its own module of this package exposing
``register(subparsers)`` (shared argument helpers in :mod:`._args`); this
module only collects them and turns errors into one readable line and an exit
code (:mod:`obturator.errors`).
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from typing import NoReturn

from .._provenance import package_version
from ..errors import (
    EXIT_CLUSTER,
    EXIT_INPUT,
    EXIT_INTERNAL,
    EXIT_SOLVER,
    ClusterError,
    InputError,
    SolverError,
)

# Sub-command -> (the module that adds it, its one-line help). Each module defines
# register(subparsers) and sets ``func`` (callable taking the parsed namespace,
# returning an exit code). A command line naming one command imports only that
# module; ``obturator --help`` imports none (start-up time; tests/cli/test_cli_startup.py
# checks that each module registers the help given here).
_COMMANDS: dict[str, tuple[str, str]] = {
    "simulate": ("obturator.cli.simulate", "integrate one case to the opening time t_cr"),
    "gasdyn": (
        "obturator.cli.gasdyn",
        "normal shock, inlet start/unstart, Fanno choking, standard atmosphere",
    ),
    "reproduce": (
        "obturator.cli.reproduce",
        "write every thesis figure (PNG) and a report (Markdown, HTML)",
    ),
    "calibrate": (
        "obturator.cli.calibrate",
        "fit the sliding friction mu_s of the exact model to spin-rig data",
    ),
    "sweep": ("obturator.cli.sweep", "t_cr on a grid of parameters (parallel, resumable)"),
    "montecarlo": ("obturator.cli.montecarlo", "t_cr quantiles under uncertain inputs"),
    "validate": (
        "obturator.cli.validate",
        "fit candidate mechanisms to all spin-rig runs and rank them",
    ),
    "design-experiment": (
        "obturator.cli.design",
        "plan the rig runs that decide between candidate mechanisms",
    ),
    "trajectory": (
        "obturator.cli.envelope",
        "t_cr along one flight: trajectory-coupled vs constant load",
    ),
    "envelope": (
        "obturator.cli.envelope",
        "t_cr map over muzzle Mach x altitude (coupled and constant load)",
    ),
    "probability": (
        "obturator.cli.robust",
        "P(t_cr > requirement) under uncertain inputs (importance sampling)",
    ),
    "sensitivity": (
        "obturator.cli.robust",
        "Sobol indices of t_cr (SALib) with bootstrap intervals",
    ),
    "optimize": (
        "obturator.cli.robust",
        "robust design: minimise the worst case / a quantile of t_cr over the envelope",
    ),
    "warmup": (
        "obturator.cli.warmup",
        "compile the integrators into numba's cache (once, after installing)",
    ),
}


class _Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line ``obturator: error: <field>: ...``, exit 2."""

    def error(self, message: str) -> NoReturn:
        if message.startswith("argument "):  # "argument --x/-x: invalid ..." -> "--x: invalid ..."
            head, _, rest = message[len("argument ") :].partition(": ")
            message = f"{head.split('/')[0]}: {rest}"
        self.exit(EXIT_INPUT, f"obturator: error: {' '.join(message.split())}\n")


def build_parser(command: str | None = None, *, full: bool = True) -> argparse.ArgumentParser:
    """Return the top-level argument parser with every available sub-command.

    With `command` (a name in the command line) only that sub-command is added;
    with ``full=False`` the sub-commands are listed by name and help only.
    """
    parser = _Parser(
        prog="obturator",
        description="Ball obturator opening dynamics (Bloomer 1980).",
    )
    parser.add_argument("--version", action="version", version=f"obturator {package_version()}")
    parser.add_argument(
        "--print-completion",
        choices=("bash", "zsh"),
        help="print a shell completion script (e.g. obturator --print-completion bash "
        "> ~/.local/share/bash-completion/completions/obturator)",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = False
    if command is None and not full:
        for name, (_, text) in _COMMANDS.items():
            sub.add_parser(name, help=text)
        return parser
    chosen = [command] if command in _COMMANDS else list(_COMMANDS)
    for name in dict.fromkeys(_COMMANDS[c][0] for c in chosen):
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as exc:  # sub-command not shipped in this build
            if exc.name != name:
                raise
            continue
        module.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; return the process exit code.

    Exit codes: 0 success, 2 bad input (one line naming the field), 3 solver
    failure on valid input, 130 interrupted, 1 anything else (a bug: one line;
    ``OBTURATOR_DEBUG=1`` re-raises it with its traceback).
    """
    from .._provenance import set_command

    argv = sys.argv[1:] if argv is None else list(argv)
    set_command(argv)
    from ._environment import check_environment

    try:  # before numba is imported: its variables break the import itself
        check_environment()
    except InputError as exc:
        print(f"obturator: error: {exc}", file=sys.stderr)
        return EXIT_INPUT
    command = _command_of(argv)
    parser = build_parser(command, full=command is not None or "--print-completion" in argv)
    try:  # every value is checked here, by its kind (cli._kinds), before any work
        args = parser.parse_args(argv)
    except SystemExit as exc:  # a usage error (one line, printed), --help, --version
        return exc.code if isinstance(exc.code, int) else EXIT_INPUT
    if args.print_completion:
        import shtab

        print(shtab.complete(parser, shell=args.print_completion))
        return 0
    if args.command is None:
        print("obturator: error: a COMMAND is required (see obturator --help)", file=sys.stderr)
        return EXIT_INPUT
    from . import _interrupt

    _interrupt.note_command(args.command, getattr(args, "out", None))
    try:
        return int(args.func(args) or 0)
    except InputError as exc:
        print(f"obturator: error: {exc}", file=sys.stderr)
        return EXIT_INPUT
    except SolverError as exc:
        print(f"obturator: solver failure: {exc}", file=sys.stderr)
        return EXIT_SOLVER
    except ClusterError as exc:
        print(
            f"obturator: cluster failure: {exc}; finished points are kept, run the same "
            "command again to resume",
            file=sys.stderr,
        )
        return EXIT_CLUSTER
    except BrokenPipeError:
        raise  # output piped into `head`: run() ends quietly
    except OSError as exc:  # files named on the command line or in a config
        where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        print(f"obturator: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return EXIT_INPUT
    except KeyboardInterrupt:
        print(_interrupt.line(), file=sys.stderr)
        return 130
    except Exception as exc:
        if os.environ.get("OBTURATOR_DEBUG", "").strip() == "1":
            raise
        text = " ".join(str(exc).split())[:300]
        print(
            f"obturator: internal error: {type(exc).__name__}: {text} "
            "(please report; OBTURATOR_DEBUG=1 shows the traceback)",
            file=sys.stderr,
        )
        return EXIT_INTERNAL


def _command_of(argv: list[str]) -> str | None:
    """The sub-command an argument list names (None: top-level options only, or unknown)."""
    if "--print-completion" in argv or not argv or argv[0].startswith("-"):
        return None
    return argv[0] if argv[0] in _COMMANDS else None


def run() -> None:  # pragma: no cover - the console-script entry point
    """``obturator`` as a program: Ctrl-C / SIGTERM end it at once with one line.

    After the command has finished (outputs written and closed, workers and
    clients shut down, exit handlers run) the process ends with ``os._exit``:
    the interpreter's own teardown of numba's LLVM state and the scientific
    stack is a large share of a short command's time (``docs/benchmarks.md``, the CLI
    latency table of ``python -m benchmarks``) and does nothing a user needs.
    """
    import atexit

    from . import _interrupt

    _interrupt.install()
    try:
        code = main()
        sys.stdout.flush()
    except BrokenPipeError:  # output piped into `head` and the like: not an error
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        code = 0
    if (
        os.environ.get("OBTURATOR_FULL_EXIT", "").strip() == "1"
    ):  # e.g. coverage tools that save at exit
        sys.exit(code)
    atexit._run_exitfuncs()
    sys.stderr.flush()
    os._exit(code)


if __name__ == "__main__":  # pragma: no cover
    run()
