"""Command-line entry point ``obturator``.

Each sub-command lives in its own module exposing ``register(subparsers)``;
this module only collects them and turns input errors into one readable line.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from .errors import InputError

# Modules that add sub-commands; each defines register(subparsers) and sets
# ``func`` (callable taking the parsed namespace, returning an exit code).
_SUBCOMMAND_MODULES = (
    "obturator.cli_simulate",
    "obturator.cli_gasdyn",
    "obturator.cli_thesis",
    "obturator.cli_sweep",
)


def build_parser() -> argparse.ArgumentParser:
    """Return the top-level argument parser with every available sub-command."""
    parser = argparse.ArgumentParser(
        prog="obturator",
        description="Ball obturator opening dynamics (Bloomer 1980).",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
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
    """Run the command line; return the process exit code."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except (InputError, FileNotFoundError, IsADirectoryError, PermissionError) as exc:
        print(f"obturator: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("obturator: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
