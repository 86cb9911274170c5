"""Write ``src/obturator/core/integrators/lanes/dop853_sums.py``: DOP853's stage sums, unrolled.

``python tools/gen_lane_sums.py`` (``--check`` exits 1 if the file is stale;
``tests/core/test_lanes.py`` runs the check). One compiled function per sum, with the
nonzero coefficients as literals, so that the only loop left in each is the one
over lanes, which LLVM vectorises. Per lane the terms are added in the order of
:func:`obturator.core.integrators.dop853._stages` (zero terms dropped: adding
0 * k leaves a sum unchanged), so the results are the same to the bit.
"""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))
from obturator.core.integrators.dop853_coefficients import E3, E5, A, B  # noqa: E402

TARGET = ROOT / "src" / "obturator" / "core" / "integrators" / "lanes" / "dop853_sums.py"

HEADER = '''"""DOP853's stage and error sums over lanes, unrolled (by ``tools/gen_lane_sums.py``).

``stage_sum(s, y, h, k, out)`` writes ``out = y + h * sum_m A[s, m] k_m`` for
every component and lane (s = 12: the eighth-order solution with the weights B).
Each sum is its own function with the nonzero coefficients as literals, so the
loop over lanes is the only loop and LLVM vectorises it; offsets are cast to
unsigned because numba wraps negative indices, which would make the addresses
non-affine. Per lane the terms are added in the order of
:func:`obturator.core.integrators.dop853._stages`, each product fused into its sum as
there (:func:`obturator.core.fma.fma`), so the results are the same to the bit.
"""

from numba import njit, uint64

from ...fma import fma
from ...layout import N_STATE
from ..dop853 import error_weight
from .simd import LANES

_KS = N_STATE * LANES

__all__ = ["stage_sum", "error_sums"]'''


# inlined into the caller (same flags): a call per sum and step would cost the
# reference counting of its array arguments
_DECORATOR = '@njit(cache=True, fastmath=False, error_model="numpy", inline="always")'


def _function(name: str, coef: list[tuple[int, float]]) -> str:
    lines = [
        "",
        "",
        _DECORATOR,
        f"def {name}(y, h, k, out):  # pragma: no cover - compiled",
        "    for i in range(N_STATE):",
        "        r = i * LANES",
        "        for j in range(LANES):",
        "            u = uint64(r + j)",
    ]
    # acc starts at 0.0 and each term is fused into it, as in dop853._stages (fusing a
    # zero coefficient's term there leaves acc unchanged, so dropping it here is exact)
    lines.append("            acc = 0.0")
    for m, a in coef:
        idx = "u" if m == 0 else f"uint64({m} * _KS + r + j)"
        lines.append(f"            acc = fma({a!r}, k[{idx}], acc)")
    lines.append("            out[u] = fma(h[j], acc, y[u])")
    return "\n".join(lines)


def _error_function() -> str:
    lines = [
        "",
        "",
        _DECORATOR,
        "def error_sums(k, y, ynew, rtol, atol, scale, s5, s3):  # pragma: no cover",
        '    """s5, s3 = sum_i (e5_i / sc_i)^2, sum_i (e3_i / sc_i)^2 per lane, e5 and e3 the',
        '    E5- and E3-weighted stage sums (as dop853._error_norm, in its order)."""',
        "    for j in range(LANES):",
        "        s5[j] = 0.0",
        "        s3[j] = 0.0",
        "    for i in range(N_STATE):",
        "        r = i * LANES",
        "        for j in range(LANES):",
        "            u = uint64(r + j)",
        "            sc = error_weight(atol, scale[u], rtol, y[u], ynew[u])",
    ]
    for name, coef in (("e5", E5), ("e3", E3)):
        lines.append(f"            {name} = 0.0")
        for m in range(12):
            if coef[m]:
                idx = "u" if m == 0 else f"uint64({m} * _KS + r + j)"
                lines.append(f"            {name} = fma({float(coef[m])!r}, k[{idx}], {name})")
    lines += [
        "            e5 /= sc",
        "            e3 /= sc",
        "            s5[j] = fma(e5, e5, s5[j])",
        "            s3[j] = fma(e3, e3, s3[j])",
    ]
    return "\n".join(lines)


def source() -> str:
    parts = [HEADER]
    for s in range(1, 12):
        parts.append(_function(f"_sum{s}", [(m, float(A[s, m])) for m in range(s) if A[s, m]]))
    parts.append(_function("_sum12", [(m, float(B[m])) for m in range(12) if B[m]]))
    body = [
        "",
        "",
        _DECORATOR,
        "def stage_sum(s, y, h, k, out):  # pragma: no cover - compiled",
        '    """out = y + h * sum_m A[s, m] k_m (s = 1..11), or the B-weighted sum (s = 12)."""',
    ]
    for s in range(1, 13):
        kw = "if" if s == 1 else "elif"
        body.append(f"    {kw} s == {s}:")
        body.append(f"        _sum{s}(y, h, k, out)")
    parts.append("\n".join(body))
    parts.append(_error_function())
    return "\n".join(parts) + "\n"


if __name__ == "__main__":
    text = source()
    if "--check" in sys.argv:
        sys.exit(0 if TARGET.read_text() == text else 1)
    TARGET.write_text(text)
