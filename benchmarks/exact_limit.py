"""The exact limit of the rig's t_cr, and the error of both default paths against it.

Used by ``python -m benchmarks.dense_accuracy --limit`` (dense sweep) and by
``python -m benchmarks.width_grid`` (family x width x rtol at fixed spins).

* Reference: the set-valued solver (no regularisation width) at rtol 1e-12,
  atol 1e-14 (:data:`LIMIT_REFERENCE`).
* Its uncertainty, on a subsample (:data:`CHECK_SPINS`, more of them below 100 rad/s
  where stick-slip lasts longest): the regularised family limit by an independent
  path, the tanh and linear families at width 1e-10 omega_p in Radau IIA alone at
  rtol 1e-12 (no events, no closed-form stick; :data:`CROSS_CHECKS`). The spread of
  the three answers (max - min, relative) is the reference's own uncertainty; a
  point is only called wrong where its error exceeds both 1e-6 and the worst spread
  of its spin band.
"""

from __future__ import annotations

import json
import time
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from obturator.model.cases import rig_case
from obturator.solve import SolverOptions, opening_time, opening_times

MU_S = 0.5473
#: The regularised path at its defaults (width 1e-7 omega_p, algebraic family, rtol 1e-8,
#: DOP853 then Radau IIA where stiff), named explicitly: the default method ``auto``
#: dispatches per point to the set-valued solver at low spin.
REGULARISED_DEFAULT = SolverOptions(method="regularised")
#: The set-valued solver at its default tolerances.
SET_VALUED_DEFAULT = SolverOptions(method="set-valued")
#: The width-free reference: the mode loop itself (no last slips in the DOP853 lanes, so
#: that the default's lanes are checked against a path without them).
LIMIT_REFERENCE = SolverOptions(method="set-valued", rtol=1e-12, atol=1e-14, slip_lanes=False)
#: Width [omega_p] of the independent regularised answers.
CROSS_CHECK_WIDTH = 1e-10
#: The independent answers: the regularised law near its limit, Radau IIA alone.
CROSS_CHECKS = {
    family: SolverOptions(
        method="radau",
        rtol=1e-12,
        atol=1e-14,
        friction_width=CROSS_CHECK_WIDTH,
        friction_family=family,
    )  # fmt: skip
    for family in ("tanh", "linear")
}
#: Spin rates [rad/s] of the cross-check subsample (the nearest sweep point is taken);
#: 65 rad/s is where the families were seen to disagree most (3.7e-6).
CHECK_SPINS = (40, 44, 48, 52, 56, 60, 65, 70, 78, 86, 94,
               120, 180, 230, 280, 330, 380, 430, 480, 530, 580, 700, 850, 1000)  # fmt: skip
#: Spin bands [rad/s] of the report, [lo, hi).
BANDS = ((40.0, 60.0), (60.0, 100.0), (100.0, 210.0), (210.0, 300.0), (300.0, 400.0),
         (400.0, 500.0), (500.0, 600.0), (600.0, 1000.0 + 1e-9))  # fmt: skip
#: What :func:`limit_check` can run.
PATHS = (
    "set-valued",
    "regularised sweep",
    "regularised one-trajectory",
    "default (auto)",
    "default (auto) one-trajectory",
)
#: Error bound of the issue's target [-].
TARGET = 1e-6


def timed_sweep(spins: np.ndarray, options: SolverOptions) -> tuple[np.ndarray, float]:
    """(t_cr [s], wall time per point [s]) of every spin by the sweep path."""
    cases = [rig_case(float(w), MU_S) for w in spins]
    t0 = time.perf_counter()
    t_cr, _, _ = opening_times(cases, options)
    return np.asarray(t_cr, dtype=float), (time.perf_counter() - t0) / max(len(cases), 1)


def timed_scalar(spins: np.ndarray, options: SolverOptions) -> tuple[np.ndarray, float]:
    """(t_cr [s], wall time per point [s]) by the one-trajectory path, point by point."""
    cases = [rig_case(float(w), MU_S) for w in spins]
    t0 = time.perf_counter()
    t_cr = np.array([opening_time(c, options) for c in cases], dtype=float)
    return t_cr, (time.perf_counter() - t0) / max(len(cases), 1)


