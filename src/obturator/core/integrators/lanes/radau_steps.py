"""The vector phases of the batched Radau IIA (:mod:`.radau`), one lane loop each.

Per lane each phase does what the named part of
:func:`obturator.core.integrators.radau.integrate` does (forward-difference Jacobian, the
two iteration matrices, the stage guess, the transformed Newton residual and update, the
Newton and error norms), on the
structure-of-arrays layout of the lanes (``x[i * LANES + lane]``, stage k of
a three-stage quantity at offset ``k * N_STATE * LANES``). Every function takes
``vw``, the lane count passed at run time (see :mod:`.lu`); those that evaluate the
right-hand side take ``kernel`` (:func:`.rates.rates_lanes`: thesis or generic kernel).
"""

from __future__ import annotations

import math

from numba import njit, uint64

from ...layout import N_STATE
from ..radau_coefficients import (
    ALPHA,
    BETA,
    C1,
    C2,
    E1,
    E2,
    E3,
    GAMMA,
    RD1,
    RD2,
    RD3,
    T00,
    T01,
    T02,
    T10,
    T11,
    T12,
    T20,
    T21,
    T22,
    TI00,
    TI01,
    TI02,
    TI10,
    TI11,
    TI12,
    TI20,
    TI21,
    TI22,
)
from .rates import rates_lanes
from .simd import LANE_KERNEL, LANES, NO_REFCOUNT

__all__ = [
    "jacobian_lanes",
    "build_lanes",
    "guess_lanes",
    "to_w",
    "residual_lanes",
    "update_lanes",
    "wnorm_lanes",
    "error_lanes",
    "error_rhs_lanes",
    "stages_rhs",
    "f0_masked",
    "NW_F",
    "NW_W",
    "NW_Z",
    "NW_R1",
    "NW_R2",
    "NW_R3",
    "NW_SCAL",
    "NW_SIZE",
    "node_states",
]

_N = N_STATE
_V = N_STATE * LANES
# The Newton workspace of the driver, one array (see .radau): stage derivatives F,
# transformed increments W, increments Z (three vectors each), the residual / correction
# R1 (real), R2 + i R3 (complex) and the reciprocal error weights. One array with
# constant offsets: LLVM then needs no runtime alias checks between them (with separate
# arrays these loops needed more than it allows and stayed scalar).
NW_F, NW_W, NW_Z = 0, 3 * _V, 6 * _V
NW_R1, NW_R2, NW_R3, NW_SCAL = 9 * _V, 10 * _V, 11 * _V, 12 * _V
NW_SIZE = 13 * _V


@njit(cache=True, inline="always", **NO_REFCOUNT)
def _u(x):
    return uint64(x)


@njit(**LANE_KERNEL)
def jacobian_lanes(Y, F0, PL, SC, JAC, NJ, WORK, FW, dj_cap, dj_row, kernel, vw) -> None:
    """Forward-difference Jacobian of every lane (as
    :func:`obturator.core.integrators.common.jacobian`), stored for the lanes with NJ set.

    dj_cap[i * LANES + lane] holds the increment cap of component i (1e-4 delta
    for rates, 1e-4 delta / omega_ref for quaternion components).
    """
    eps = math.sqrt(2.220446049250313e-16)
    for c in range(_N):
        for v in range(_N * vw):
            WORK[v] = Y[v]
        for j in range(vw):
            u = _u(c * LANES + j)
            y = Y[u]
            dj = eps * max(abs(y), SC[u])
            dj = min(dj, dj_cap[u])
            WORK[u] = y + dj
            dj_row[j] = WORK[u] - y  # the increment actually taken
        rates_lanes(WORK, PL, FW, 0, kernel, NJ)
        for i in range(_N):
            for j in range(vw):
                a = _u((i * _N + c) * LANES + j)
                d = (FW[_u(i * LANES + j)] - F0[_u(i * LANES + j)]) / dj_row[j]
                JAC[a] = d if NJ[j] else JAC[a]


