"""Whole sweeps as a user runs them, and back to back against other source trees.

``python -m benchmarks.sweeps [--sweeps 40:1000:10000,100:700:20000] [--workers 2]
[--rounds 2] [--against TREE ...] [--json FILE]``

Each run is ``obturator sweep --case spin-rig --mu-s 0.5473 --spin-rate A:B:N
--workers W --no-progress --out TMP`` in a fresh process (the tree's ``src`` first on
the path), timed from outside: the wall time a user waits, process start, imports,
packing, the workers, the output files and the validity warning included. The sweep's
summary line gives the part the workers computed ("in X s on 2 workers", the runner's
wall time); the rest, *outside compute*, is the parent process's serial work before
and after. *CPU* is the processor time of the whole process tree (the parent, its
workers and helpers: user and system time of the children this process has waited for,
:func:`resource.getrusage`): on a shared machine it varies less than the wall, so a
difference between trees that the walls cannot resolve shows there first.

Every tree first runs a small sweep over the same range (its numba cache then holds
what the sweeps use); then the rounds run interleaved (round by round, sweep by
sweep, tree by tree), so that a drift of the machine's speed touches every tree
alike. Timings compare only within one run: the ratios are the result, and the
table names the machine.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

MU_S = 0.5473
ROOT = Path(__file__).resolve().parents[1]
SWEEPS = ((40.0, 1000.0, 10_000), (100.0, 700.0, 20_000))


def _commit(tree: Path) -> str:
    try:
        out = subprocess.run(
            ["git", "-C", str(tree), "rev-parse", "--short", "HEAD"],
            capture_output=True, text=True, check=True,
        )  # fmt: skip
    except (OSError, subprocess.CalledProcessError):
        return tree.name
    return out.stdout.strip()


def run_sweep(tree: Path, sweep: tuple[float, float, int], workers: int) -> dict[str, Any]:
    """One ``obturator sweep`` of `tree` in a fresh process, as a user runs it (its
    default outputs, its warnings): the wall time [s] from outside, the workers' part
    that its summary line reports (``compute_s``, NaN where it lacks one) and the
    processor time of the process tree (``cpu_s``)."""
    lo, hi, n = sweep
    with tempfile.TemporaryDirectory(prefix="obturator-bench-") as tmp:
        cmd = [
            sys.executable, "-m", "obturator", "sweep", "--case", "spin-rig",
            "--mu-s", str(MU_S), "--spin-rate", f"{lo:g}:{hi:g}:{n}",
            "--workers", str(workers), "--no-progress", "--out", os.path.join(tmp, "sweep.nc"),
        ]  # fmt: skip
        env = os.environ | {"PYTHONPATH": str(tree / "src")}
        cpu0 = _children_cpu()
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=tmp)
        wall = time.perf_counter() - t0
        cpu = _children_cpu() - cpu0
    if proc.returncode != 0:
        raise RuntimeError(f"{tree}: sweep failed: {proc.stderr.strip()[-500:]}")
    found = re.search(r" in ([0-9.e+-]+) s on ", proc.stdout)
    compute = float(found.group(1)) if found else float("nan")
    return {"wall_s": wall, "compute_s": compute, "cpu_s": cpu}


def _children_cpu() -> float:
    """User and system time [s] of this process's waited-for descendants so far."""
    use = resource.getrusage(resource.RUSAGE_CHILDREN)
    return use.ru_utime + use.ru_stime


def measure(
    trees: list[Path],
    sweeps: tuple[tuple[float, float, int], ...] = SWEEPS,
    workers: int = 2,
    rounds: int = 2,
    warm_points: int = 200,
) -> dict[str, Any]:
    """Each sweep of each tree `rounds` times, interleaved; per (sweep, tree) the walls
    of the rounds and their medians. The first tree is the reference of the ratios.
    First each tree runs each range with `warm_points` points (its numba cache then
    holds the paths the sweeps take)."""
    from benchmarks.run import _meta

    for tree in trees:
        for lo, hi, _ in sweeps:
            run_sweep(tree, (lo, hi, warm_points), workers)
    runs: dict[tuple[int, int], list[dict[str, Any]]] = {}
    for _ in range(rounds):
        for s, sweep in enumerate(sweeps):
            for t, tree in enumerate(trees):
                runs.setdefault((s, t), []).append(run_sweep(tree, sweep, workers))
    rows = []
    for s, (lo, hi, n) in enumerate(sweeps):
        ref = statistics.median(r["wall_s"] for r in runs[(s, 0)])
        ref_cpu = statistics.median(r["cpu_s"] for r in runs[(s, 0)])
        for t, tree in enumerate(trees):
            rs = runs[(s, t)]
            wall = statistics.median(r["wall_s"] for r in rs)
            compute = statistics.median(r["compute_s"] for r in rs)
            cpu = statistics.median(r["cpu_s"] for r in rs)
            rows.append(
                {
                    "sweep": f"{n:,} points, {lo:g}-{hi:g} rad/s",
                    "tree": _commit(tree),
                    "walls_s": [r["wall_s"] for r in rs],
                    "wall_s": wall,
                    "compute_s": compute,
                    "outside_s": wall - compute,
                    "speed_up": wall / ref,  # > 1: the first tree is faster
                    "cpu_s": cpu,
                    "cpu_ratio": cpu / ref_cpu,  # > 1: the first tree needs less CPU
                }
            )
    return {"meta": _meta() | {"workers": workers, "rounds": rounds}, "rows": rows}


def _parse_sweeps(text: str) -> tuple[tuple[float, float, int], ...]:
    out = []
    for part in text.split(","):
        lo, hi, n = part.split(":")
        out.append((float(lo), float(hi), int(n)))
    return tuple(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m benchmarks.sweeps", description=__doc__.splitlines()[0]
    )
    ap.add_argument("--sweeps", default="40:1000:10000,100:700:20000",
                    help="LO:HI:N[,LO:HI:N...] spin grids [rad/s]")  # fmt: skip
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--against", action="append", default=[], metavar="TREE",
                    help="another source tree (repeatable)")  # fmt: skip
    ap.add_argument("--json", metavar="FILE")
    args = ap.parse_args(argv)
    trees = [ROOT, *(Path(a).resolve() for a in args.against)]
    rec = measure(trees, _parse_sweeps(args.sweeps), args.workers, args.rounds)
    meta = rec["meta"]
    print(
        f"{meta.get('cpu')} ({meta.get('cpus_available', '?')} CPUs available), "
        f"{args.workers} workers, {args.rounds} rounds interleaved; wall with process start"
    )
    print(f"{'sweep':32} {'tree':10} {'walls [s]':22} {'median':>7} {'compute':>8} "
          f"{'outside':>8} {'this tree faster':>17} {'CPU [s]':>8} "
          f"{'this tree less CPU':>19}")  # fmt: skip
    for r in rec["rows"]:
        walls = ", ".join(f"{w:.2f}" for w in r["walls_s"])
        print(
            f"{r['sweep']:32} {r['tree']:10} {walls:22} {r['wall_s']:7.2f} "
            f"{r['compute_s']:8.2f} {r['outside_s']:8.2f} {r['speed_up']:16.2f}x "
            f"{r['cpu_s']:8.2f} {r['cpu_ratio']:18.2f}x"
        )
    if args.json:
        Path(args.json).write_text(json.dumps(rec, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
