"""Every point of a rig sweep against an independent reference: the accuracy behind
``OPENING_TIME_ACCURACY``.

``python -m benchmarks.dense_accuracy [--points 10000] [--spins 100,700]
[--rtols 1e-8,3e-9,1e-9,1e-10] [--json FILE]``: integration error at the default width.

``python -m benchmarks.dense_accuracy --limit [--points 2000] [--spins 40,1000]
[--regularised name=value,...] [--set-valued name=value,...] [--paths P1,P2]
[--no-cross-check] [--json FILE]``: the
error of both default paths (the set-valued solver and the regularised law) against
the exact limit, width error included (:mod:`benchmarks.exact_limit`), per spin band
with the reference's own uncertainty, and the time per point of each path.

A sample of 100 points (``benchmarks.lanes``) misses isolated outliers; this check
takes every point of a rig sweep (mu_s = 0.5473, omega_p over 100-700 rad/s by
default, the issue's sweep; ``--spins 40,100`` is the long near-stick band) and
compares:

* the sweep path (:func:`obturator.solve.opening_times`: DOP853 lanes, stiff
  points in Radau IIA lanes) at each rtol (atol = rtol/100) with
* a reference by another method: Radau IIA alone (in lanes) from release at rtol
  1e-12 (near stick Radau IIA at rtol 1e-11 is itself up to 1e-7 off), and
* the one-trajectory ``auto`` path (:func:`obturator.solve.opening_time`) at the same
  rtol, against the same reference and for the batched-vs-scalar agreement.

Printed per rtol: the worst relative t_cr error over all points and per spin band,
how many points exceed 1e-7, 3e-7 and 1e-6, the worst batched-vs-scalar gap, and the
worst error of the one-trajectory path (near stick the two paths round differently and
stick-slip amplifies it, so each has its own outliers).
"""

from __future__ import annotations

import argparse
import time
from typing import Any

import numpy as np

from benchmarks.exact_limit import (
    PATHS,
    REGULARISED_DEFAULT,
    SET_VALUED_DEFAULT,
    limit_check,
    print_limit_check,
    with_fields,
    write_json,
)
from obturator.core.integrators.lanes import LANES, integrate_radau_lanes
from obturator.model.cases import rig_case
from obturator.solve import SolverOptions, integration_setup, opening_time, opening_times

MU_S = 0.5473
REFERENCE_RTOL = 1e-12
BANDS = ((40.0, 60.0), (60.0, 100.0), (100.0, 210.0), (210.0, 300.0), (300.0, 400.0),
         (400.0, 500.0), (500.0, 600.0), (600.0, 1000.0 + 1e-9))  # fmt: skip


def reference(spins: np.ndarray) -> np.ndarray:
    """t_cr [s] of every spin by Radau IIA alone (in lanes) from release, rtol 1e-12."""
    o = SolverOptions(method="radau", rtol=REFERENCE_RTOL, atol=REFERENCE_RTOL * 1e-2)
    setups = [integration_setup(rig_case(float(w), MU_S), o) for w in spins]
    pr = [s[0] for s in setups]
    ct = [s[1] for s in setups]
    st, t_ev, *_ = integrate_radau_lanes(
        np.array([p.y0 for p in pr]), np.zeros(len(pr)), np.array([p.p for p in pr]),
        np.array([p.scale for p in pr]), np.array([c.t_max for c in ct]),
        np.array([c.h0 for c in ct]), np.array([c.h_max for c in ct]),
        np.array([c.max_steps for c in ct]), np.zeros(len(pr), dtype=bool),
        np.argsort(spins, kind="stable"), o.rtol, o.atol,
        o.event_tol, LANES, LANES,
    )  # fmt: skip
    return np.asarray(t_ev, dtype=float)