@njit(**LANE_KERNEL)
def build_lanes(JAC, H, LUR, LUCR, LUCI, vw) -> None:
    """gamma/h I - J and (alpha + i beta)/h I - J of every lane (as ``radau._factor``)."""
    for i in range(_N):
        for c in range(_N):
            for j in range(vw):
                a = _u((i * _N + c) * LANES + j)
                LUR[a] = -JAC[a]
                LUCR[a] = -JAC[a]
                LUCI[a] = 0.0
        for j in range(vw):
            a = _u((i * _N + i) * LANES + j)
            LUR[a] += GAMMA / H[j]
            LUCR[a] += ALPHA / H[j]
            LUCI[a] = BETA / H[j]


@njit(**LANE_KERNEL)
def guess_lanes(NW, ZACC, H, HACC, POLY, vw) -> None:
    """Stage guess: the last collocation polynomial extrapolated (0 for a first step)."""
    for k in range(3):
        ck = C1 if k == 0 else (C2 if k == 1 else 1.0)
        for j in range(vw):
            s = 1.0 + ck * H[j] / HACC[j]
            l1 = s * (s - C2) * (s - 1.0) * RD1
            l2 = s * (s - C1) * (s - 1.0) * RD2
            l3 = s * (s - C1) * (s - C2) * RD3
            for i in range(_N):
                u = _u(i * LANES + j)
                z = (
                    l1 * ZACC[u] + l2 * ZACC[_u(_V + u)] + l3 * ZACC[_u(2 * _V + u)]
                    - ZACC[_u(2 * _V + u)]
                )  # fmt: skip
                NW[_u(NW_Z + k * _V + u)] = z if POLY[j] else 0.0


@njit(inline="always", **LANE_KERNEL)
def _stage_transform(X, src, dst, c, vw) -> None:
    """X[dst] = (C x I) X[src] for a 3x3 matrix C (row-major tuple c), three stages."""
    c00, c01, c02, c10, c11, c12, c20, c21, c22 = c
    for u in range(_N * vw):
        s0 = X[_u(src + u)]
        s1 = X[_u(src + _V + u)]
        s2 = X[_u(src + 2 * _V + u)]
        X[_u(dst + u)] = c00 * s0 + c01 * s1 + c02 * s2
        X[_u(dst + _V + u)] = c10 * s0 + c11 * s1 + c12 * s2
        X[_u(dst + 2 * _V + u)] = c20 * s0 + c21 * s1 + c22 * s2


@njit(**LANE_KERNEL)
def to_w(NW, vw) -> None:
    """W = (T^-1 x I) Z in the Newton workspace, every lane."""
    _stage_transform(NW, NW_Z, NW_W, (TI00, TI01, TI02, TI10, TI11, TI12, TI20, TI21, TI22), vw)


@njit(**LANE_KERNEL)
def residual_lanes(NW, H, FIN, vw) -> None:
    """Transformed Newton residual of every lane into R1, R2, R3 of the workspace;
    FIN[lane] False where non-finite."""
    for j in range(vw):
        FIN[j] = True
    for i in range(_N):
        for j in range(vw):
            u = _u(i * LANES + j)
            fr = GAMMA / H[j]
            ar = ALPHA / H[j]
            br = BETA / H[j]
            f0 = NW[_u(NW_F + u)]
            f1 = NW[_u(NW_F + _V + u)]
            f2 = NW[_u(NW_F + 2 * _V + u)]
            g1 = TI00 * f0 + TI01 * f1 + TI02 * f2
            g2 = TI10 * f0 + TI11 * f1 + TI12 * f2
            g3 = TI20 * f0 + TI21 * f1 + TI22 * f2
            w1 = NW[_u(NW_W + _V + u)]
            w2 = NW[_u(NW_W + 2 * _V + u)]
            r1 = g1 - fr * NW[_u(NW_W + u)]
            r2 = g2 - (ar * w1 - br * w2)
            r3 = g3 - (br * w1 + ar * w2)
            FIN[j] = FIN[j] & (r1 == r1) & (r2 == r2) & (r3 == r3)
            NW[_u(NW_R1 + u)] = r1
            NW[_u(NW_R2 + u)] = r2
            NW[_u(NW_R3 + u)] = r3


