"""Where a result came from: the command line (NetCDF ``history``, report provenance)
and the package version."""

from __future__ import annotations

import shlex
import sys
from collections.abc import Sequence

__all__ = ["set_command", "command_line", "package_version"]

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


def package_version() -> str:
    """The installed version of ``obturator`` ("0+unknown" in a bare source tree)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("obturator")
    except PackageNotFoundError:  # pragma: no cover - source tree without metadata
        return "0+unknown"
