"""Freshly compiled against cached machine code: same t_cr bit for bit, or not?

``python -m benchmarks.cache_binding [--points 200] [--stiff 35] [--paths P1,P2]``

Runs the same rig points (mu_s = 0.5473; the first ``--stiff`` of ``--points`` spins
over 40-1000 rad/s, the ones that stick and reach Radau IIA) in three fresh processes
that share one new, empty ``XDG_CACHE_HOME``:

1. ``fresh``: numba compiles everything (and fills the cache);
2. ``cached``: everything is loaded from that cache;
3. ``cached+callees``: every cached overload of every core function that is not inlined
   at numba's IR level is loaded first (:func:`load_callees`), then the same run.

and prints, per path (the default ``auto`` in lanes and one trajectory at a time;
regularised sweep: DOP853 and Radau IIA lanes; regularised one-trajectory; set-valued),
how many t_cr of 2 and 3 equal those of 1 bit for bit.

Why 3: numba links a copy of each non-inlined callee into its caller's module
(``linkonce_odr``, weak in the object file), and the caller's copy, optimised again
inside the caller, need not round as the callee's own code does. In a compiling
process every callee's own library is in the JIT before its caller, so the caller's
calls bind to it; a process that loads the caller from the cache alone runs the
caller's own copies. Measured (2026-11-26): the Radau IIA lanes differed on every
stiff point (up to 1.2e-5 at 40 rad/s), and loading ``lu_factor_complex_lanes``
alone before the lanes made them bit-identical again.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import pkgutil
import subprocess
import sys
import tempfile
from typing import Any

import numpy as np

MODES = ("fresh", "cached", "cached+callees")
PATHS = (
    "default (auto)",
    "default (auto) one-trajectory",
    "regularised sweep",
    "regularised one-trajectory",
    "set-valued",
)


def load_callees() -> int:
    """Load every cached overload of the core's non-inlined functions; return how many.

    The integrators themselves (``integrate*``, ``_integrate*``: what Python calls) are
    left to load on their first call, after every callee; nothing is compiled here.
    """
    from numba.core.registry import CPUDispatcher

    import obturator.core

    n = 0
    for info in pkgutil.walk_packages(obturator.core.__path__, "obturator.core."):
        module = importlib.import_module(info.name)
        for name, d in vars(module).items():
            if not isinstance(d, CPUDispatcher) or d.py_func.__module__ != info.name:
                continue
            if d.targetoptions.get("inline") == "always" or name.lstrip("_").startswith(
                "integrate"
            ):
                continue
            for key in d._cache._cache_file._load_index():  # numba's own index
                d.compile(key[0])
                n += 1
    return n


def worker(mode: str, points: int, stiff: int, paths: tuple[str, ...] = PATHS) -> dict[str, Any]:
    """In this process: t_cr (hex) of each of `paths` at the stiff points."""
    if mode == "cached+callees":
        load_callees()
    from benchmarks.exact_limit import REGULARISED_DEFAULT as REGULARISED
    from obturator.model.cases import rig_case
    from obturator.solve import SolverOptions, opening_time, opening_times

    spins = np.linspace(40.0, 1000.0, points)[:stiff]
    cases = [rig_case(float(w), 0.5473) for w in spins]
    run = {
        "default (auto)": lambda: opening_times(cases, SolverOptions())[0],
        "default (auto) one-trajectory": lambda: [opening_time(c, SolverOptions()) for c in cases],
        "regularised sweep": lambda: opening_times(cases, REGULARISED)[0],
        "regularised one-trajectory": lambda: [opening_time(c, REGULARISED) for c in cases],
        "set-valued": lambda: opening_times(cases, SolverOptions(method="set-valued"))[0],
    }
    t_cr = {k: run[k]() for k in paths}
    return {"spins": spins.tolist(), **{k: [float(t).hex() for t in v] for k, v in t_cr.items()}}


def compare(runs: dict[str, dict[str, Any]], paths: tuple[str, ...] = PATHS) -> list[str]:
    """One line per mode and path: bit-identical count and worst relative gap to fresh."""
    lines = []
    for mode in MODES[1:]:
        for path in paths:
            a = np.array([float.fromhex(x) for x in runs["fresh"][path]])
            b = np.array([float.fromhex(x) for x in runs[mode][path]])
            gap = float(np.max(np.abs(b / a - 1.0)))
            lines.append(
                f"{mode:>15} vs fresh, {path:<30}: {int(np.sum(a == b))}/{a.size} "
                f"bit-identical, worst {gap:.1e}"
            )
    return lines


def main(argv: list[str] | None = None) -> dict[str, dict[str, Any]]:
    """Run the three processes and print the comparison."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=200)
    ap.add_argument("--stiff", type=int, default=35)
    ap.add_argument("--paths", default=",".join(PATHS), help="comma-separated, of: "
                    + ", ".join(PATHS))  # fmt: skip
    ap.add_argument("--worker", choices=MODES, help=argparse.SUPPRESS)
    ap.add_argument("--out", help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    paths = tuple(p.strip() for p in a.paths.split(","))
    unknown = sorted(set(paths) - set(PATHS))
    if unknown:
        ap.error(f"--paths: unknown {', '.join(unknown)}; allowed: {', '.join(PATHS)}")
    if a.worker:
        with open(a.out, "w") as fh:
            json.dump(worker(a.worker, a.points, a.stiff, paths), fh)
        return {}
    runs = {}
    with tempfile.TemporaryDirectory(prefix="obturator-cache-") as cache:
        env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
        env["XDG_CACHE_HOME"] = cache
        for mode in MODES:
            out = os.path.join(cache, f"{mode}.json")
            cmd = [sys.executable, "-m", "benchmarks.cache_binding", "--worker", mode,
                   "--out", out, "--points", str(a.points), "--stiff", str(a.stiff),
                   "--paths", ",".join(paths)]  # fmt: skip
            subprocess.run(cmd, env=env, check=True)
            with open(out) as fh:
                runs[mode] = json.load(fh)
    print("\n".join(compare(runs, paths)))
    return runs


if __name__ == "__main__":
    main()
