"""Down to which regularisation width each regularised path carries t_cr.

``python -m benchmarks.regularised_limits [--spins 100,300] [--methods regularised,radau]
[--families algebraic,tanh,linear] [--widths 1e-9,1e-10,1e-11,1e-12] [--rtols 1e-8,1e-10]
[--json FILE]``

For the rig (mu_s = 0.5473) at each spin: t_cr of each method (``regularised``: DOP853
then Radau IIA where stiff; ``radau``: Radau IIA alone) for every friction family x
width (``friction_width``, relative to omega_p) x rtol (atol = rtol/100), and its
relative error against the exact limit (:data:`benchmarks.exact_limit.LIMIT_REFERENCE`,
the set-valued solver at rtol 1e-12). The width's own error shrinks with the width; an
error that jumps above that trend as the width shrinks is the path failing to carry
the width (its Radau IIA stick phases), which :mod:`obturator.solve.limits` refuses.
Printed: one row per setting with the error at each spin; ``--json`` keeps the rows.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from benchmarks.exact_limit import LIMIT_REFERENCE, MU_S, write_json
from obturator.errors import SolverError
from obturator.model.cases import rig_case
from obturator.solve import SolverOptions, opening_time
from obturator.solve import options as options_module
from obturator.solve.limits import width_rule_waived


def _floats(text: str) -> list[float]:
    return [float(x) for x in text.split(",")]


def _words(text: str) -> list[str]:
    return [x.strip() for x in text.split(",")]


def main(argv: list[str] | None = None) -> list[dict[str, Any]]:
    """Measure and print the table; return its rows."""
    ap = argparse.ArgumentParser(prog="python -m benchmarks.regularised_limits")
    ap.add_argument("--spins", type=_floats, default=[100.0, 300.0])
    ap.add_argument("--methods", type=_words, default=["regularised", "radau"])
    ap.add_argument("--families", type=_words, default=["algebraic", "tanh", "linear"])
    ap.add_argument("--widths", type=_floats, default=[1e-9, 1e-10, 1e-11, 1e-12])
    ap.add_argument("--rtols", type=_floats, default=[1e-8, 1e-10])
    ap.add_argument("--json")
    args = ap.parse_args(argv)
    # measure also where the package refuses (that is what sets the refusal): the width
    # floor of SolverOptions and, below, the width-against-rtol rule of solve.limits
    options_module.check_regularised_limits = lambda options: None
    cases = {w: rig_case(w, MU_S) for w in args.spins}
    ref = {w: opening_time(c, LIMIT_REFERENCE) for w, c in cases.items()}
    rows = []
    print("method       family     width    rtol    " + "  ".join(f"{w:>8g}" for w in ref))
    for method in args.methods:
        for family in args.families:
            for width in args.widths:
                for rtol in args.rtols:
                    opts = SolverOptions(
                        method=method,  # type: ignore[arg-type]
                        friction_family=family,  # type: ignore[arg-type]
                        friction_width=width,
                        rtol=rtol,
                        atol=rtol / 100,
                    )
                    errs = []
                    for w, case in cases.items():
                        try:
                            with width_rule_waived():
                                t = opening_time(case, opts)
                        except SolverError:
                            t = math.nan
                        errs.append(abs(t - ref[w]) / ref[w])
                    rows.append(
                        {"method": method, "family": family, "width": width, "rtol": rtol,
                         "spins": list(ref), "rel_error": errs}
                    )  # fmt: skip
                    print(
                        f"{method:12s} {family:10s} {width:7.0e} {rtol:7.0e} "
                        + "  ".join(f"{e:8.1e}" for e in errs),
                        flush=True,
                    )
    write_json(args.json, rows)
    return rows


if __name__ == "__main__":
    main()
