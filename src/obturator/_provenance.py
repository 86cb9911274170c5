"""The command line a result came from, for NetCDF ``history`` and report provenance."""

from __future__ import annotations

import shlex
import sys
from collections.abc import Sequence

__all__ = ["set_command", "command_line"]

_COMMAND: list[str] | None = None


def set_command(argv: Sequence[str]) -> None:
    """Record the ``obturator`` arguments being run (called by the CLI entry point)."""
    global _COMMAND
    _COMMAND = ["obturator", *argv]


def command_line() -> str:
    """The recorded ``obturator ...`` command, else this process's own argv."""
    if _COMMAND is not None:
        return shlex.join(_COMMAND)
    return shlex.join(sys.argv or ["python"])