def measure(spins: np.ndarray, ref: np.ndarray, rtol: float) -> dict[str, Any]:
    """Errors of the sweep path and of the scalar path at `rtol` against `ref`."""
    o = SolverOptions(rtol=rtol, atol=rtol * 1e-2)
    cases = [rig_case(float(w), MU_S) for w in spins]
    t0 = time.perf_counter()
    batched, _, stats = opening_times(cases, o)
    elapsed = time.perf_counter() - t0
    scalar = np.array([opening_time(c, o) for c in cases])
    err = np.abs(batched / ref - 1.0)
    err_scalar = np.abs(scalar / ref - 1.0)
    rec: dict[str, Any] = {
        "rtol": rtol,
        "n_points": int(spins.size),
        "n_stiff": int(stats["n_stiff"]),
        "batched_s_one_process": elapsed,
        "max_error": float(np.nanmax(err)),
        "worst_spin": float(spins[int(np.nanargmax(err))]),
        "n_over_1e-7": int(np.sum(err > 1e-7)),
        "n_over_3e-7": int(np.sum(err > 3e-7)),
        "n_over_1e-6": int(np.sum(err > 1e-6)),
        "max_batched_vs_scalar": float(np.nanmax(np.abs(batched / scalar - 1.0))),
        "max_error_scalar": float(np.nanmax(err_scalar)),
        "worst_spin_scalar": float(spins[int(np.nanargmax(err_scalar))]),
        "n_over_1e-6_scalar": int(np.sum(err_scalar > 1e-6)),
        "same_nan": bool(np.array_equal(np.isnan(batched), np.isnan(ref))),
        "bands": {},
    }
    for lo, hi in BANDS:
        m = (spins >= lo) & (spins < hi)
        if m.any():
            rec["bands"][f"{lo:g}-{min(hi, spins.max()):g}"] = float(np.nanmax(err[m]))
    return rec


def main(argv: list[str] | None = None) -> list[dict[str, Any]]:
    """Run the dense check and print one block per rtol."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=None, help="10000; 2000 with --limit")
    ap.add_argument("--spins", default=None, help="omega_p range LO,HI [rad/s]; 100,700 "
                    "(40,1000 with --limit)")  # fmt: skip
    ap.add_argument("--rtols", default="1e-8,3e-9,1e-9,1e-10")
    ap.add_argument("--json", default=None, help="also write the records to this file")
    ap.add_argument("--limit", action="store_true", help="both default paths against the "
                    "exact limit (benchmarks.exact_limit)")  # fmt: skip
    ap.add_argument("--regularised", default="", help="with --limit: fields of the "
                    "regularised path's options, e.g. friction_width=1e-9,rtol=1e-10")  # fmt: skip
    ap.add_argument("--set-valued", default="", help="with --limit: fields of the "
                    "set-valued path's options, e.g. rtol=1e-9,atol=1e-11")  # fmt: skip
    ap.add_argument("--paths", default=",".join(PATHS), help="with --limit: which of "
                    f"{', '.join(PATHS)}")  # fmt: skip
    ap.add_argument("--no-cross-check", action="store_true", help="with --limit: skip the "
                    "reference's cross-check")  # fmt: skip
    a = ap.parse_args(argv)
    lo, hi = (float(v) for v in (a.spins or ("40,1000" if a.limit else "100,700")).split(","))
    spins = np.linspace(lo, hi, a.points or (2_000 if a.limit else 10_000))
    if a.limit:
        unknown = set(a.paths.split(",")) - set(PATHS)
        if unknown:
            ap.error(f"--paths: unknown {', '.join(sorted(unknown))}; allowed: {', '.join(PATHS)}")
        rec = limit_check(
            spins, with_fields(REGULARISED_DEFAULT, a.regularised),
            with_fields(SET_VALUED_DEFAULT, a.set_valued), a.paths.split(","),
            cross=not a.no_cross_check,
        )  # fmt: skip
        print_limit_check(rec)
        write_json(a.json, rec)
        return [rec]
    t0 = time.perf_counter()
    ref = reference(spins)
    print(f"reference (Radau IIA lanes, rtol {REFERENCE_RTOL:g}): {time.perf_counter() - t0:.1f} s")
    rows = []
    for rtol in (float(r) for r in a.rtols.split(",")):
        rec = measure(spins, ref, rtol)
        rows.append(rec)
        bands = "  ".join(f"{k}: {v:.1e}" for k, v in rec["bands"].items())
        print(
            f"rtol {rtol:g}: worst {rec['max_error']:.2e} at {rec['worst_spin']:.2f} rad/s; "
            f"> 1e-7: {rec['n_over_1e-7']}, > 3e-7: {rec['n_over_3e-7']}, "
            f"> 1e-6: {rec['n_over_1e-6']} of {rec['n_points']} ({rec['n_stiff']} stiff); "
            f"batched vs scalar <= {rec['max_batched_vs_scalar']:.1e}; one-trajectory path "
            f"worst {rec['max_error_scalar']:.2e} at {rec['worst_spin_scalar']:.2f} rad/s "
            f"(> 1e-6: {rec['n_over_1e-6_scalar']}); "
            f"one process {rec['batched_s_one_process']:.2f} s\n    per band: {bands}"
        )
    write_json(a.json, rows)
    return rows


if __name__ == "__main__":
    main()
