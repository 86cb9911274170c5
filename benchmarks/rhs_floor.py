"""Where an opening time's cost goes across the operating range, and the floor under it.

``python -m benchmarks.rhs_floor [--points 2000] [--spins 40,1000] [--sample 200]
[--against TREE] [--json FILE]``

On the rig (mu_s = 0.5473) over a linear grid of spins, as a sweep runs them
(:func:`obturator.solve.opening_times`, the sweep's options), per spin band:

* the route counts, CPU time per point (this process, one thread), right-hand-side
  evaluations per point (the band's total, a shared return map's nodes included) and
  nanoseconds per evaluation (CPU time over evaluations: everything the integrator does
  per evaluation, not the evaluation alone);
* on a sample of points run alone at the default options (a batch of one, each
  point's own return map built for it where it takes one), the median right-hand-side
  evaluations per point: the count that envelope following would have to cut;
* the floor: nanoseconds per lane of the thesis kernel's right-hand side in its
  vector loop over :data:`~obturator.core.integrators.lanes.LANES` lanes, and of the
  scalar right-hand side, each in a tight compiled loop of this run. A band's ns per
  evaluation over the lane floor is how far its integrator is from doing nothing but
  evaluate the right-hand side in lanes.

``--against TREE`` measures the same in another source tree (``TREE/src`` first on the
path, its own numba cache) in a subprocess of the same run, and prints each band's ratio
and the ratio of the median evaluations per point: timings are only compared within one
run, on one machine.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

MU_S = 0.5473
BANDS = ((40.0, 100.0), (100.0, 150.0), (150.0, 218.0), (218.0, 300.0), (300.0, 500.0),
         (500.0, 700.0), (700.0, 1000.0 + 1e-9))  # fmt: skip
ROOT = Path(__file__).resolve().parents[1]


def _sweep_options():
    """The options ``obturator sweep`` runs with (shared return maps where the tree has
    them)."""
    from obturator.solve import SolverOptions

    try:
        return SolverOptions(shared_maps=True)
    except TypeError:  # a tree before the option
        return SolverOptions()


def _opening_times():
    """The front door of many opening times (``obturator.sweeps.batch`` in trees before
    ``obturator.solve.many``)."""
    try:
        from obturator.solve import opening_times
    except ImportError:
        from obturator.sweeps.batch import opening_times
    return opening_times


def band_costs(spins: np.ndarray) -> list[dict[str, Any]]:
    """Per band of :data:`BANDS`: points, routes, CPU time and evaluations per point."""
    from obturator.model.cases import rig_case

    opening_times = _opening_times()
    options = _sweep_options()
    # load every path's compiled code first (set-valued, DOP853 and Radau IIA lanes)
    opening_times([rig_case(float(w), MU_S) for w in np.linspace(40.0, 1000.0, 64)], options)
    rows = []
    for lo, hi in BANDS:
        band = spins[(spins >= lo) & (spins < hi)]
        if band.size == 0:
            continue
        cases = [rig_case(float(w), MU_S) for w in band]
        t0 = time.process_time()
        out = opening_times(cases, options)
        cpu = time.process_time() - t0
        stats = out[-1]
        nfev = int(stats["nfev"]) + int(stats.get("nfev_shared", 0))
        rows.append(
            {
                "band": f"{lo:g}-{min(hi, 1000.0):g}",
                "points": int(band.size),
                "routes": ", ".join(f"{k} {v}" for k, v in stats.get("routes", {}).items()),
                "cpu_s": cpu,
                "ms_per_point": 1e3 * cpu / band.size,
                "rhs_per_point": nfev / band.size,
                "ns_per_rhs": 1e9 * cpu / max(nfev, 1),
            }
        )
    return rows


def point_rhs(spins: np.ndarray) -> np.ndarray:
    """Right-hand-side evaluations of each spin's rig point run alone at the defaults."""
    from obturator.model.cases import rig_case
    from obturator.solve import SolverOptions

    opening_times = _opening_times()
    out = np.empty(spins.size)
    for i, w in enumerate(spins):
        stats = opening_times([rig_case(float(w), MU_S)], SolverOptions())[-1]
        out[i] = int(stats["nfev"]) + int(stats.get("nfev_shared", 0))
    return out


