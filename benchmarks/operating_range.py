"""Cost across the rig's operating range, the DOP853 -> Radau hand-over, sweep throughput.

* :func:`cost_per_point`: one rig trajectory (mu_s = 0.5473, default options) at
  omega_p = 40-1000 rad/s: t_cr, right-hand-side calls, whether and when DOP853
  handed the run to Radau IIA, and the best wall time; beside it the cost of the
  former fallback (the DOP853 attempt, then Radau from t = 0) for the same run.
* :func:`plot_cost`: those costs against omega_p (PNG).
* :func:`throughput`: a rig sweep through :func:`obturator.sweeps.execute_sweep`
  (points/s as the sweep itself reports them) and its accuracy: a seeded random
  sample of points recomputed with Radau IIA at rtol 1e-11, the worst relative
  t_cr difference reported.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from obturator.core.integrators import auto_radau_tolerances, method_module
from obturator.model.cases import rig_case
from obturator.runs import Runner
from obturator.solve import SolverOptions, integration_setup, opening_time, simulate

MU_S = 0.5473
RANGE_SPINS = (40.0, 60.0, 78.0, 100.0, 125.0, 150.0, 200.0, 300.0, 500.0, 700.0, 1000.0)
RANGE_SPINS_QUICK = (78.0, 150.0, 300.0, 700.0)
REFERENCE = SolverOptions(method="radau", rtol=1e-11, atol=1e-13)


def _best(fn, repeat: int) -> tuple[float, Any]:
    best, out = math.inf, None
    for _ in range(max(1, repeat)):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def _raw(case, method: str, as_in_auto: bool = False):
    """One compiled integrator on `case` with the default options (no hand-over); with
    `as_in_auto` at the tolerances ``auto`` gives its Radau IIA stretches."""
    problem, controls = integration_setup(case, SolverOptions())
    if as_in_auto:
        rtol, atol = auto_radau_tolerances(controls.rtol, controls.atol)
        controls = controls._replace(rtol=rtol, atol=atol)
    return method_module(method).integrate(problem, controls)


def cost_per_point(spins: Sequence[float], repeat: int) -> list[dict[str, Any]]:
    """Cost of one rig trajectory per spin rate (see the module docstring)."""
    rows = []
    for w in spins:
        case = rig_case(float(w), MU_S)
        wall, res = _best(lambda c=case: simulate(c), repeat)
        dop = _raw(case, "dop853")
        handed = bool(res.njev > 0)
        row = {
            "spin_rad_s": float(w),
            "t_cr_s": res.opening_time,
            "nfev": int(res.nfev),
            "hand_over": handed,
            "hand_over_at_s": float(dop.t_end) if handed else math.nan,
            "wall_s": wall,
        }
        if handed:  # the former fallback: the DOP853 attempt, then Radau from t = 0
            # (at the tolerances auto gives its Radau stretches, for a like comparison)
            w_dop, _ = _best(lambda c=case: _raw(c, "dop853"), repeat)
            w_rad, rad = _best(lambda c=case: _raw(c, "radau", as_in_auto=True), repeat)
            row["restart_wall_s"] = w_dop + w_rad
            row["restart_nfev"] = int(dop.nfev + rad.nfev)
        rows.append(row)
    return rows


def plot_cost(rows: list[dict[str, Any]], path: str) -> None:
    """Wall time and right-hand-side calls per trajectory against omega_p (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    w = np.array([r["spin_rad_s"] for r in rows])
    wall = np.array([r["wall_s"] for r in rows]) * 1e3
    restart = np.array([r.get("restart_wall_s", np.nan) for r in rows]) * 1e3
    nfev = np.array([r["nfev"] for r in rows])
    fig, ax = plt.subplots(figsize=(6.4, 4.0), layout="constrained")
    ax.loglog(w, wall, "o-", label="auto (to Radau IIA and back, in flight)")
    ax.loglog(w, restart, "s--", label="DOP853 attempt + Radau from t = 0 (former)")
    ax.set_xlabel(r"spin rate $\omega_p$ [rad/s]")
    ax.set_ylabel("wall time per trajectory [ms]")
    ax.grid(True, which="both", alpha=0.3)
    ax2 = ax.twinx()
    ax2.loglog(w, nfev, ":", color="0.5", label="RHS calls (auto)")
    ax2.set_ylabel("right-hand-side calls", color="0.4")
    lines = ax.get_legend_handles_labels()
    lines2 = ax2.get_legend_handles_labels()
    ax.legend(lines[0] + lines2[0], lines[1] + lines2[1], fontsize=8, loc="upper center")
    ax.set_title(f"rig, mu_s = {MU_S}, default options: cost per point")
    fig.savefig(path, dpi=120)
    plt.close(fig)


def throughput(
    n_points: int,
    spin_range: tuple[float, float],
    workers: int,
    *,
    options: SolverOptions | None = None,
    n_check: int = 100,
    seed: int = 12,
    reference: SolverOptions = REFERENCE,
) -> dict[str, Any]:
    """A rig sweep's points/s (as the sweep reports it) and its accuracy on a sample
    against `reference` (default Radau IIA at rtol 1e-11, the same width)."""
    from obturator.sweeps import SweepSpec, execute_sweep

    opts = options or SolverOptions()
    spins = np.linspace(*spin_range, n_points)
    spec = SweepSpec(case="spin-rig", axes={"spin_rate": spins}, fixed={"mu_s": MU_S}, options=opts)
    ends = spins[[0, -1]]  # both ends, so every integrator the sweep meets is loaded
    warm = SweepSpec(case="spin-rig", axes={"spin_rate": ends}, fixed={"mu_s": MU_S}, options=opts)
    execute_sweep(warm, runner=Runner(workers=1))  # imports and caches outside the timing
    run = execute_sweep(spec, runner=Runner(workers=workers))
    t_cr = np.asarray(run.dataset["t_cr"].values, dtype=float)
    rng = np.random.default_rng(seed)
    sample = rng.choice(n_points, size=min(n_check, n_points), replace=False)
    errs = []
    for i in sample:
        ref = opening_time(rig_case(float(spins[i]), MU_S), reference)
        if math.isfinite(ref) and math.isfinite(t_cr[i]):
            errs.append(abs(t_cr[i] / ref - 1.0))
        elif math.isfinite(ref) != math.isfinite(t_cr[i]):
            errs.append(math.inf)
    return {
        "n_points": n_points,
        "spin_range_rad_s": list(spin_range),
        "workers": run.workers,
        "rtol": opts.rtol,
        "method": opts.method,
        "compute_s": run.elapsed_s,
        "points_per_s": n_points / run.elapsed_s,
        "n_checked": len(errs),
        "max_rel_error": max(errs) if errs else math.nan,
        "median_rel_error": float(np.median(errs)) if errs else math.nan,
    }


def print_range(rows: list[dict[str, Any]], tput: list[dict[str, Any]]) -> None:
    """Rich tables of :func:`cost_per_point` and :func:`throughput` results."""
    from rich.console import Console
    from rich.table import Table

    con = Console(width=160)
    t = Table(title=f"rig cost per point across the operating range (mu_s {MU_S}, defaults)")
    for col in ("omega_p", "t_cr", "nfev", "hand-over at", "wall", "former fallback", "ratio"):
        t.add_column(col, justify="right")
    for r in rows:
        former = r.get("restart_wall_s", math.nan)
        t.add_row(
            f"{r['spin_rad_s']:g}",
            f"{r['t_cr_s']:.6g} s",
            str(r["nfev"]),
            f"{r['hand_over_at_s'] * 1e3:.3g} ms" if r["hand_over"] else "-",
            f"{r['wall_s'] * 1e3:.3g} ms",
            f"{former * 1e3:.3g} ms ({r['restart_nfev']} nfev)" if r["hand_over"] else "-",
            f"{former / r['wall_s']:.2f}x" if r["hand_over"] else "-",
        )
    con.print(t)
    if tput:
        t = Table(title="rig sweep throughput (points/s as the sweep reports them) and accuracy")
        for col in ("points", "range", "workers", "rtol", "compute", "points/s", "max err (n)"):
            t.add_column(col, justify="right")
        for r in tput:
            lo, hi = r["spin_range_rad_s"]
            t.add_row(
                str(r["n_points"]),
                f"{lo:g}-{hi:g} rad/s",
                str(r["workers"]),
                f"{r['rtol']:g}",
                f"{r['compute_s']:.3g} s",
                f"{r['points_per_s']:.0f}",
                f"{r['max_rel_error']:.1e} ({r['n_checked']})",
            )
        con.print(t)
        con.print("  accuracy: a seeded random sample recomputed with Radau IIA at rtol 1e-11\n")
