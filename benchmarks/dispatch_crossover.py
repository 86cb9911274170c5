"""Where the set-valued solver stops being the faster: the thresholds of ``method="auto"``.

``python -m benchmarks.dispatch_crossover [--quick] [--json PATH]``. For the rig
(mu_s = 0.5473, the thesis law and the Coulomb patch law) at spins around the crossover,
the cost per point of

* ``"set-valued"`` one by one (how ``auto`` runs the points it gives that solver, in
  both paths),
* ``"regularised"`` one by one (``opening_time``: the one-trajectory path),
* ``"regularised"`` through ``opening_times`` (the lanes: DOP853 lanes, stiff points
  in Radau IIA lanes), a band of :data:`BAND` points spread over +-5 rad/s,

and each path's relative t_cr error against ``"set-valued"`` at rtol 1e-12. The
thresholds :data:`obturator.solve.dispatch.SET_VALUED_BELOW` come from these tables.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from obturator.model.cases import rig_case
from obturator.solve import SolverOptions, opening_time, opening_times

MU_S = 0.5473
SPINS = (80.0, 100.0, 110.0, 120.0, 130.0, 140.0, 150.0, 160.0, 180.0, 200.0, 250.0)
SPINS_QUICK = (100.0, 150.0, 200.0)
BAND = 32
LAWS = ("thesis", "coulomb")
SET_VALUED = SolverOptions(method="set-valued")
REGULARISED = SolverOptions(method="regularised")
REFERENCE = SolverOptions(method="set-valued", rtol=1e-12, atol=1e-14)


def _best(fn, repeat: int) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def crossover(spins: Sequence[float], law: str, repeat: int = 3) -> list[dict[str, Any]]:
    """One row per spin: ms per point of each path and each path's t_cr error."""
    rows = []
    for w in spins:
        band = [rig_case(float(s), MU_S, torque_model=law) for s in np.linspace(w - 5, w + 5, BAND)]
        probe = band[:: BAND // 4]  # four spins of the band, one by one
        ref = np.array([opening_time(c, REFERENCE) for c in probe])
        sv = np.array([opening_time(c, SET_VALUED) for c in probe])
        reg = np.array([opening_time(c, REGULARISED) for c in probe])

        def one_by_one(options: SolverOptions, probe: list = probe) -> None:
            for c in probe:
                opening_time(c, options)

        def lanes(band: list = band) -> None:
            opening_times(band, REGULARISED)

        rows.append(
            {
                "law": law,
                "spin_rad_s": float(w),
                "set_valued_ms": _best(lambda: one_by_one(SET_VALUED), repeat) / len(probe) * 1e3,
                "regularised_ms": _best(lambda: one_by_one(REGULARISED), repeat) / len(probe) * 1e3,
                "lanes_ms": _best(lanes, repeat) / BAND * 1e3,
                "set_valued_err": float(np.max(np.abs(sv / ref - 1.0))),
                "regularised_err": float(np.max(np.abs(reg / ref - 1.0))),
            }
        )
    return rows


def print_table(rows: list[dict[str, Any]]) -> None:
    """The rows as a rich table."""
    from rich.console import Console
    from rich.table import Table

    t = Table(title=f"set-valued vs regularised per point (rig, mu_s {MU_S}; best of runs)")
    cols = ("law", "spin", "set-valued [ms]", "regularised 1x1 [ms]", "lanes [ms]")
    for col in (*cols, "sv/1x1", "sv/lanes", "err sv", "err reg"):
        t.add_column(col, justify="right")
    for r in rows:
        sv, one, lanes = r["set_valued_ms"], r["regularised_ms"], r["lanes_ms"]
        t.add_row(
            r["law"], f"{r['spin_rad_s']:g}", f"{sv:.3f}", f"{one:.3f}", f"{lanes:.3f}",
            f"{sv / one:.2f}", f"{sv / lanes:.2f}",
            f"{r['set_valued_err']:.1e}", f"{r['regularised_err']:.1e}",
        )  # fmt: skip
    Console(width=160).print(t)


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m benchmarks.dispatch_crossover``."""
    from benchmarks._module import run_module

    def rows_of(quick: bool) -> list[dict[str, Any]]:
        spins = SPINS_QUICK if quick else SPINS
        return [r for law in LAWS for r in crossover(spins, law, 2 if quick else 3)]

    prog = "python -m benchmarks.dispatch_crossover"
    return run_module(prog, "three spins, two repeats", rows_of, print_table, argv)


if __name__ == "__main__":
    raise SystemExit(main())