def rhs_floor(calls: int = 200_000) -> dict[str, float]:
    """ns per lane of the thesis kernel's vector loop and ns per scalar right-hand side,
    each the best of three tight compiled loops of `calls` evaluations on slipping rig
    states (300-700 rad/s)."""
    from numba import njit

    from obturator.core.dynamics import rhs
    from obturator.core.integrators.lanes import LANES
    from obturator.core.integrators.lanes.rates import rhs_thesis_lanes
    from obturator.model.cases import rig_case
    from obturator.solve import SolverOptions, pack_points

    @njit
    def lanes_loop(y, p, dy, n):
        s = 0.0
        for _ in range(n):
            rhs_thesis_lanes(y, p, dy, 0)
            s += dy[5 * LANES]
            y[4 * LANES] += 1e-300 * dy[3]  # a dependence, so no call is hoisted
        return s

    @njit
    def scalar_loop(y, p, dy, n):
        s = 0.0
        for _ in range(n):
            rhs(0.0, y, p, dy)
            s += dy[5]
            y[4] += 1e-300 * dy[3]
        return s

    spins = np.linspace(300.0, 700.0, LANES)
    pk = pack_points([rig_case(float(w), MU_S) for w in spins], SolverOptions())
    p = np.ascontiguousarray(pk.p.T).ravel()
    y = np.ascontiguousarray(pk.y0.T).ravel()
    y[4 * LANES : 5 * LANES] += 10.0  # slipping at 10 rad/s about the first body axis
    dy = np.zeros_like(y)
    y1, p1, d1 = pk.y0[0].copy(), pk.p[0].copy(), np.zeros(pk.y0.shape[1])
    y1[4] += 10.0
    lanes_loop(y, p, dy, 10)
    scalar_loop(y1, p1, d1, 10)
    best_l = best_s = np.inf
    for _ in range(3):
        t0 = time.perf_counter()
        lanes_loop(y, p, dy, calls)
        best_l = min(best_l, time.perf_counter() - t0)
        t0 = time.perf_counter()
        scalar_loop(y1, p1, d1, calls)
        best_s = min(best_s, time.perf_counter() - t0)
    return {
        "lanes": int(LANES),
        "ns_per_lane_rhs": 1e9 * best_l / (calls * LANES),
        "ns_per_scalar_rhs": 1e9 * best_s / calls,
    }


def measure(points: int, spins: tuple[float, float], sample: int) -> dict[str, Any]:
    """Bands, the sample's evaluations per point and the floor, in this process."""
    from benchmarks.run import _meta

    grid = np.linspace(spins[0], spins[1], points)
    bands = band_costs(grid)
    per_point = point_rhs(np.linspace(spins[0], spins[1], sample))
    try:
        floor = rhs_floor()
    except Exception as exc:  # noqa: BLE001 - another tree's kernels may not fit this loop
        floor = {"error": repr(exc)}
    if "ns_per_lane_rhs" in floor:
        for row in bands:
            row["over_floor"] = row["ns_per_rhs"] / floor["ns_per_lane_rhs"]
    return {
        "meta": _meta(),
        "points": points,
        "spins": list(spins),
        "bands": bands,
        "median_rhs_per_point": float(np.median(per_point)),
        "rhs_per_point_sample": per_point.tolist(),
        "floor": floor,
        "cpu_s": sum(r["cpu_s"] for r in bands),
    }