def warm_up(options: Sequence[SolverOptions]) -> float:
    """Compile or load each path on cheap points (so timings exclude it) [s].

    120-200 rad/s stick briefly: 40 points there take the regularised sweep into its
    Radau IIA lanes (at least ``RADAU_LANES_MIN`` = 32 stiff points), one the
    one-trajectory path into Radau IIA; 700 and 1000 rad/s stay in DOP853."""
    t0 = time.perf_counter()
    spins = np.concatenate([np.linspace(120.0, 200.0, 40), [700.0, 1000.0]])
    for o in options:
        timed_sweep(spins, o)
        timed_scalar(spins[[0, -1]], o)
    return time.perf_counter() - t0


def check_indices(spins: np.ndarray, targets: Sequence[float] = CHECK_SPINS) -> np.ndarray:
    """Indices of the sweep points nearest each target inside the sweep's range."""
    lo, hi = spins.min(), spins.max()
    inside = [t for t in targets if lo - 1e-9 <= t <= hi + 1e-9]
    return np.unique([int(np.argmin(np.abs(spins - t))) for t in inside]).astype(int)


def cross_check(spins: np.ndarray, reference: np.ndarray) -> dict[str, np.ndarray]:
    """The independent answers at `spins` and the relative spread of all three [-]."""
    out: dict[str, np.ndarray] = {}
    for family, options in CROSS_CHECKS.items():
        out[family] = timed_scalar(spins, options)[0]
    stack = np.vstack([reference, *out.values()])
    out["spread"] = (stack.max(axis=0) - stack.min(axis=0)) / reference
    return out


