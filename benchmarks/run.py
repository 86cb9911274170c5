"""The benchmark: trajectories, compile time, sweeps; rich tables and a JSON record.

Measured (all in one run, wall-clock, ``time.perf_counter``):

* Per trajectory (rig at 300 rad/s, mu_s = 0.5473; flight, Table 1), after
  warm-up, best of several repeats: the baseline (LSODA on plain NumPy), the
  package with its default options (method "auto": DOP853 with a Radau IIA
  fallback, rtol = 1e-8), the package at the baseline's tolerances (rtol =
  1e-6, atol = 1e-9), Radau IIA alone at both, and the package's Rosenbrock
  method. Also nfev, the cost of one right-hand-side evaluation in
  isolation and wall time per evaluation, and t_cr against the baseline
  (required: 1e-3 relative) and against a tight-tolerance reference.
* Compile time: a fresh interpreter with ``NUMBA_CACHE_DIR`` pointed at an
  empty temporary directory (cold: numba compiles) and then at the same,
  now filled, directory (warm: numba loads its cache).
* A 200-point omega_p sweep (100-700 rad/s) of the rig case: the baseline in
  a plain loop, :func:`obturator.solve.opening_time` in a loop, and with 1
  and 2 worker processes (``concurrent.futures.ProcessPoolExecutor`` over
  ``opening_time``, and :func:`obturator.sweeps.run_sweep` when that
  module is present). ``--quick`` shrinks the sweep; ``--big`` adds a
  10,000-point package-only sweep.
* Low spin (40-200 rad/s, long near-stick phases): t_cr, nfev, steps and wall
  time per trajectory for "auto" and "radau" and for each regularisation
  family, with the "auto" hand-overs to Radau.
* The operating range (:mod:`benchmarks.operating_range`): cost per rig point at
  40-1000 rad/s with the DOP853 -> Radau hand-over against the former restart
  (table and ``--plot`` PNG), and sweep throughput over 100-700 and 40-1000 rad/s
  with 1 and 2 workers, each with an accuracy check on 100 random points.
* Command-line latency (:mod:`benchmarks.latency`): ``simulate`` and a 20-point
  ``sweep`` against a plain LSODA loop, process start included.
* Batched sweeps (:mod:`benchmarks.lanes`): points/s of the lanes (DOP853, stiff
  points in Radau IIA lanes) against the same with stiff points one by one and the
  scalar path, for rig (100-700 rad/s, default tolerances and t_cr rtol 1e-6) and
  flight (Mach 1.5-4) sweeps of 1,000 and 10,000 points with 1 and 2 workers, every
  point compared with the scalar path.
* Set-valued stick-slip (:mod:`benchmarks.stick_slip`): cost per trajectory of
  ``method="set-valued"`` against the regularised path at 40-1000 rad/s and flight,
  as ratios, with each t_cr's error against a tight set-valued reference; and the
  40-1000 rad/s sweep with the default ``auto`` (set-valued at low spin) against
  ``regularised``, points/s with 1 and 2 workers and errors on a sample.
* Small batches (:mod:`benchmarks.small_groups`): 1-28 points of the thesis and the
  generic kernel with the lanes forced, with the front door's own rule (groups too
  small for lanes one by one) and in a loop over ``opening_time``, as ratios, and
  whether all three give the same bits.
* Slip-speed laws (:mod:`benchmarks.speed_law_kernel`): the 54 Appendix B spins at the
  validation tolerances in the thesis kernel's variants against the generic right-hand
  side, as ratios, with the t_cr difference.
* Trajectory-coupled openings (:mod:`benchmarks.coupled`): the probability study's
  points through ``FlightModel.evaluate_many`` in lanes against one point at a time.
* Other integrators (:mod:`benchmarks.alternatives`, optional ``.[bench]`` extra):
  numbalsoda's DOP853 and LSODA and diffrax's Tsit5 and Dopri8 on the same trajectory.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from datetime import UTC, datetime
from typing import Any

import numpy as np

from benchmarks.baseline import initial_state as baseline_initial_state
from benchmarks.baseline import model_from_case, solve_baseline
from obturator.model.case import Case
from obturator.model.cases import flight_case, rig_case
from obturator.solve import SolverOptions, opening_time, simulate

MU_S = 0.5473
SWEEP_RANGE = (100.0, 700.0)  # rad/s
BASE_RTOL, BASE_ATOL = 1e-6, 1e-9
AGREEMENT = 1e-3  # required |t_cr(package) / t_cr(baseline) - 1|

# ---------------------------------------------------------------- helpers


def _best_of(fn: Callable[[], Any], repeat: int, warm_up: bool = False) -> tuple[float, float, Any]:
    """(best, median, last result) of `repeat` timed calls [s], after one untimed call
    if `warm_up`."""
    if warm_up:
        fn()
    times = []
    out = None
    for _ in range(max(1, repeat)):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), statistics.median(times), out


def _package_rhs_ns(case: Case, n: int = 200_000) -> float:
    """Cost of one compiled right-hand-side evaluation, called from compiled code [ns]."""
    from numba import njit

    from obturator.core.dynamics import rhs
    from obturator.model.case import initial_state
    from obturator.solve import pack_parameters

    @njit(cache=False)
    def loop(y, p, n):  # pragma: no cover - compiled
        dy = np.empty(y.shape[0])
        acc = 0.0
        for _ in range(n):
            y[4] += 1e-12  # defeat hoisting of the loop-invariant call
            rhs(0.0, y, p, dy)
            acc += dy[4]
        return acc

    opt = SolverOptions()
    y0 = initial_state(case.theta0, case.spin_rate)
    p = pack_parameters(case, opt, y0)
    loop(y0.copy(), p, 10)
    best, _, _ = _best_of(lambda: loop(y0.copy(), p, n), 3)
    return best / n * 1e9


def _baseline_rhs_us(case: Case, n: int = 20_000) -> float:
    """Cost of one plain-Python right-hand-side evaluation [us]."""
    model = model_from_case(case)
    y = baseline_initial_state(model)

    def loop() -> None:
        for _ in range(n):
            model.rhs(0.0, y)

    best, _, _ = _best_of(loop, 3)
    return best / n * 1e6


def _rel(a: float, b: float) -> float:
    return a / b - 1.0 if math.isfinite(a) and math.isfinite(b) else math.nan


# ---------------------------------------------------------------- trajectories


def trajectory(name: str, case: Case, repeat: int, repeat_base: int) -> dict[str, Any]:
    """Baseline vs package on one trajectory to t_cr."""
    model = model_from_case(case)
    solve_baseline(model)  # warm-up (imports, scipy internals)
    b_best, b_med, (b_tcr, b_nfev, _) = _best_of(lambda: solve_baseline(model), repeat_base)
    reference = opening_time(case, SolverOptions(rtol=1e-11, atol=1e-13, method="radau"))
    b_err = abs(_rel(b_tcr, reference))
    variants = {
        "auto (default), rtol=1e-8": SolverOptions(),
        f"auto, baseline tol (rtol={BASE_RTOL:g})": SolverOptions(rtol=BASE_RTOL, atol=BASE_ATOL),
    }
    # work-precision: the loosest tolerance whose t_cr error is no worse than the baseline's
    for rtol in (1e-4, 1e-5, 1e-6, 1e-7, 1e-8):
        opt = SolverOptions(rtol=rtol, atol=rtol * 1e-3)
        if abs(_rel(opening_time(case, opt), reference)) <= b_err:
            variants[f"auto, equal accuracy (rtol={rtol:g})"] = opt
            break
    # no Radau IIA at the baseline's rtol: it cannot resolve the default width below it
    # (obturator.solve.limits refuses that pair)
    variants["radau, rtol=1e-8"] = SolverOptions(method="radau")
    variants["rosenbrock, default rtol=1e-8"] = SolverOptions(method="rosenbrock")
    out: dict[str, Any] = {
        "case": name,
        "spin_rate_rad_s": case.spin_rate,
        "reference_t_cr_s": reference,
        "baseline": {
            "method": f"scipy solve_ivp LSODA rtol={BASE_RTOL:g} atol={BASE_ATOL:g}, NumPy RHS",
            "t_cr_s": b_tcr,
            "wall_s": b_best,
            "wall_median_s": b_med,
            "nfev": b_nfev,
            "rhs_eval_us": _baseline_rhs_us(case),
            "wall_per_nfev_us": b_best / b_nfev * 1e6,
            "error_vs_reference": _rel(b_tcr, reference),
        },
        "package": {},
    }
    rhs_ns = _package_rhs_ns(case)
    for label, opt in variants.items():
        opening_time(case, opt)  # warm-up: the numba cache is loaded once per process
        best, med, t_cr = _best_of(lambda opt=opt: opening_time(case, opt), repeat)
        res = simulate(case, opt)  # same integration, for the counters
        out["package"][label] = {
            "t_cr_s": t_cr,
            "wall_s": best,
            "wall_median_s": med,
            "nfev": res.nfev,
            "njev": res.njev,
            "n_steps": res.n_steps,
            "n_rejected": res.n_rejected,
            "rhs_eval_ns": rhs_ns,
            "wall_per_nfev_us": best / res.nfev * 1e6,
            "speedup_vs_baseline": b_best / best,
            "rel_diff_vs_baseline": _rel(t_cr, b_tcr),
            "agrees_with_baseline": abs(_rel(t_cr, b_tcr)) <= AGREEMENT,
            "error_vs_reference": _rel(t_cr, reference),
        }
    return out


# ---------------------------------------------------------------- compile time

_COMPILE_SNIPPET = """
import json, time
t0 = time.perf_counter()
from obturator.model.cases import rig_case
from obturator.solve import opening_time
from obturator.runs import Runner
t1 = time.perf_counter()
opening_time(rig_case(300.0, 0.5473))
t2 = time.perf_counter()
opening_time(rig_case(300.0, 0.5473))
t3 = time.perf_counter()
print(json.dumps({"import_s": t1 - t0, "first_call_s": t2 - t1, "second_call_s": t3 - t2}))
"""


def compile_times() -> dict[str, Any]:
    """First call in a fresh interpreter with an empty (cold) and a filled (warm) numba cache."""
    out: dict[str, Any] = {}
    with tempfile.TemporaryDirectory(prefix="obturator-numba-cache-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        for label in ("cold", "warm"):
            t0 = time.perf_counter()
            proc = subprocess.run(
                [sys.executable, "-c", _COMPILE_SNIPPET],
                env=env,
                capture_output=True,
                text=True,
                check=True,
            )
            rec = json.loads(proc.stdout.strip().splitlines()[-1])
            rec["process_s"] = time.perf_counter() - t0
            out[label] = rec
    return out


# ---------------------------------------------------------------- sweeps


def _pkg_point(spin: float) -> float:
    """t_cr [s] of the rig case at `spin` [rad/s] (module level: picklable for pools)."""
    return opening_time(rig_case(float(spin), MU_S))


def _pool_sweep(spins: np.ndarray, workers: int) -> tuple[float, np.ndarray]:
    """ProcessPoolExecutor over opening_time; wall time includes starting the pool [s]."""
    chunk = max(1, len(spins) // (8 * workers))
    # Interleave the points so each chunk mixes cheap (fast opening) and costly
    # (sticking, no opening) spins, as a user balancing the load would.
    order = np.argsort(np.arange(len(spins)) % max(1, len(spins) // chunk), kind="stable")
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=workers) as pool:
        vals = list(pool.map(_pkg_point, spins[order].tolist(), chunksize=chunk))
    wall = time.perf_counter() - t0
    t_cr = np.empty(len(spins))
    t_cr[order] = vals
    return wall, t_cr


def _studies_sweep(spins: np.ndarray, workers: int) -> tuple[float, np.ndarray] | None:
    try:
        from obturator.runs import Runner
        from obturator.sweeps import SweepSpec, run_sweep
    except ImportError:  # pragma: no cover - depends on the installed package
        return None
    spec = SweepSpec(case="spin-rig", axes={"spin_rate": spins}, fixed={"mu_s": MU_S})
    warm = SweepSpec(case="spin-rig", axes={"spin_rate": spins[:2]}, fixed={"mu_s": MU_S})
    run_sweep(warm, runner=Runner(workers=1))  # lazy imports (xarray) outside the timing
    t0 = time.perf_counter()
    ds = run_sweep(spec, runner=Runner(workers=workers))
    return time.perf_counter() - t0, np.asarray(ds["t_cr"].values, dtype=float)


def _agreement(a: np.ndarray, b: np.ndarray) -> dict[str, Any]:
    both = np.isfinite(a) & np.isfinite(b)
    rel = np.abs(a[both] / b[both] - 1.0)
    return {
        "both_opened": int(both.sum()),
        "open_status_mismatches": int(np.sum(np.isfinite(a) != np.isfinite(b))),
        "max_rel_diff": float(rel.max()) if rel.size else math.nan,
        "median_rel_diff": float(np.median(rel)) if rel.size else math.nan,
    }


def sweep(n_points: int, *, baseline: bool, workers: Sequence[int]) -> dict[str, Any]:
    """omega_p sweep of the rig case: baseline loop, package loop and worker pools."""
    spins = np.linspace(*SWEEP_RANGE, n_points)
    out: dict[str, Any] = {"n_points": n_points, "spin_range_rad_s": list(SWEEP_RANGE)}
    _pkg_point(300.0)  # warm
    t0 = time.perf_counter()
    serial = np.array([_pkg_point(w) for w in spins])
    wall = time.perf_counter() - t0
    out["package_loop"] = {
        "wall_s": wall,
        "throughput_per_s": n_points / wall,
        "n_opened": int(np.isfinite(serial).sum()),
    }
    if baseline:
        t_b = np.empty(n_points)
        per_point = np.empty(n_points)
        t0 = time.perf_counter()
        for i, w in enumerate(spins):
            t1 = time.perf_counter()
            t_b[i] = solve_baseline(model_from_case(rig_case(float(w), MU_S)))[0]
            per_point[i] = time.perf_counter() - t1
        wall_b = time.perf_counter() - t0
        opened = np.isfinite(t_b)
        out["baseline_loop"] = {
            "wall_s": wall_b,
            "throughput_per_s": n_points / wall_b,
            "n_opened": int(opened.sum()),
            "wall_opened_points_s": float(per_point[opened].sum()),
            "wall_not_opened_points_s": float(per_point[~opened].sum()),
        }
        out["speedup_loop"] = wall_b / wall
        out["agreement_vs_baseline"] = _agreement(serial, t_b)
    for k in workers:
        wall_k, t_k = _pool_sweep(spins, k)
        out[f"pool_{k}_workers"] = {
            "wall_s": wall_k,
            "throughput_per_s": n_points / wall_k,
            "identical_to_loop": bool(np.array_equal(t_k, serial, equal_nan=True)),
        }
        st = _studies_sweep(spins, k)
        if st is not None:
            out[f"studies_sweep_{k}_workers"] = {
                "wall_s": st[0],
                "throughput_per_s": n_points / st[0],
                "identical_to_loop": bool(np.array_equal(st[1], serial, equal_nan=True)),
            }
    return out


# ---------------------------------------------------------------- report


LOW_SPINS = (40.0, 60.0, 78.0, 100.0, 125.0, 150.0, 175.0, 200.0)
LOW_SPINS_QUICK = (78.0, 150.0, 200.0)


def low_spin_cost(spins: Sequence[float], repeat: int) -> list[dict[str, Any]]:
    """Cost of one rig trajectory at low spin (long near-stick phases), mu_s = 0.5473.

    For each spin: "auto" and "radau" with the default (algebraic) family, and
    "auto" with the tanh and linear families; t_cr, nfev, steps, best wall time, and
    whether "auto" fell back to Radau (njev > 0).
    """
    from dataclasses import replace

    rows = []
    runs = [("auto", "algebraic"), ("radau", "algebraic"), ("auto", "tanh"), ("auto", "linear")]
    for w in spins:
        case = rig_case(w, MU_S)
        for method, family in runs:
            opts = replace(SolverOptions(), method=method, friction_family=family)
            best, _, res = _best_of(lambda c=case, o=opts: simulate(c, o), repeat)
            rows.append(
                {
                    "spin_rad_s": w,
                    "method": method,
                    "family": family,
                    "t_cr_s": res.opening_time,
                    "status": res.status,
                    "nfev": res.nfev,
                    "n_steps": res.n_steps,
                    "radau_fallback": method == "auto" and res.njev > 0,
                    "wall_s": best,
                }
            )
    return rows


def _fmt(x: float, unit: str = "", digits: int = 3) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "-"
    return f"{x:.{digits}g}{unit}"


def _print_report(rec: dict[str, Any]) -> None:
    from rich.console import Console
    from rich.table import Table

    con = Console() if sys.stdout.isatty() else Console(width=160)
    con.print(f"[bold]obturator benchmark[/bold]  {rec['meta']['date']}  {rec['meta']['cpu']}")
    for tr in rec["trajectories"]:
        t = Table(title=f"{tr['case']}: one trajectory to t_cr (best of repeats, after warm-up)")
        for col in (
            "solver",
            "wall (ms)",
            "speed-up",
            "nfev",
            "steps",
            "wall/nfev (us)",
            "t_cr (s)",
            "vs baseline",
            "vs reference",
        ):
            t.add_column(col, justify="right" if col != "solver" else "left")
        b = tr["baseline"]
        t.add_row(
            "baseline: LSODA, NumPy RHS",
            _fmt(b["wall_s"] * 1e3),
            "1",
            str(b["nfev"]),
            "-",
            _fmt(b["wall_per_nfev_us"]),
            f"{b['t_cr_s']:.10f}",
            "-",
            _fmt(b["error_vs_reference"], "", 2),
        )
        for label, p in tr["package"].items():
            t.add_row(
                label,
                _fmt(p["wall_s"] * 1e3),
                _fmt(p["speedup_vs_baseline"], "x"),
                str(p["nfev"]),
                str(p["n_steps"]),
                _fmt(p["wall_per_nfev_us"]),
                f"{p['t_cr_s']:.10f}",
                _fmt(p["rel_diff_vs_baseline"], "", 2)
                + ("" if p["agrees_with_baseline"] else " [red]FAIL[/red]"),
                _fmt(p["error_vs_reference"], "", 2),
            )
        con.print(t)
        pk = next(iter(tr["package"].values()))
        rhs_ratio = b["rhs_eval_us"] * 1e3 / pk["rhs_eval_ns"]
        con.print(
            f"  one RHS evaluation: baseline {_fmt(b['rhs_eval_us'])} us (NumPy), package "
            f"{_fmt(pk['rhs_eval_ns'])} ns (compiled): {_fmt(rhs_ratio)}x;"
            f" reference t_cr {tr['reference_t_cr_s']:.12f} s (radau rtol=1e-11);"
            f" agreement required: {AGREEMENT:g} relative\n"
        )
    if rec["compile"]:
        ct = Table(title="compile time: first opening_time() in a fresh interpreter")
        for col in ("numba cache", "import", "first call", "second call", "process"):
            ct.add_column(col, justify="right")
        for label, c in rec["compile"].items():
            ct.add_row(
                label,
                _fmt(c["import_s"], " s"),
                _fmt(c["first_call_s"], " s"),
                _fmt(c["second_call_s"] * 1e3, " ms"),
                _fmt(c["process_s"], " s"),
            )
        con.print(ct)
    for key in ("sweep", "big_sweep"):
        sw = rec.get(key)
        if not sw:
            continue
        st = Table(
            title=f"rig omega_p sweep: {sw['n_points']} points, "
            f"{sw['spin_range_rad_s'][0]:g}-{sw['spin_range_rad_s'][1]:g} rad/s, mu_s {MU_S}"
        )
        for col in ("runner", "wall", "trajectories/s", "note"):
            st.add_column(col, justify="right" if col != "runner" else "left")
        for name, r in sw.items():
            if not isinstance(r, dict) or "wall_s" not in r:
                continue
            note = ""
            if "n_opened" in r:
                note = f"{r['n_opened']} opened"
            if "identical_to_loop" in r:
                note = "t_cr identical to loop" if r["identical_to_loop"] else "DIFFERS from loop"
            st.add_row(name, _fmt(r["wall_s"], " s"), _fmt(r["throughput_per_s"]), note)
        con.print(st)
        if "agreement_vs_baseline" in sw:
            a = sw["agreement_vs_baseline"]
            con.print(
                f"  sweep speed-up (loop vs loop): {_fmt(sw['speedup_loop'])}x; "
                f"t_cr vs baseline on {a['both_opened']} opened points: max rel diff "
                f"{_fmt(a['max_rel_diff'], '', 2)}, median {_fmt(a['median_rel_diff'], '', 2)}; "
                f"opened/not-opened mismatches: {a['open_status_mismatches']}"
            )


def _print_low_spin(rows: list[dict[str, Any]]) -> None:
    from rich.console import Console
    from rich.table import Table

    t = Table(title=f"rig trajectories at low spin (mu_s {MU_S}, default tolerances and width)")
    for col in ("omega_p", "method", "family", "t_cr", "nfev", "steps", "fallback", "wall"):
        t.add_column(col, justify="right")
    for r in rows:
        t.add_row(
            f"{r['spin_rad_s']:g}",
            r["method"],
            r["family"],
            _fmt(r["t_cr_s"], " s", 6),
            str(r["nfev"]),
            str(r["n_steps"]),
            "yes" if r["radau_fallback"] else "",
            _fmt(r["wall_s"] * 1e3, " ms"),
        )
    Console().print(t)


def _meta() -> dict[str, Any]:
    import numba
    import scipy

    try:
        commit = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True, check=True
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        commit = None
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return {
        "date": datetime.now(UTC).isoformat(timespec="seconds"),
        "git_commit": commit,
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "numba": numba.__version__,
        "platform": platform.platform(),
        "cpu": cpu,
        "cpu_count": os.cpu_count(),
        "cpus_available": len(os.sched_getaffinity(0))
        if hasattr(os, "sched_getaffinity")
        else os.cpu_count(),
    }


def main(argv: Sequence[str] | None = None) -> int:
    """Command-line entry point (``python -m benchmarks``).

    ``python -m benchmarks report ...`` runs :func:`benchmarks.report.main` instead
    (measure and rewrite the measured sections of ``docs/benchmarks.md``).

    Returns
    -------
    int
        0, or 1 when a package t_cr disagrees with the baseline by more than 1e-3.
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["report"]:  # python -m benchmarks report: rewrite docs/benchmarks.md
        from benchmarks import report

        return report.main(argv[1:])
    ap = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.split("\n")[0])
    ap.add_argument("--json", metavar="PATH", help="write the results as JSON to PATH")
    ap.add_argument("--quick", action="store_true", help="small sweep and fewer repeats (CI)")
    ap.add_argument("--big", action="store_true", help="add a 10,000-point package-only sweep")
    ap.add_argument("--sweep-points", type=int, default=None, help="sweep size (default 200)")
    ap.add_argument(
        "--no-compile", action="store_true", help="skip the cold/warm compile-time subprocesses"
    )
    ap.add_argument("--plot", metavar="PNG", default=None, help="cost per point vs omega_p figure")
    ap.add_argument(
        "--throughput-points",
        type=int,
        default=None,
        help="points of the throughput sweeps (default 10000; --quick 200)",
    )
    ap.add_argument(
        "--lanes-sizes",
        default=None,
        help="point counts of the lanes-vs-scalar sweeps (default 1000,10000; --quick 100)",
    )
    args = ap.parse_args(argv)
    n_sweep = args.sweep_points or (7 if args.quick else 200)
    repeat, repeat_base = (5, 1) if args.quick else (30, 3)

    rec: dict[str, Any] = {"meta": _meta(), "settings": vars(args)}
    rec["trajectories"] = [
        trajectory("rig 300 rad/s", rig_case(300.0, MU_S), repeat, repeat_base),
        trajectory("flight (Table 1)", flight_case(), repeat, repeat_base),
    ]
    rec["compile"] = {} if args.no_compile else compile_times()
    rec["low_spin"] = low_spin_cost(LOW_SPINS_QUICK if args.quick else LOW_SPINS, repeat)
    rec["sweep"] = sweep(n_sweep, baseline=True, workers=(1, 2))
    if args.big:
        rec["big_sweep"] = sweep(10_000, baseline=False, workers=(2,))
    from benchmarks import latency, operating_range

    rec["cost_per_point"] = operating_range.cost_per_point(
        operating_range.RANGE_SPINS_QUICK if args.quick else operating_range.RANGE_SPINS,
        3 if args.quick else 10,
    )
    n_tp = args.throughput_points or (200 if args.quick else 10_000)
    rec["throughput"] = [
        operating_range.throughput(n_tp, rng, k)
        for rng in ((100.0, 700.0), (40.0, 1000.0))
        for k in (1, 2)
    ]
    from benchmarks import lanes

    lanes.warm()
    rec["lanes"] = [
        lanes.measure(case, int(n), k, tcr_rtol=tol)
        for n in (args.lanes_sizes or ("100" if args.quick else "1000,10000")).split(",")
        for case, tol in (("rig", "default"), ("rig", "1e-6"), ("flight", "default"))
        for k in (1, 2)
    ]
    from benchmarks import stick_slip

    rec["stick_slip"] = stick_slip.cost(
        stick_slip.SPINS_QUICK if args.quick else stick_slip.SPINS, 2 if args.quick else 5
    )
    rec["stick_slip_sweep"] = stick_slip.sweep(n_tp)
    from benchmarks import small_groups

    rec["small_groups"] = small_groups.cost(
        small_groups.SIZES_QUICK if args.quick else small_groups.SIZES, 2 if args.quick else 5
    )
    from benchmarks import speed_law_kernel

    rec["speed_law_kernel"] = speed_law_kernel.cost(2 if args.quick else 5)
    from benchmarks import coupled

    rec["coupled"] = coupled.cost(coupled.SIZES_QUICK if args.quick else coupled.SIZES)
    rec["cli_latency"] = latency.cli_latency(2 if args.quick else 5)
    from benchmarks import alternatives

    rec["alternatives"] = alternatives.alternatives(5 if args.quick else 20)
    _print_report(rec)
    _print_low_spin(rec["low_spin"])
    operating_range.print_range(rec["cost_per_point"], rec["throughput"])
    lanes.print_table(rec["lanes"])
    stick_slip.print_table(rec["stick_slip"])
    stick_slip.print_sweep(rec["stick_slip_sweep"])
    small_groups.print_table(rec["small_groups"])
    speed_law_kernel.print_table(rec["speed_law_kernel"])
    coupled.print_table(rec["coupled"])
    latency.print_latency(rec["cli_latency"])
    alternatives.print_alternatives(rec["alternatives"])
    if args.plot:
        operating_range.plot_cost(rec["cost_per_point"], args.plot)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rec, fh, indent=2, default=float)
    ok = all(
        p["agrees_with_baseline"] for tr in rec["trajectories"] for p in tr["package"].values()
    )
    agree = rec["sweep"].get("agreement_vs_baseline", {})
    ok = ok and not (agree.get("max_rel_diff", 0.0) > AGREEMENT)
    ok = ok and all(lanes.agrees(r) for r in rec["lanes"])
    ok = ok and all(r["same_bits"] for r in rec["small_groups"])
    return 0 if ok else 1