def measure_in(tree: Path, points: int, spins: tuple[float, float], sample: int) -> dict:
    """:func:`measure` in another source tree, in a subprocess (its numba cache its own)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "rec.json"
        env = dict(os.environ, PYTHONPATH=f"{Path(tree).resolve() / 'src'}{os.pathsep}{ROOT}")
        cmd = [sys.executable, "-m", "benchmarks.rhs_floor", "--points", str(points),
               "--spins", f"{spins[0]},{spins[1]}", "--sample", str(sample),
               "--json", str(out), "--quiet"]  # fmt: skip
        subprocess.run(cmd, check=True, env=env, cwd=tmp)
        rec = json.loads(out.read_text())
    git = ["git", "-C", str(tree), "rev-parse", "--short", "HEAD"]
    commit = subprocess.run(git, capture_output=True, text=True, check=False).stdout.strip()
    rec["meta"]["git_commit"] = commit or None
    return rec


def print_record(rec: dict[str, Any], label: str) -> None:
    m = rec["meta"]
    print(f"\n{label}: commit {m.get('git_commit')}, {m['cpu']} "
          f"({m['cpus_available']} CPUs available), {rec['points']} points over "
          f"{rec['spins'][0]:g}-{rec['spins'][1]:g} rad/s")  # fmt: skip
    print(f"{'band [rad/s]':>13} {'points':>6} {'ms/point':>9} {'RHS/point':>10} "
          f"{'ns/RHS':>7} {'x floor':>7}  routes")  # fmt: skip
    for r in rec["bands"]:
        over = r.get("over_floor")
        print(f"{r['band']:>13} {r['points']:>6} {r['ms_per_point']:>9.3f} "
              f"{r['rhs_per_point']:>10.0f} {r['ns_per_rhs']:>7.1f} "
              f"{'-' if over is None else f'{over:.1f}':>7}  {r['routes']}")  # fmt: skip
    print(
        f"CPU total {rec['cpu_s']:.2f} s; median RHS per point alone "
        f"({len(rec['rhs_per_point_sample'])} points) {rec['median_rhs_per_point']:.0f}"
    )
    f = rec["floor"]
    if "ns_per_lane_rhs" in f:
        print(
            f"floor: {f['ns_per_lane_rhs']:.2f} ns per lane-RHS ({f['lanes']} lanes, "
            f"thesis kernel), {f['ns_per_scalar_rhs']:.1f} ns per scalar RHS"
        )


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.rhs_floor", description=__doc__)
    ap.add_argument("--points", type=int, default=2000)
    ap.add_argument("--spins", default="40,1000", help="omega_p range LO,HI [rad/s]")
    ap.add_argument("--sample", type=int, default=200, help="points run alone")
    ap.add_argument("--against", type=Path, default=None, help="another source tree")
    ap.add_argument("--json", type=Path, default=None)
    ap.add_argument("--quiet", action="store_true")
    a = ap.parse_args(argv)
    lo, hi = (float(x) for x in a.spins.split(","))
    rec = {"this": measure(a.points, (lo, hi), a.sample)}
    if a.against is not None:
        rec["against"] = measure_in(a.against, a.points, (lo, hi), a.sample)
    if not a.quiet:
        print_record(rec["this"], "this tree")
        if "against" in rec:
            base = rec["against"]
            print_record(base, f"against {a.against}")
            print("\nratios (against / this): CPU per band")
            old = {r["band"]: r for r in base["bands"]}
            for r in rec["this"]["bands"]:
                if r["band"] in old:
                    print(f"{r['band']:>13} {old[r['band']]['cpu_s'] / r['cpu_s']:.2f}x")
            fewer = base["median_rhs_per_point"] / rec["this"]["median_rhs_per_point"]
            print(f"whole range {base['cpu_s'] / rec['this']['cpu_s']:.2f}x; median RHS per "
                  f"point {fewer:.2f}x")  # fmt: skip
    if a.json is not None:
        a.json.write_text(json.dumps(rec if not a.quiet else rec["this"], indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
