"""Command-line latency: what a user waits for, process start included.

Each command runs in a fresh process (best of `repeat`, wall clock from the
parent), warm numba cache:

* ``obturator --help`` and ``obturator simulate --case spin-rig``;
* ``obturator sweep`` over 20 rig spin rates (100-700 rad/s, mu_s 0.5473),
  each repeat in a new directory (no resume), NetCDF and CSV written;
* the baseline: a fresh ``python`` running a plain loop of
  ``scipy.integrate.solve_ivp(method="LSODA")`` over the same 20 points
  (:mod:`benchmarks.baseline`; no output files), and ``import numpy, scipy``
  alone for scale.
"""

from __future__ import annotations

import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
SPINS = "100:700:20"
MU_S = "0.5473"

_LSODA_LOOP = f"""
import sys
sys.path.insert(0, {str(ROOT)!r})
import numpy as np
from benchmarks.baseline import model_from_case, solve_baseline
from obturator.model.cases import rig_case
for w in np.linspace(100.0, 700.0, 20):
    solve_baseline(model_from_case(rig_case(float(w), {MU_S})))
"""


def _obturator() -> list[str]:
    exe = shutil.which("obturator")
    return [exe] if exe else [sys.executable, "-m", "obturator"]


def _time(cmd: list[str], repeat: int, fresh_dir: bool = False) -> float:
    best = math.inf
    for _ in range(max(1, repeat)):
        with tempfile.TemporaryDirectory(prefix="obturator-latency-") as tmp:
            argv = [a.replace("{tmp}", tmp) for a in cmd] if fresh_dir else cmd
            t0 = time.perf_counter()
            subprocess.run(argv, check=True, capture_output=True, cwd=tmp, env=dict(os.environ))
            best = min(best, time.perf_counter() - t0)
    return best


def cli_latency(repeat: int = 3) -> dict[str, Any]:
    """Best wall times [s] of the commands above and the sweep's ratio to the baseline."""
    ob = _obturator()
    _time([*ob, "simulate", "--case", "spin-rig"], 1)  # fill the numba cache if cold
    out = {
        "python_import_numpy_scipy_s": _time(
            [sys.executable, "-c", "import numpy, scipy.integrate"], repeat
        ),
        "obturator_help_s": _time([*ob, "--help"], repeat),
        "simulate_s": _time([*ob, "simulate", "--case", "spin-rig"], repeat),
        "sweep_20_s": _time(
            [
                *ob,
                "sweep",
                "--case",
                "spin-rig",
                "--spin-rate",
                SPINS,
                "--mu-s",
                MU_S,
                "--out",
                "{tmp}/s.nc",
                "--no-progress",
            ],
            repeat,
            fresh_dir=True,
        ),  # fmt: skip
        "lsoda_loop_20_s": _time([sys.executable, "-c", _LSODA_LOOP], max(1, repeat - 1)),
    }
    out["sweep_speedup_vs_lsoda_loop"] = out["lsoda_loop_20_s"] / out["sweep_20_s"]
    return out


def print_latency(rec: dict[str, Any]) -> None:
    """A rich table of :func:`cli_latency`."""
    from rich.console import Console
    from rich.table import Table

    con = Console(width=160)
    t = Table(title="command-line latency (fresh process each, best of repeats, warm cache)")
    t.add_column("command")
    t.add_column("wall", justify="right")
    t.add_column("vs LSODA loop", justify="right")
    base = rec["lsoda_loop_20_s"]
    rows = (
        ("python -c 'import numpy, scipy.integrate'", "python_import_numpy_scipy_s"),
        ("obturator --help", "obturator_help_s"),
        ("obturator simulate --case spin-rig", "simulate_s"),
        ("obturator sweep, 20 points (NetCDF + CSV)", "sweep_20_s"),
        ("python: LSODA loop over the same 20 points", "lsoda_loop_20_s"),
    )
    for label, key in rows:
        t.add_row(label, f"{rec[key]:.3g} s", f"{base / rec[key]:.2f}x")
    con.print(t)