@njit(**LANE_KERNEL)
def update_lanes(NW, RUN, vw) -> None:
    """W += the Newton correction (R1, R2, R3) in the running lanes; Z = (T x I) W."""
    for i in range(_N):
        for j in range(vw):
            u = _u(i * LANES + j)
            if RUN[j]:
                NW[_u(NW_W + u)] += NW[_u(NW_R1 + u)]
                NW[_u(NW_W + _V + u)] += NW[_u(NW_R2 + u)]
                NW[_u(NW_W + 2 * _V + u)] += NW[_u(NW_R3 + u)]
    _stage_transform(NW, NW_W, NW_Z, (T00, T01, T02, T10, T11, T12, T20, T21, T22), vw)


@njit(**LANE_KERNEL)
def wnorm_lanes(NW, out, vw) -> None:
    """sqrt(mean over components of (R1 scal)^2 + (R2 scal)^2 + (R3 scal)^2), every lane."""
    for j in range(vw):
        out[j] = 0.0
    for i in range(_N):
        for j in range(vw):
            u = _u(i * LANES + j)
            sc = NW[_u(NW_SCAL + u)]
            d1 = NW[_u(NW_R1 + u)] * sc
            d2 = NW[_u(NW_R2 + u)] * sc
            d3 = NW[_u(NW_R3 + u)] * sc
            out[j] += d1 * d1 + d2 * d2 + d3 * d3
    for j in range(vw):
        out[j] = math.sqrt(out[j] / (3 * _N))


@njit(**LANE_KERNEL)
def error_lanes(Y, YN, WORK, rtol, atol, SC, out, vw) -> None:
    """:func:`obturator.core.integrators.common.rms_norm` of WORK, every lane."""
    for j in range(vw):
        out[j] = 0.0
    for i in range(_N):
        for j in range(vw):
            u = _u(i * LANES + j)
            sc = atol * SC[u] + rtol * max(abs(Y[u]), abs(YN[u]))
            q = WORK[u] / sc
            out[j] += q * q
    for j in range(vw):
        out[j] = math.sqrt(out[j] / _N)


@njit(**LANE_KERNEL)
def stages_rhs(Y, Z, PL, F, WORK, WANT, kernel, vw) -> None:
    """The three stage derivatives f(y + Z_k) of every lane (the kernel is autonomous;
    the generic one only where WANT is set)."""
    for k in range(3):
        for u in range(_N * vw):
            WORK[u] = Y[u] + Z[_u(k * _V + u)]
        rates_lanes(WORK, PL, F, k * _V, kernel, WANT)


@njit(**LANE_KERNEL)
def f0_masked(Y, PL, F0, FW, ACC, CNT, kernel, vw) -> None:
    """F0 = f(Y) in the lanes with ACC set (one vector evaluation for all)."""
    any_acc = False
    for j in range(vw):
        any_acc = any_acc or ACC[j]
    if not any_acc:
        return
    rates_lanes(Y, PL, FW, 0, kernel, ACC)
    for i in range(_N):
        for j in range(vw):
            u = _u(i * LANES + j)
            F0[u] = FW[u] if ACC[j] else F0[u]
    for j in range(vw):
        if ACC[j]:
            CNT[0, j] += 1


@njit(**LANE_KERNEL)
def error_rhs_lanes(Y, Z, F0, H, YN, ERRV, WORK, vw) -> None:
    """y_new = y + Z_3 and the right side of the embedded error estimate (H&W IV.8),
    f0 + (e1 Z1 + e2 Z2 + e3 Z3) / h, into ERRV and WORK, every lane."""
    for i in range(_N):
        for j in range(vw):
            u = _u(i * LANES + j)
            YN[u] = Y[u] + Z[_u(2 * _V + u)]
            ERRV[u] = F0[u] + (E1 * Z[u] + E2 * Z[_u(_V + u)] + E3 * Z[_u(2 * _V + u)]) / H[j]
            WORK[u] = ERRV[u]


@njit(**LANE_KERNEL)
def node_states(Y, Z, k, out, vw) -> None:
    """y + Z_k (the collocation solution at node c_k), every lane."""
    for i in range(_N):
        for j in range(vw):
            u = _u(i * LANES + j)
            out[u] = Y[u] + Z[_u(k * _V + u)]
