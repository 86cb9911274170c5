"""Which regularised settings reach the exact limit within 1e-6, and at what cost.

``python -m benchmarks.width_grid [--spins 40,50,65,78,100,150,300,1000]
[--families algebraic,tanh,linear] [--widths 1e-7,1e-8,1e-9,1e-10] [--rtols 1e-8,1e-10]
[--atol-below-width] [--set-valued-rtols 1e-8,3e-9,1e-9] [--json FILE]``

For the rig (mu_s = 0.5473) at each spin: t_cr of the regularised path (method
``regularised``, the one-trajectory path) for every friction family x width
(``friction_width``, relative to omega_p) x rtol (atol = rtol/100, or with
``--atol-below-width`` min(rtol, width)/100: the width and atol are both in units of
omega_p, and atol near the width lets the integrator skip the slip scale), its relative error
against the exact limit (:data:`benchmarks.exact_limit.LIMIT_REFERENCE`, the set-valued
solver at rtol 1e-12) and its wall time (best of up to three runs where a run takes
under 0.2 s). Printed: one row per setting with the error at each spin, the worst,
and the cost at each spin in ms; the reference's spread (tanh and linear at width 1e-10
in Radau IIA at rtol 1e-12, :func:`benchmarks.exact_limit.cross_check`) in the last row.
The set-valued solver's rows come first (width NaN: it has none).
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from typing import Any

import numpy as np

from benchmarks.exact_limit import (
    LIMIT_REFERENCE,
    MU_S,
    REGULARISED_DEFAULT,
    SET_VALUED_DEFAULT,
    TARGET,
    cross_check,
    warm_up,
    write_json,
)
from obturator.errors import SolverError
from obturator.model.cases import rig_case
from obturator.solve import SolverOptions, opening_time

SPINS = (40.0, 50.0, 65.0, 78.0, 100.0, 150.0, 300.0, 1000.0)
FAMILIES = ("algebraic", "tanh", "linear")
WIDTHS = (1e-7, 1e-8, 1e-9, 1e-10)
RTOLS = (1e-8, 1e-10)
#: The set-valued solver's rows (no width, no family), for comparison.
SET_VALUED_RTOLS = (1e-8, 3e-9, 1e-9)


def _timed(case: Any, options: SolverOptions) -> tuple[float, float]:
    """(t_cr [s], best wall time [s]) of up to three runs (one where a run is slow);
    t_cr NaN where the integration failed (e.g. the step limit)."""
    best, t_cr = float("inf"), float("nan")
    for _ in range(3):
        t0 = time.perf_counter()
        try:
            t_cr = opening_time(case, options)
        except SolverError:
            t_cr = float("nan")
        best = min(best, time.perf_counter() - t0)
        if best > 0.2:
            break
    return t_cr, best


def _row(cases: list[Any], ref: np.ndarray, o: SolverOptions, family: str, width: float):
    """One setting's errors and costs at every case, printed as it finishes."""
    runs = [_timed(c, o) for c in cases]
    err = np.array([t for t, _ in runs]) / ref - 1.0
    row = {
        "family": family, "width": width, "rtol": o.rtol, "atol": o.atol,
        "error": err.tolist(), "wall_s": [s for _, s in runs],
        "worst": float(np.max(np.abs(err))),  # NaN where one failed
    }  # fmt: skip
    print_row(row, flush=True)
    return row


