"""Set-valued stick-slip solver against the regularised path, per trajectory and in sweeps.

``python -m benchmarks.stick_slip [--quick] [--json PATH]``; also part of
``python -m benchmarks``. For the rig at 40-1000 rad/s (mu_s = 0.5473) and the
flight case (Table 1): best-of wall time per trajectory of ``opening_time`` with

* the regularised path (method "regularised", rtol 1e-8, width 1e-7 omega_p),
* the set-valued solver (method "set-valued") at rtol 1e-8 and at rtol 1e-10,

their ratios (set-valued / regularised, in the same run), and each t_cr's relative
error against the set-valued solver at rtol 1e-12 (which agrees with the regularised
family limit, ``docs/stick_slip.md``).

:func:`sweep`: a rig sweep over 40-1000 rad/s through ``obturator.sweeps`` (the
front door, :func:`obturator.solve.opening_times`, same workers) with the default
method ("auto": set-valued below the stick-ratio threshold of
:mod:`obturator.solve.dispatch`, its points of one band of spins sharing return maps,
regularised lanes above), with each set-valued point building its own map
(``OBTURATOR_SHARED_MAPS=0``) and with "regularised", in the same run:
points/s, the
ratios, and the worst error of a seeded sample of points against the set-valued solver
at rtol 1e-12.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

from obturator.model.cases import flight_case, rig_case
from obturator.solve import SolverOptions, opening_time

MU_S = 0.5473
SPINS = (40.0, 60.0, 78.0, 100.0, 150.0, 200.0, 300.0, 700.0, 1000.0)
SPINS_QUICK = (78.0, 200.0, 1000.0)
PATHS = {
    "regularised": SolverOptions(method="regularised"),
    "set-valued": SolverOptions(method="set-valued"),
    "set-valued 1e-10": SolverOptions(method="set-valued", rtol=1e-10, atol=1e-12),
}
REFERENCE = SolverOptions(method="set-valued", rtol=1e-12, atol=1e-14)


def _best(case, options: SolverOptions, repeat: int) -> tuple[float, float]:
    """(best wall time [s], t_cr [s]) of `repeat` runs (one warm-up first)."""
    t_cr = opening_time(case, options)
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        opening_time(case, options)
        best = min(best, time.perf_counter() - t0)
    return best, t_cr


def cost(spins: Sequence[float] = SPINS, repeat: int = 5) -> list[dict[str, Any]]:
    """One row per case: wall time, t_cr and error of each path, and the ratios."""
    cases = [(f"rig {w:g} rad/s", rig_case(w, MU_S)) for w in spins]
    cases.append(("flight (Table 1)", flight_case()))
    rows = []
    for name, case in cases:
        ref = opening_time(case, REFERENCE)
        row: dict[str, Any] = {"case": name, "t_cr_reference_s": ref}
        for label, options in PATHS.items():
            # fewer repeats where one run takes long (the low-spin regularised path)
            wall, t_cr = _best(case, options, repeat if ref < 5.0 else max(1, repeat // 5))
            row[label] = {"wall_s": wall, "t_cr_s": t_cr, "rel_error": abs(t_cr - ref) / ref}
        base = row["regularised"]["wall_s"]
        row["ratio"] = {k: row[k]["wall_s"] / base for k in PATHS if k != "regularised"}
        rows.append(row)
    return rows


#: The sweep's range [rad/s] and the points of its full and quick runs.
SWEEP_RANGE = (40.0, 1000.0)
SWEEP_POINTS, SWEEP_POINTS_QUICK = 10_000, 500
#: The sweep's paths: label -> (method, environment). "own maps" is the default with
#: each set-valued point building its own return map (before the shared maps of
#: :mod:`obturator.core.integrators.stick_slip_family`).
SWEEP_PATHS: dict[str, tuple[str, dict[str, str]]] = {
    "auto": ("auto", {}),
    "auto, own maps": ("auto", {"OBTURATOR_SHARED_MAPS": "0"}),
    "regularised": ("regularised", {}),
}


def sweep(
    n_points: int = SWEEP_POINTS, workers: Sequence[int] = (1, 2), n_check: int = 60
) -> list[dict[str, Any]]:
    """One row per worker count: points/s of each of :data:`SWEEP_PATHS`, the ratios of
    ``auto`` to the others, and each path's worst and median error on `n_check` seeded
    points against :data:`REFERENCE`."""
    from benchmarks._module import environment
    from benchmarks.operating_range import throughput

    rows = []
    for k in workers:
        row: dict[str, Any] = {"n_points": n_points, "spin_range_rad_s": list(SWEEP_RANGE)}
        for label, (method, env) in SWEEP_PATHS.items():
            opts = SolverOptions(method=method)  # type: ignore[arg-type]
            with environment(env):
                row[label] = throughput(
                    n_points, SWEEP_RANGE, k, options=opts, n_check=n_check, reference=REFERENCE
                )
        row["workers"] = row["auto"]["workers"]
        auto = row["auto"]["points_per_s"]
        row["ratio"] = {
            label: auto / row[label]["points_per_s"] for label in SWEEP_PATHS if label != "auto"
        }
        rows.append(row)
    return rows


def print_sweep(rows: list[dict[str, Any]]) -> None:
    """The sweep rows as a rich table."""
    from rich.console import Console
    from rich.table import Table

    others = [label for label in SWEEP_PATHS if label != "auto"]
    t = Table(title="rig sweep 40-1000 rad/s: auto (dispatch, shared maps) vs others, same run")
    t.add_column("points", justify="right")
    t.add_column("workers", justify="right")
    for label in SWEEP_PATHS:
        t.add_column(f"{label} [pts/s]", justify="right")
    for label in others:
        t.add_column(f"auto / {label}", justify="right")
    for label in SWEEP_PATHS:
        t.add_column(f"{label} max / median err", justify="right")
    for r in rows:
        cells = [str(r["n_points"]), str(r["workers"])]
        cells += [f"{r[label]['points_per_s']:.0f}" for label in SWEEP_PATHS]
        cells += [f"{r['ratio'][label]:.2f}" for label in others]
        cells += [
            f"{r[label]['max_rel_error']:.1e} / {r[label]['median_rel_error']:.1e}"
            for label in SWEEP_PATHS
        ]
        t.add_row(*cells)
    Console(width=200).print(t)
    print(f"  errors: {rows[0]['auto']['n_checked']} seeded points against set-valued, rtol 1e-12")


def print_table(rows: list[dict[str, Any]]) -> None:
    """The rows as a rich table (ms per trajectory, ratio to the regularised path)."""
    from rich.console import Console
    from rich.table import Table

    t = Table(title="set-valued stick-slip vs regularised, per trajectory (best of runs)")
    t.add_column("case")
    t.add_column("t_cr ref [s]", justify="right")
    for label in PATHS:
        t.add_column(f"{label} [ms]", justify="right")
        t.add_column("err", justify="right")
    t.add_column("ratio sv/reg", justify="right")
    t.add_column("ratio sv 1e-10/reg", justify="right")
    for r in rows:
        cells = [r["case"], f"{r['t_cr_reference_s']:.9g}"]
        for label in PATHS:
            cells += [f"{r[label]['wall_s'] * 1e3:.2f}", f"{r[label]['rel_error']:.1e}"]
        cells += [f"{r['ratio']['set-valued']:.2f}", f"{r['ratio']['set-valued 1e-10']:.2f}"]
        t.add_row(*cells)
    Console().print(t)


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m benchmarks.stick_slip``."""
    from benchmarks._module import run_module

    def rows_of(quick: bool) -> list[dict[str, Any]]:
        rows = cost(SPINS_QUICK if quick else SPINS, 2 if quick else 5)
        return rows + sweep(SWEEP_POINTS_QUICK if quick else SWEEP_POINTS)

    def print_all(rows: list[dict[str, Any]]) -> None:
        print_table([r for r in rows if "case" in r])
        print_sweep([r for r in rows if "case" not in r])

    prog = "python -m benchmarks.stick_slip"
    quick = f"three spins, two repeats; a {SWEEP_POINTS_QUICK}-point sweep"
    return run_module(prog, quick, rows_of, print_all, argv)


if __name__ == "__main__":
    raise SystemExit(main())
