"""Small batches through the front door: the lanes against one by one, per kernel.

``python -m benchmarks.small_groups [--quick] [--json PATH]``; also part of
``python -m benchmarks``. For n = 1 ... 28 rig points spread over 250-440 rad/s (no
stick, so DOP853 throughout) with the thesis kernel (constant mu_s = 0.5473), its
variant for the slip-speed law "strengthening" (r = 0.3, v_s = 0.1 m/s) and the generic
kernel (the tanh regularisation family), at the default rtol 1e-8 and at the
validation study's 1e-9: best-of wall time of :func:`obturator.solve.opening_times`
with the lanes forced on every group, with its
own rule (:func:`obturator.solve.many.lanes_pay_from`: groups too small for lanes run
one by one), and of a loop over :func:`obturator.solve.opening_time`, as ratios to that
loop in the same run; and whether the three give the same t_cr to the bit.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from benchmarks.run import _best_of
from obturator.model.cases import rig_case
from obturator.model.torques import SlipSpeedLaw
from obturator.solve import SolverOptions, many, opening_time, opening_times

MU_S = 0.5473
SIZES = (1, 2, 3, 4, 6, 8, 16, 28)
SIZES_QUICK = (1, 4, 8)
#: name -> (slip-speed law, regularisation family)
KERNELS = {
    "thesis": (None, "algebraic"),
    "thesis (strengthening)": (SlipSpeedLaw("strengthening", 0.3, 0.1), "algebraic"),
    "generic (tanh)": (None, "tanh"),
}
RTOLS = (1e-8, 1e-9)


def _forced(cases: list[Any], options: SolverOptions) -> np.ndarray:
    """t_cr with every kernel group in lanes, however small."""
    saved = many.THESIS_LANES_MIN, many.GENERIC_LANES_MIN
    many.THESIS_LANES_MIN = many.GENERIC_LANES_MIN = 1
    try:
        return opening_times(cases, options)[0]
    finally:
        many.THESIS_LANES_MIN, many.GENERIC_LANES_MIN = saved


def measure(kernel: str, n: int, rtol: float, repeat: int = 5) -> dict[str, Any]:
    """One row: the three timings, their ratios to the loop and the bitwise agreement."""
    law, family = KERNELS[kernel]
    options = SolverOptions(rtol=rtol, atol=rtol / 100.0, friction_family=family)
    cases = [rig_case(float(w), MU_S, speed_law=law) for w in np.linspace(250, 440, n)]
    loop_s, _, loop = _best_of(
        lambda: [opening_time(c, options) for c in cases], repeat, warm_up=True
    )
    lanes_s, _, lanes = _best_of(lambda: _forced(cases, options), repeat, warm_up=True)
    rule_s, _, rule = _best_of(lambda: opening_times(cases, options)[0], repeat, warm_up=True)
    kernel_code = many.pack_points(cases[:1], options).p[0, many.P_KERNEL]
    return {
        "kernel": kernel,
        "points": n,
        "rtol": rtol,
        "one_by_one_s": loop_s,
        "lanes_s": lanes_s,
        "rule_s": rule_s,
        "lanes_ratio": lanes_s / loop_s,
        "rule_ratio": rule_s / loop_s,
        "rule_takes_lanes": n >= many.lanes_pay_from(kernel_code),
        "same_bits": bool(np.array_equal(loop, lanes) and np.array_equal(loop, rule)),
    }


def cost(sizes: Sequence[int] = SIZES, repeat: int = 5) -> list[dict[str, Any]]:
    """Rows of :func:`measure` for every kernel, rtol and size."""
    return [measure(k, int(n), r, repeat) for k in KERNELS for r in RTOLS for n in sizes]


def print_table(rows: list[dict[str, Any]]) -> None:
    """Rich table of :func:`cost`."""
    from rich.console import Console
    from rich.table import Table

    t = Table(title="Small batches: time / one-by-one loop (same run)")
    for col in ("kernel", "rtol", "points", "loop (ms)", "lanes forced", "the rule", "rule runs",
                "same bits"):  # fmt: skip
        t.add_column(col, justify="right")
    for r in rows:
        t.add_row(
            r["kernel"], f"{r['rtol']:.0e}", str(r["points"]), f"{1e3 * r['one_by_one_s']:.2f}",
            f"{r['lanes_ratio']:.2f}x", f"{r['rule_ratio']:.2f}x",
            "lanes" if r["rule_takes_lanes"] else "one by one",
            "yes" if r["same_bits"] else "NO",
        )  # fmt: skip
    Console().print(t)


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m benchmarks.small_groups``."""
    from benchmarks._module import run_module

    def rows_of(quick: bool) -> list[dict[str, Any]]:
        return cost(SIZES_QUICK if quick else SIZES, 2 if quick else 5)

    prog = "python -m benchmarks.small_groups"
    return run_module(prog, "sizes 1, 4, 8; two repeats", rows_of, print_table, argv)


if __name__ == "__main__":
    raise SystemExit(main())
