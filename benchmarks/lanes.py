"""Batched sweeps (DOP853 and Radau IIA in lanes) against the scalar path, same run.

``python -m benchmarks.lanes [--sizes 1000,10000] [--workers 1,2] [--tcr-rtol default,1e-6]
[--json FILE]``

For each size, case, tolerance setting and worker count: a sweep through
:func:`obturator.sweeps.execute_sweep` in lanes, in lanes with the stiff points
continued in the scalar Radau IIA (the solver option ``radau_lanes=False``) and
one trajectory at a time (``lanes=False, radau_lanes=False``); points/s as the
sweep reports them (pool start included, compiled code loaded beforehand), the
ratios, and the accuracy of the batched results: every point against the scalar
path's t_cr (same options) and a seeded sample of 100 against Radau IIA at rtol
1e-11. ``default`` is rtol 1e-8; ``1e-6`` the tolerances
``SolverOptions.for_opening_time_accuracy(1e-6, method="regularised")`` chooses (rtol
1e-10; the default method auto keeps rtol 1e-8 for 1e-6).

* rig: omega_p over 100-700 rad/s, mu_s = 0.5473 (thesis);
* flight: Mach 1.5-4 (Table 1 otherwise).
"""

from __future__ import annotations

import argparse
import json
from dataclasses import replace
from typing import Any

import numpy as np

from obturator.model.cases import flight_case, rig_case
from obturator.runs import Runner
from obturator.solve import OPENING_TIME_ACCURACY, SolverOptions, opening_time
from obturator.sweeps import SweepSpec, execute_sweep

MU_S = 0.5473
REFERENCE = SolverOptions(method="radau", rtol=1e-11, atol=1e-13)


def _options(tcr_rtol: str) -> SolverOptions:
    if tcr_rtol == "default":
        return SolverOptions()
    return SolverOptions.for_opening_time_accuracy(float(tcr_rtol), method="regularised")


def _spec(case: str, n: int, tcr_rtol: str = "default") -> tuple[SweepSpec, np.ndarray]:
    o = _options(tcr_rtol)
    if case == "rig":
        x = np.linspace(100.0, 700.0, n)
        spec = SweepSpec(case="spin-rig", axes={"spin_rate": x}, fixed={"mu_s": MU_S}, options=o)
        return spec, x
    x = np.linspace(1.5, 4.0, n)
    return SweepSpec(case="flight", axes={"mach": x}, options=o), x


#: path -> the solver options (lanes, radau_lanes) it sets
_PATHS = {
    "lanes": {"lanes": True, "radau_lanes": True},
    "stiff-one-by-one": {"lanes": True, "radau_lanes": False},
    "scalar": {"lanes": False, "radau_lanes": False},
}


def _sweep(spec: SweepSpec, workers: int, path: str) -> tuple[float, np.ndarray]:
    spec = replace(spec, options=replace(spec.options, **_PATHS[path]))
    run = execute_sweep(spec, runner=Runner(workers=workers))
    return run.elapsed_s, np.asarray(run.dataset["t_cr"].values, dtype=float).ravel()


def _reference(case: str, x: float) -> float:
    c = rig_case(x, MU_S) if case == "rig" else flight_case(mach=x)
    return opening_time(c, REFERENCE)


def measure(
    case: str, n: int, workers: int, scalar: bool = True, tcr_rtol: str = "default"
) -> dict[str, Any]:
    """One size/case/tolerance/worker count: the paths, their ratios and the accuracy checks."""
    spec, x = _spec(case, n, tcr_rtol)
    t_lane, tcr = _sweep(spec, workers, "lanes")
    rec: dict[str, Any] = {
        "case": case,
        "tcr_rtol": tcr_rtol,
        "n_points": n,
        "workers": workers,
        "lanes_s": t_lane,
        "lanes_points_per_s": n / t_lane,
    }
    if scalar:
        t_one, _ = _sweep(spec, workers, "stiff-one-by-one")
        t_scalar, tcr_s = _sweep(spec, workers, "scalar")
        rec |= {
            "stiff_one_by_one_s": t_one,
            "stiff_one_by_one_points_per_s": n / t_one,
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


def agrees(rec: dict[str, Any]) -> bool:
    """Whether the batched t_cr match the scalar path's within the accuracy both promise:
    the requested t_cr rtol, or at the default rtol 1e-8 the 5e-4 that
    ``OPENING_TIME_ACCURACY`` states (near-stick points of either path scatter by up to
    ~2e-4 there; the Radau lanes round differently from the scalar Radau IIA)."""
    if "speedup" not in rec:
        return True
    tol = OPENING_TIME_ACCURACY[0][0] if rec["tcr_rtol"] == "default" else float(rec["tcr_rtol"])
    return bool(rec["same_nan"] and rec["max_rel_diff_vs_scalar"] <= tol)


def warm() -> None:
    """Compile or load every path outside the timings."""
    from obturator.warmup import load_radau_lanes

    load_radau_lanes()
    for case in ("rig", "flight"):
        spec, _ = _spec(case, 3)
        for path in _PATHS:
            _sweep(spec, 1, path)


def print_table(rows: list[dict[str, Any]]) -> None:
    """A rich table of :func:`measure` records."""
    from rich.console import Console
    from rich.table import Table

    t = Table(title="sweeps: lanes vs one trajectory at a time (pool start included)")
    for col in ("case", "t_cr rtol", "points", "workers", "lanes pts/s (s)",
                "stiff 1-by-1 pts/s", "scalar pts/s", "speed-up", "max |diff| vs scalar",
                "max err vs Radau 1e-11"):  # fmt: skip
        t.add_column(col, justify="right")
    for r in rows:
        t.add_row(
            r["case"], r["tcr_rtol"], f"{r['n_points']:,}", str(r["workers"]),
            f"{r['lanes_points_per_s']:,.0f} ({r['lanes_s']:.2f})",
            f"{r['stiff_one_by_one_points_per_s']:,.0f}" if "scalar_s" in r else "-",
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
        "--tcr-rtol", default="default,1e-6", help="tolerance settings: default and/or t_cr rtol"
    )
    ap.add_argument(
        "--scalar-max", type=int, default=10_000, help="largest size also run on the scalar path"
    )
    ap.add_argument("--json", default=None, help="write the records here")
    a = ap.parse_args(argv)
    warm()
    rows = []
    for n in (int(s) for s in a.sizes.split(",")):
        for case in a.cases.split(","):
            for tol in a.tcr_rtol.split(","):
                for w in (int(s) for s in a.workers.split(",")):
                    rows.append(measure(case, n, w, scalar=n <= a.scalar_max, tcr_rtol=tol))
                    print(json.dumps(rows[-1]), flush=True)
    print_table(rows)
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(rows, fh, indent=1, default=lambda v: None if v != v else v)
    return 0 if all(agrees(r) for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
