"""Batched sweeps (DOP853 in lanes) against the scalar path, same run, same machine.

``python -m benchmarks.lanes [--sizes 1000,10000] [--workers 1,2] [--json FILE]``

For each size, case and worker count: a sweep through
:func:`obturator.sweeps.execute_sweep` in lanes and with ``OBTURATOR_LANES=0``
(one trajectory at a time), points/s as the sweep reports them (pool start
included), the ratio, and the accuracy of the batched results: every point
against the scalar path's t_cr (same options) and a seeded sample of 100
against Radau IIA at rtol 1e-11.

* rig: omega_p over 100-700 rad/s, mu_s = 0.5473 (thesis);
* flight: Mach 1.5-4 (Table 1 otherwise).
"""

from __future__ import annotations

import argparse
import json
import os
from typing import Any

import numpy as np

from obturator.model.cases import flight_case, rig_case
from obturator.solve import SolverOptions, opening_time
from obturator.sweeps import SweepSpec, execute_sweep

MU_S = 0.5473
REFERENCE = SolverOptions(method="radau", rtol=1e-11, atol=1e-13)


def _spec(case: str, n: int) -> tuple[SweepSpec, np.ndarray]:
    if case == "rig":
        x = np.linspace(100.0, 700.0, n)
        return SweepSpec(case="spin-rig", axes={"spin_rate": x}, fixed={"mu_s": MU_S}), x
    x = np.linspace(1.5, 4.0, n)
    return SweepSpec(case="flight", axes={"mach": x}), x


def _sweep(spec: SweepSpec, workers: int, lanes: bool) -> tuple[float, np.ndarray]:
    old = os.environ.get("OBTURATOR_LANES")
    os.environ["OBTURATOR_LANES"] = "1" if lanes else "0"
    try:
        run = execute_sweep(spec, workers=workers, progress=False)
    finally:
        if old is None:
            del os.environ["OBTURATOR_LANES"]
        else:
            os.environ["OBTURATOR_LANES"] = old
    return run.elapsed_s, np.asarray(run.dataset["t_cr"].values, dtype=float).ravel()


def _reference(case: str, x: float) -> float:
    c = rig_case(x, MU_S) if case == "rig" else flight_case(mach=x)
    return opening_time(c, REFERENCE)


def measure(case: str, n: int, workers: int, scalar: bool = True) -> dict[str, Any]:
    """One size/case/worker count: both paths, their ratio and the accuracy checks."""
    spec, x = _spec(case, n)
    t_lane, tcr = _sweep(spec, workers, True)
    rec: dict[str, Any] = {
        "case": case,
        "n_points": n,
        "workers": workers,
        "lanes_s": t_lane,
        "lanes_points_per_s": n / t_lane,
    }
    if scalar:
        t_scalar, tcr_s = _sweep(spec, workers, False)
        rec |= {
            "scalar_s": t_scalar,
            "scalar_points_per_s": n / t_scalar,
            "speedup": t_scalar / t_lane,
            "max_rel_diff_vs_scalar": float(np.nanmax(np.abs(tcr / tcr_s - 1.0))),
            "same_nan": bool(np.array_equal(np.isnan(tcr), np.isnan(tcr_s))),
        }
    rng = np.random.default_rng(12)
    sample = rng.choice(n, size=min(100, n), replace=False)
    errs = [abs(tcr[i] / _reference(case, float(x[i])) - 1.0) for i in sample]
    rec["max_rel_error_vs_reference"] = float(np.nanmax(errs))
    return rec


def warm() -> None:
    """Compile or load every path outside the timings."""
    for case in ("rig", "flight"):
        spec, _ = _spec(case, 3)
        _sweep(spec, 1, True)
        _sweep(spec, 1, False)


def print_table(rows: list[dict[str, Any]]) -> None:
    """A rich table of :func:`measure` records."""
    from rich.console import Console
    from rich.table import Table

    t = Table(title="sweeps: DOP853 lanes vs one trajectory at a time (pool start included)")
    for col in ("case", "points", "workers", "lanes pts/s", "scalar pts/s", "speed-up",
                "max |diff| vs scalar", "max err vs Radau 1e-11"):  # fmt: skip
        t.add_column(col, justify="right")
    for r in rows:
        t.add_row(
            r["case"], f"{r['n_points']:,}", str(r["workers"]), f"{r['lanes_points_per_s']:,.0f}",
            f"{r['scalar_points_per_s']:,.0f}" if "scalar_s" in r else "-",
            f"{r['speedup']:.2f}x" if "speedup" in r else "-",
            f"{r['max_rel_diff_vs_scalar']:.1e}" if "speedup" in r else "-",
            f"{r['max_rel_error_vs_reference']:.1e}",
        )  # fmt: skip
    Console(width=160).print(t)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.lanes", description=__doc__)
    ap.add_argument("--sizes", default="1000,10000", help="comma-separated point counts")
    ap.add_argument("--workers", default="1,2", help="comma-separated worker counts")
    ap.add_argument("--cases", default="rig,flight")
    ap.add_argument(
        "--scalar-max", type=int, default=10_000, help="largest size also run on the scalar path"
    )
    ap.add_argument("--json", default=None, help="write the records here")
    a = ap.parse_args(argv)
    warm()
    rows = []
    for n in (int(s) for s in a.sizes.split(",")):
        for case in a.cases.split(","):
            for w in (int(s) for s in a.workers.split(",")):
                rows.append(measure(case, n, w, scalar=n <= a.scalar_max))
                print(json.dumps(rows[-1]), flush=True)
    print_table(rows)
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(rows, fh, indent=1, default=lambda v: None if v != v else v)
    return 0 if all(r.get("same_nan", True) for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
