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

# Modules that add sub-commands; each defines register(subparsers) and sets
# ``func`` (callable taking the parsed namespace, returning an exit code).
_SUBCOMMAND_MODULES = (
    "obturator.cli.simulate",
    "obturator.cli.gasdyn",
    "obturator.cli.reproduce",
    "obturator.cli.calibrate",
    "obturator.cli.sweep",
    "obturator.cli.montecarlo",
    "obturator.cli.validate",
)


class _Parser(argparse.ArgumentParser):
    """argparse, but a usage error is one line ``obturator: error: <field>: ...``, exit 2."""

    def error(self, message: str) -> NoReturn:
        if message.startswith("argument "):  # "argument --x/-x: invalid ..." -> "--x: invalid ..."
            head, _, rest = message[len("argument ") :].partition(": ")
            message = f"{head.split('/')[0]}: {rest}"
        self.exit(EXIT_INPUT, f"obturator: error: {' '.join(message.split())}\n")


def build_parser() -> argparse.ArgumentParser:
    """Return the top-level argument parser with every available sub-command."""
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
    for name in _SUBCOMMAND_MODULES:
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
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.print_completion:
        import shtab

        print(shtab.complete(parser, shell=args.print_completion))
        return 0
    if args.command is None:
        parser.error("a COMMAND is required (see obturator --help)")
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
    except OSError as exc:  # files named on the command line or in a config
        where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        print(f"obturator: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return EXIT_INPUT
    except KeyboardInterrupt:
        print("obturator: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:
        if os.environ.get("OBTURATOR_DEBUG"):
            raise
        text = " ".join(str(exc).split())[:300]
        print(
            f"obturator: internal error: {type(exc).__name__}: {text} "
            "(please report; OBTURATOR_DEBUG=1 shows the traceback)",
            file=sys.stderr,
        )
        return EXIT_INTERNAL


def run() -> None:  # pragma: no cover - the console-script entry point
    """``obturator`` as a program: Ctrl-C / SIGTERM end it at once with one line."""
    from . import _interrupt

    _interrupt.install()
    try:
        code = main()
        sys.stdout.flush()
    except BrokenPipeError:  # output piped into `head` and the like: not an error
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        code = 0
    sys.exit(code)


if __name__ == "__main__":  # pragma: no cover
    run()