def band_of(spins: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """Mask of the spins in [lo, hi)."""
    return (spins >= lo) & (spins < hi)


def band_table(
    spins: np.ndarray,
    errors: dict[str, np.ndarray],
    check_spins: np.ndarray,
    spread: np.ndarray,
) -> list[dict[str, Any]]:
    """Per band: worst |error| and counts over 1e-6 (and over the band's spread) per path."""
    rows = []
    for lo, hi in BANDS:
        m = band_of(spins, lo, hi)
        if not m.any():
            continue
        mc = band_of(check_spins, lo, hi)
        unc = float(np.max(spread[mc])) if mc.any() else float("nan")
        bound = max(TARGET, unc) if np.isfinite(unc) else TARGET
        row: dict[str, Any] = {
            "band": f"{lo:g}-{min(hi, spins.max()):g}",
            "n_points": int(m.sum()),
            "n_checked": int(mc.sum()),
            "reference_spread": unc,
        }
        for name, err in errors.items():
            e = np.abs(err[m])
            row[name] = {
                "worst": float(np.nanmax(e)),
                "worst_spin": float(spins[m][int(np.nanargmax(e))]),
                "n_over_1e-6": int(np.sum(e > TARGET)),
                "n_wrong": int(np.sum(e > bound)),
                "n_nan": int(np.sum(np.isnan(e))),
            }
        rows.append(row)
    return rows


def limit_check(
    spins: np.ndarray,
    regularised: SolverOptions = REGULARISED_DEFAULT,
    set_valued: SolverOptions = SET_VALUED_DEFAULT,
    paths: Sequence[str] = PATHS,
    cross: bool = True,
) -> dict[str, Any]:
    """Both default paths against the exact limit at every spin (see the module doc).

    `paths`: any of :data:`PATHS` (the set-valued solver; the regularised law in the
    sweep's lanes and point by point through the one-trajectory path; the package's
    default ``SolverOptions()``, which dispatches per point, through the sweep)."""
    rec: dict[str, Any] = {"n_points": int(spins.size), "spins": spins.tolist()}
    rec["warm_up_s"] = warm_up([regularised, set_valued])
    t0 = time.perf_counter()
    ref = timed_scalar(spins, LIMIT_REFERENCE)[0]
    rec["reference_s"] = time.perf_counter() - t0
    runs = {
        "set-valued": lambda: timed_sweep(spins, set_valued),
        "regularised sweep": lambda: timed_sweep(spins, regularised),
        "regularised one-trajectory": lambda: timed_scalar(spins, regularised),
        "default (auto)": lambda: timed_sweep(spins, SolverOptions()),
        "default (auto) one-trajectory": lambda: timed_scalar(spins, SolverOptions()),
    }
    t_cr: dict[str, np.ndarray] = {"reference": ref}
    errors: dict[str, np.ndarray] = {}
    rec["s_per_point"] = {}
    for name in paths:
        t_cr[name], rec["s_per_point"][name] = runs[name]()
        errors[name] = t_cr[name] / ref - 1.0
    idx = check_indices(spins) if cross else np.zeros(0, dtype=int)
    t0 = time.perf_counter()
    checks = cross_check(spins[idx], ref[idx]) if idx.size else {"spread": np.zeros(0)}
    rec["cross_check_s"] = time.perf_counter() - t0
    rec["check"] = {"spins": spins[idx].tolist(), "reference": ref[idx].tolist()}
    rec["check"].update({k: v.tolist() for k, v in checks.items()})
    rec["bands"] = band_table(spins, errors, spins[idx], checks["spread"])
    rec["t_cr"] = {k: v.tolist() for k, v in t_cr.items()}
    rec["options"] = {"regularised": _fields(regularised), "set-valued": _fields(set_valued)}
    return rec


def print_limit_check(rec: dict[str, Any]) -> None:
    """One line per band and path; the cost per point of each path."""
    print(
        f"{rec['n_points']} points; reference (set-valued, rtol "
        f"{LIMIT_REFERENCE.rtol:g}) {rec['reference_s']:.1f} s; cross-check "
        f"(tanh, linear at width {CROSS_CHECK_WIDTH:g} omega_p, Radau IIA rtol 1e-12) at "
        f"{len(rec['check']['spins'])} points {rec['cross_check_s']:.1f} s; "
        f"warm-up {rec['warm_up_s']:.1f} s"
    )
    for name, opts in rec["options"].items():
        print(f"  {name}: {opts}")
    names = list(rec["s_per_point"])
    head = f"{'band [rad/s]':>14} {'n':>5} {'ref spread':>10}"
    for n in names:
        head += f" | {n[:26]:<26} worst at [rad/s] >1e-6 wrong"
    print(head)
    for row in rec["bands"]:
        line = f"{row['band']:>14} {row['n_points']:>5} {row['reference_spread']:>10.1e}"
        for n in names:
            b = row[n]
            line += (
                f" | {'':>26} {b['worst']:>8.1e} {b['worst_spin']:>7.2f} "
                f"{b['n_over_1e-6']:>5} {b['n_wrong']:>5}"
            )
        print(line)
    cost = "; ".join(f"{n} {1e3 * s:.2f} ms" for n, s in rec["s_per_point"].items())
    print(f"time per point (one process, warm): {cost}")
    worst = {n: max(r[n]["worst"] for r in rec["bands"]) for n in names}
    print("worst |error| over all: " + "; ".join(f"{n} {w:.2e}" for n, w in worst.items()))


def _fields(options: SolverOptions) -> str:
    """The fields that set a path apart: method, tolerances, width, family."""
    keys = ("method", "rtol", "atol", "friction_width", "friction_family")
    return ", ".join(f"{k}={getattr(options, k)!r}" for k in keys)


def with_fields(base: SolverOptions, spec: str) -> SolverOptions:
    """`base` with fields from ``"name=value,..."`` (floats where they parse)."""
    kw: dict[str, Any] = {}
    for item in filter(None, spec.split(",")):
        key, value = item.split("=", 1)
        try:
            kw[key.strip()] = float(value)
        except ValueError:
            kw[key.strip()] = value.strip()
    return replace(base, **kw)


def write_json(path: str | None, records: Any) -> None:
    """Write `records` to `path` as JSON, when a path is given."""
    if path:
        with open(path, "w") as fh:
            json.dump(records, fh, indent=1)
