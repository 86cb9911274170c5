"""Trajectory-coupled openings in lanes against one point at a time.

``python -m benchmarks.coupled [--quick] [--json PATH]``; also part of
``python -m benchmarks``. The points of ``obturator probability``'s default study
(Mach 1.75 at 6000 m, mu_s and theta_0 drawn as its defaults, seeded), each a
trajectory-coupled opening with its convergence reruns (tolerances, width, family,
half segment): wall time of :meth:`obturator.envelope.model.FlightModel.evaluate_many`
on all points at once (every segment of every running point one call of
:func:`obturator.solve.advance`, the SIMD lanes) against the same function called
with one point at a time, in the same process, and the largest relative difference
of their t_cr (the lanes' rounding).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from obturator.envelope.model import FlightModel, warm_integrators
from obturator.envelope.trajectory import Launch

SIZES = (16, 64)
SIZES_QUICK = (16,)


def _points(n: int) -> list[dict[str, float]]:
    rng = np.random.default_rng(1)
    mu = rng.lognormal(math.log(0.35), 0.1, n)
    theta0 = rng.uniform(86.25, 88.25, n)
    return [{"mu_s": float(m), "theta0_deg": float(t)} for m, t in zip(mu, theta0, strict=True)]


def measure(n: int) -> dict[str, Any]:
    """One row: n points in one batch and one by one."""
    model = FlightModel(launch=Launch(mach=1.75, altitude_m=6000.0))
    pts = _points(n)
    model.evaluate_many(pts[:2])  # flights cached, code loaded
    t0 = time.perf_counter()
    many = model.evaluate_many(pts)
    t_many = time.perf_counter() - t0
    t0 = time.perf_counter()
    one = [model.evaluate_many([p])[0] for p in pts]
    t_one = time.perf_counter() - t0
    a = np.array([r["t_cr"] for r in many])
    b = np.array([r["t_cr"] for r in one])
    ok = np.isfinite(a) & np.isfinite(b)
    return {
        "points": n,
        "batch_s": t_many,
        "one_by_one_s": t_one,
        "speed_up": t_one / t_many,
        "max_rel_difference": float(np.max(np.abs(a[ok] / b[ok] - 1.0))) if ok.any() else math.nan,
        "same_statuses": [r["status"] for r in many] == [r["status"] for r in one],
    }


def cost(sizes: Sequence[int]) -> list[dict[str, Any]]:
    """Rows of :func:`measure` (after loading the compiled code)."""
    warm_integrators()
    return [measure(int(n)) for n in sizes]


def print_table(rows: list[dict[str, Any]]) -> None:
    """Rich table of :func:`cost`."""
    from rich.console import Console
    from rich.table import Table

    t = Table(title="Trajectory-coupled openings (probability's study): lanes vs one by one")
    for col in ("points", "batch (s)", "one by one (s)", "speed-up", "max |rel. diff|", "statuses"):
        t.add_column(col, justify="right")
    for r in rows:
        t.add_row(
            str(r["points"]), f"{r['batch_s']:.2f}", f"{r['one_by_one_s']:.2f}",
            f"{r['speed_up']:.1f}x", f"{r['max_rel_difference']:.1e}",
            "same" if r["same_statuses"] else "DIFFER",
        )  # fmt: skip
    Console().print(t)


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m benchmarks.coupled``."""
    from benchmarks._module import run_module

    def rows_of(quick: bool) -> list[dict[str, Any]]:
        return cost(SIZES_QUICK if quick else SIZES)

    prog = "python -m benchmarks.coupled"
    return run_module(prog, "16 points only", rows_of, print_table, argv)


if __name__ == "__main__":
    raise SystemExit(main())
