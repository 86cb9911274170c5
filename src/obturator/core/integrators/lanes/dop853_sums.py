"""DOP853's stage and error sums over lanes, unrolled (by ``tools/gen_lane_sums.py``).

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

__all__ = ["stage_sum", "error_sums"]


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _sum1(y, h, k, out):  # pragma: no cover - compiled
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            acc = 0.0
            acc = fma(0.05260015195876773, k[u], acc)
            out[u] = fma(h[j], acc, y[u])


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _sum2(y, h, k, out):  # pragma: no cover - compiled
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            acc = 0.0
            acc = fma(0.0197250569845379, k[u], acc)
            acc = fma(0.0591751709536137, k[uint64(1 * _KS + r + j)], acc)
            out[u] = fma(h[j], acc, y[u])


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _sum3(y, h, k, out):  # pragma: no cover - compiled
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            acc = 0.0
            acc = fma(0.02958758547680685, k[u], acc)
            acc = fma(0.08876275643042054, k[uint64(2 * _KS + r + j)], acc)
            out[u] = fma(h[j], acc, y[u])


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _sum4(y, h, k, out):  # pragma: no cover - compiled
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            acc = 0.0
            acc = fma(0.2413651341592667, k[u], acc)
            acc = fma(-0.8845494793282861, k[uint64(2 * _KS + r + j)], acc)
            acc = fma(0.924834003261792, k[uint64(3 * _KS + r + j)], acc)
            out[u] = fma(h[j], acc, y[u])


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _sum5(y, h, k, out):  # pragma: no cover - compiled
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            acc = 0.0
            acc = fma(0.037037037037037035, k[u], acc)
            acc = fma(0.17082860872947386, k[uint64(3 * _KS + r + j)], acc)
            acc = fma(0.12546768756682242, k[uint64(4 * _KS + r + j)], acc)
            out[u] = fma(h[j], acc, y[u])


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _sum6(y, h, k, out):  # pragma: no cover - compiled
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            acc = 0.0
            acc = fma(0.037109375, k[u], acc)
            acc = fma(0.17025221101954405, k[uint64(3 * _KS + r + j)], acc)
            acc = fma(0.06021653898045596, k[uint64(4 * _KS + r + j)], acc)
            acc = fma(-0.017578125, k[uint64(5 * _KS + r + j)], acc)
            out[u] = fma(h[j], acc, y[u])


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _sum7(y, h, k, out):  # pragma: no cover - compiled
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            acc = 0.0
            acc = fma(0.03709200011850479, k[u], acc)
            acc = fma(0.17038392571223998, k[uint64(3 * _KS + r + j)], acc)
            acc = fma(0.10726203044637328, k[uint64(4 * _KS + r + j)], acc)
            acc = fma(-0.015319437748624402, k[uint64(5 * _KS + r + j)], acc)
            acc = fma(0.008273789163814023, k[uint64(6 * _KS + r + j)], acc)
            out[u] = fma(h[j], acc, y[u])


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _sum8(y, h, k, out):  # pragma: no cover - compiled
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            acc = 0.0
            acc = fma(0.6241109587160757, k[u], acc)
            acc = fma(-3.3608926294469414, k[uint64(3 * _KS + r + j)], acc)
            acc = fma(-0.868219346841726, k[uint64(4 * _KS + r + j)], acc)
            acc = fma(27.59209969944671, k[uint64(5 * _KS + r + j)], acc)
            acc = fma(20.154067550477894, k[uint64(6 * _KS + r + j)], acc)
            acc = fma(-43.48988418106996, k[uint64(7 * _KS + r + j)], acc)
            out[u] = fma(h[j], acc, y[u])


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _sum9(y, h, k, out):  # pragma: no cover - compiled
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            acc = 0.0
            acc = fma(0.47766253643826434, k[u], acc)
            acc = fma(-2.4881146199716677, k[uint64(3 * _KS + r + j)], acc)
            acc = fma(-0.590290826836843, k[uint64(4 * _KS + r + j)], acc)
            acc = fma(21.230051448181193, k[uint64(5 * _KS + r + j)], acc)
            acc = fma(15.279233632882423, k[uint64(6 * _KS + r + j)], acc)
            acc = fma(-33.28821096898486, k[uint64(7 * _KS + r + j)], acc)
            acc = fma(-0.020331201708508627, k[uint64(8 * _KS + r + j)], acc)
            out[u] = fma(h[j], acc, y[u])


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _sum10(y, h, k, out):  # pragma: no cover - compiled
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            acc = 0.0
            acc = fma(-0.9371424300859873, k[u], acc)
            acc = fma(5.186372428844064, k[uint64(3 * _KS + r + j)], acc)
            acc = fma(1.0914373489967295, k[uint64(4 * _KS + r + j)], acc)
            acc = fma(-8.149787010746927, k[uint64(5 * _KS + r + j)], acc)
            acc = fma(-18.52006565999696, k[uint64(6 * _KS + r + j)], acc)
            acc = fma(22.739487099350505, k[uint64(7 * _KS + r + j)], acc)
            acc = fma(2.4936055526796523, k[uint64(8 * _KS + r + j)], acc)
            acc = fma(-3.0467644718982196, k[uint64(9 * _KS + r + j)], acc)
            out[u] = fma(h[j], acc, y[u])


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _sum11(y, h, k, out):  # pragma: no cover - compiled
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            acc = 0.0
            acc = fma(2.273310147516538, k[u], acc)
            acc = fma(-10.53449546673725, k[uint64(3 * _KS + r + j)], acc)
            acc = fma(-2.0008720582248625, k[uint64(4 * _KS + r + j)], acc)
            acc = fma(-17.9589318631188, k[uint64(5 * _KS + r + j)], acc)
            acc = fma(27.94888452941996, k[uint64(6 * _KS + r + j)], acc)
            acc = fma(-2.8589982771350235, k[uint64(7 * _KS + r + j)], acc)
            acc = fma(-8.87285693353063, k[uint64(8 * _KS + r + j)], acc)
            acc = fma(12.360567175794303, k[uint64(9 * _KS + r + j)], acc)
            acc = fma(0.6433927460157636, k[uint64(10 * _KS + r + j)], acc)
            out[u] = fma(h[j], acc, y[u])


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def _sum12(y, h, k, out):  # pragma: no cover - compiled
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            acc = 0.0
            acc = fma(0.054293734116568765, k[u], acc)
            acc = fma(4.450312892752409, k[uint64(5 * _KS + r + j)], acc)
            acc = fma(1.8915178993145003, k[uint64(6 * _KS + r + j)], acc)
            acc = fma(-5.801203960010585, k[uint64(7 * _KS + r + j)], acc)
            acc = fma(0.3111643669578199, k[uint64(8 * _KS + r + j)], acc)
            acc = fma(-0.1521609496625161, k[uint64(9 * _KS + r + j)], acc)
            acc = fma(0.20136540080403034, k[uint64(10 * _KS + r + j)], acc)
            acc = fma(0.04471061572777259, k[uint64(11 * _KS + r + j)], acc)
            out[u] = fma(h[j], acc, y[u])


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def stage_sum(s, y, h, k, out):  # pragma: no cover - compiled
    """out = y + h * sum_m A[s, m] k_m (s = 1..11), or the B-weighted sum (s = 12)."""
    if s == 1:
        _sum1(y, h, k, out)
    elif s == 2:
        _sum2(y, h, k, out)
    elif s == 3:
        _sum3(y, h, k, out)
    elif s == 4:
        _sum4(y, h, k, out)
    elif s == 5:
        _sum5(y, h, k, out)
    elif s == 6:
        _sum6(y, h, k, out)
    elif s == 7:
        _sum7(y, h, k, out)
    elif s == 8:
        _sum8(y, h, k, out)
    elif s == 9:
        _sum9(y, h, k, out)
    elif s == 10:
        _sum10(y, h, k, out)
    elif s == 11:
        _sum11(y, h, k, out)
    elif s == 12:
        _sum12(y, h, k, out)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always")
def error_sums(k, y, ynew, rtol, atol, scale, s5, s3):  # pragma: no cover
    """s5, s3 = sum_i (e5_i / sc_i)^2, sum_i (e3_i / sc_i)^2 per lane, e5 and e3 the
    E5- and E3-weighted stage sums (as dop853._error_norm, in its order)."""
    for j in range(LANES):
        s5[j] = 0.0
        s3[j] = 0.0
    for i in range(N_STATE):
        r = i * LANES
        for j in range(LANES):
            u = uint64(r + j)
            sc = error_weight(atol, scale[u], rtol, y[u], ynew[u])
            e5 = 0.0
            e5 = fma(0.01312004499419488, k[u], e5)
            e5 = fma(-1.2251564463762044, k[uint64(5 * _KS + r + j)], e5)
            e5 = fma(-0.4957589496572502, k[uint64(6 * _KS + r + j)], e5)
            e5 = fma(1.6643771824549864, k[uint64(7 * _KS + r + j)], e5)
            e5 = fma(-0.35032884874997366, k[uint64(8 * _KS + r + j)], e5)
            e5 = fma(0.3341791187130175, k[uint64(9 * _KS + r + j)], e5)
            e5 = fma(0.08192320648511571, k[uint64(10 * _KS + r + j)], e5)
            e5 = fma(-0.022355307863886294, k[uint64(11 * _KS + r + j)], e5)
            e3 = 0.0
            e3 = fma(-0.18980075407240762, k[u], e3)
            e3 = fma(4.450312892752409, k[uint64(5 * _KS + r + j)], e3)
            e3 = fma(1.8915178993145003, k[uint64(6 * _KS + r + j)], e3)
            e3 = fma(-5.801203960010585, k[uint64(7 * _KS + r + j)], e3)
            e3 = fma(-0.4226823213237919, k[uint64(8 * _KS + r + j)], e3)
            e3 = fma(-0.1521609496625161, k[uint64(9 * _KS + r + j)], e3)
            e3 = fma(0.20136540080403034, k[uint64(10 * _KS + r + j)], e3)
            e3 = fma(0.02265179219836082, k[uint64(11 * _KS + r + j)], e3)
            e5 /= sc
            e3 /= sc
            s5[j] = fma(e5, e5, s5[j])
            s3[j] = fma(e3, e3, s3[j])