def grid(
    spins: tuple[float, ...] = SPINS,
    families: tuple[str, ...] = FAMILIES,
    widths: tuple[float, ...] = WIDTHS,
    rtols: tuple[float, ...] = RTOLS,
    atol_below_width: bool = False,
    set_valued_rtols: tuple[float, ...] = SET_VALUED_RTOLS,
) -> dict[str, Any]:
    """Error against the exact limit and cost of every setting at every spin; the
    set-valued solver at `set_valued_rtols` first, for comparison."""
    warm_up([REGULARISED_DEFAULT, SET_VALUED_DEFAULT])
    cases = [rig_case(w, MU_S) for w in spins]
    ref = np.array([opening_time(c, LIMIT_REFERENCE) for c in cases])
    spread = cross_check(np.array(spins), ref)["spread"]
    rows = []
    for rtol in set_valued_rtols:
        o = replace(SET_VALUED_DEFAULT, rtol=rtol, atol=rtol * 1e-2)
        rows.append(_row(cases, ref, o, "set-valued", float("nan")))
    for family in families:
        for width in widths:
            for rtol in rtols:
                atol = min(rtol, width) * 1e-2 if atol_below_width else rtol * 1e-2
                o = replace(
                    REGULARISED_DEFAULT, friction_family=family, friction_width=width,
                    rtol=rtol, atol=atol,
                )  # fmt: skip
                rows.append(_row(cases, ref, o, family, width))
    return {"spins": list(spins), "reference": ref.tolist(), "spread": spread.tolist(),
            "rows": rows}  # fmt: skip


def print_header(spins: tuple[float, ...]) -> None:
    """Column heads: the spins, twice (errors, then costs)."""
    cols = "".join(f"{w:>9g}" for w in spins)
    print(f"{'family':>10} {'width':>6} {'rtol':>6} {'atol':>6} |{cols} | worst  ok |{cols}  [ms]")


def print_row(row: dict[str, Any], flush: bool = False) -> None:
    """One setting: signed error per spin, worst, within target, cost per spin [ms]."""
    errs = "".join(f"{e:>+9.1e}" for e in row["error"])
    cost = "".join(f"{1e3 * s:>9.2f}" for s in row["wall_s"])
    ok = "yes" if row["worst"] <= TARGET else "no"  # NaN (a failed run): no
    print(
        f"{row['family']:>10} {row['width']:>6.0e} {row['rtol']:>6.0e} {row['atol']:>6.0e} |"
        f"{errs} | "
        f"{row['worst']:.1e} {ok:>3} |{cost}",
        flush=flush,
    )


def main(argv: list[str] | None = None) -> dict[str, Any]:
    """Run the grid and print it (rows as they finish)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spins", default=",".join(f"{w:g}" for w in SPINS))
    ap.add_argument("--families", default=",".join(FAMILIES))
    ap.add_argument("--widths", default=",".join(f"{w:g}" for w in WIDTHS))
    ap.add_argument("--rtols", default=",".join(f"{r:g}" for r in RTOLS))
    ap.add_argument("--set-valued-rtols", default=",".join(f"{r:g}" for r in SET_VALUED_RTOLS),
                    help="rtols of the set-valued rows ('' for none)")  # fmt: skip
    ap.add_argument("--json", default=None, help="also write the results to this file")
    ap.add_argument("--atol-below-width", action="store_true", help="atol = min(rtol, "
                    "width)/100 (the width is in the same units) instead of rtol/100")  # fmt: skip
    a = ap.parse_args(argv)
    spins = tuple(float(v) for v in a.spins.split(","))

    def floats(s: str) -> tuple[float, ...]:
        return tuple(float(v) for v in s.split(","))

    from benchmarks.run import _meta

    print(f"CPU: {_meta()['cpu']}; rig mu_s {MU_S}; reference {LIMIT_REFERENCE.method} "
          f"rtol {LIMIT_REFERENCE.rtol:g}")  # fmt: skip
    print_header(spins)
    out = grid(
        spins, tuple(a.families.split(",")), floats(a.widths), floats(a.rtols),
        a.atol_below_width, floats(a.set_valued_rtols) if a.set_valued_rtols else (),
    )  # fmt: skip
    print(f"{'spread':>32} |" + "".join(f"{s:>9.1e}" for s in out["spread"]))
    print("reference t_cr [s]: " + ", ".join(f"{t:.10g}" for t in out["reference"]))
    write_json(a.json, out)
    return out


if __name__ == "__main__":
    main()
