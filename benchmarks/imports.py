"""Import costs: what a module adds to every command's start-up.

``python -m benchmarks.imports [--quick] [--json PATH]``; also a section of
``python -m benchmarks report``. Each module is imported in a fresh interpreter after
``numpy`` (which every command loads), wall clock around the import alone, best of
repeats. The package defers the heavy ones (``scipy.optimize``, ``scipy.integrate``,
``scipy.stats``, ``xarray``) to first use; this table is why.
"""

from __future__ import annotations

import math
import subprocess
import sys
from collections.abc import Sequence
from typing import Any

#: Modules timed, in order: the package and the command line, then what they defer.
MODULES = (
    "obturator",
    "obturator.cli",
    "scipy.optimize",
    "scipy.integrate",
    "scipy.stats",
    "xarray",
)
_PROGRAM = (
    "import time, numpy; t = time.perf_counter(); import {module}; print(time.perf_counter() - t)"
)


def import_seconds(module: str, repeat: int = 3) -> float:
    """Best wall time [s] of ``import module`` in a fresh interpreter, after numpy."""
    best = math.inf
    for _ in range(max(1, repeat)):
        out = subprocess.run(
            [sys.executable, "-c", _PROGRAM.format(module=module)],
            capture_output=True,
            text=True,
            check=True,
        )
        best = min(best, float(out.stdout.strip().splitlines()[-1]))
    return best


def cost(modules: Sequence[str] = MODULES, repeat: int = 3) -> list[dict[str, Any]]:
    """One row per module: its import time [s] on top of numpy."""
    return [{"module": m, "import_s": import_seconds(m, repeat)} for m in modules]


def print_table(rows: list[dict[str, Any]]) -> None:
    """Rich table of :func:`cost`."""
    from rich.console import Console
    from rich.table import Table

    t = Table(title="import cost in a fresh interpreter, after numpy (best of repeats)")
    t.add_column("module")
    t.add_column("import (ms)", justify="right")
    for r in rows:
        t.add_row(r["module"], f"{1e3 * r['import_s']:.0f}")
    Console().print(t)


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m benchmarks.imports``."""
    from benchmarks._module import run_module

    prog = "python -m benchmarks.imports"
    return run_module(prog, "one repeat", lambda q: cost(repeat=1 if q else 5), print_table, argv)


if __name__ == "__main__":
    raise SystemExit(main())
