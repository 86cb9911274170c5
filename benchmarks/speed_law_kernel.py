"""The slip-speed laws of mu in the thesis kernel's variants against the generic code.

``python -m benchmarks.speed_law_kernel [--quick] [--json PATH]``; also part of
``python -m benchmarks``. The 54 spin-rig runs of Appendix B (their spins), at the
validation study's tolerances (rtol 1e-9), as ``obturator validate`` evaluates a
candidate: one parameter vector (an optimiser step) and four (a three-parameter
finite-difference Jacobian, handed over at once). The same packed points go through
:func:`obturator.solve.integrate_packed` twice in the same run: as packed (the variant
``KERNEL_THESIS_STRENGTHENING`` or ``KERNEL_THESIS_WEAKENING``, vectorised in the
lanes) and with ``P_KERNEL`` set to the generic right-hand side (the law term by term,
lane by lane, as before the variants). Best-of wall times, their ratio, and the largest
relative t_cr difference between the two codes (rounding, amplified near stick).

Laws: strengthening at the values ``obturator validate`` fits to the thesis data
(mu_s 0.766, r 0.269, v_s 0.127 m/s); weakening (Stribeck) at mu_s 0.5473, r 0.7,
v_s 0.05 m/s (the fit itself goes to r = 1, no weakening).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from benchmarks.run import _best_of
from obturator.calibration.data import load_thesis_data
from obturator.core.layout import KERNEL_GENERIC, P_KERNEL
from obturator.model.cases import rig_case
from obturator.model.torques import SlipSpeedLaw
from obturator.solve import SolverOptions, integrate_packed, pack_points

#: name -> (mu_s, slip-speed law)
LAWS = {
    "strengthening": (0.766, ("strengthening", 0.269, 0.127)),
    "weakening": (0.5473, ("weakening", 0.7, 0.05)),
}
VECTORS = (1, 4)
OPTIONS = SolverOptions(rtol=1e-9, atol=1e-11)  # the validation study's


def _cases(law: str, n_vectors: int) -> list[Any]:
    """The Appendix B spins for `n_vectors` parameter vectors (mu_s 0.1 % apart)."""
    mu_s, (kind, ratio, speed) = LAWS[law]
    spins = np.asarray(load_thesis_data().spin_rate, dtype=float)
    return [
        rig_case(float(w), mu_s * (1.0 - 1e-3 * j), speed_law=SlipSpeedLaw(kind, ratio, speed))
        for j in range(n_vectors)
        for w in spins
    ]


def measure(law: str, n_vectors: int, repeat: int = 5) -> dict[str, Any]:
    """One row: both codes on the same packed points, the ratio and the t_cr difference."""
    packed = pack_points(_cases(law, n_vectors), OPTIONS)

    def run() -> np.ndarray:
        return integrate_packed(packed, OPTIONS)[0]

    variant_s, _, t_variant = _best_of(run, repeat, warm_up=True)
    packed.p[:, P_KERNEL] = KERNEL_GENERIC
    generic_s, _, t_generic = _best_of(run, repeat, warm_up=True)
    return {
        "law": law,
        "vectors": n_vectors,
        "points": int(packed.valid.size),
        "variant_s": variant_s,
        "generic_s": generic_s,
        "speed_up": generic_s / variant_s,
        "max_rel_t_cr_diff": float(np.nanmax(np.abs(t_variant / t_generic - 1.0))),
    }


def cost(repeat: int = 5) -> list[dict[str, Any]]:
    """Rows of :func:`measure` for every law and batch size."""
    return [measure(law, n, repeat) for law in LAWS for n in VECTORS]


def print_table(rows: list[dict[str, Any]]) -> None:
    """Rich table of :func:`cost`."""
    from rich.console import Console
    from rich.table import Table

    t = Table(title="Slip-speed laws, 54 Appendix B spins, rtol 1e-9: variant vs generic")
    for col in ("law", "vectors", "points", "variant (ms)", "generic (ms)", "speed-up",
                "max |dt_cr|/t_cr"):  # fmt: skip
        t.add_column(col, justify="right")
    for r in rows:
        t.add_row(
            r["law"], str(r["vectors"]), str(r["points"]), f"{1e3 * r['variant_s']:.1f}",
            f"{1e3 * r['generic_s']:.1f}", f"{r['speed_up']:.2f}x",
            f"{r['max_rel_t_cr_diff']:.1e}",
        )  # fmt: skip
    Console().print(t)


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m benchmarks.speed_law_kernel``."""
    from benchmarks._module import run_module

    def rows_of(quick: bool) -> list[dict[str, Any]]:
        return cost(2 if quick else 5)

    prog = "python -m benchmarks.speed_law_kernel"
    return run_module(prog, "two repeats", rows_of, print_table, argv)


if __name__ == "__main__":
    raise SystemExit(main())
