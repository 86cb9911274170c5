"""Partial pivoting of the lane LU (:mod:`.lu`, :mod:`.solves`), lane by lane.

The pivot search is a vectorised running maximum over the lanes; the row
interchange differs between lanes and is rare in Radau's iteration matrices
(gamma/h I - J is dominated by its diagonal for all but the longest steps), so
it is done lane by lane, only where a lane's pivot row is not the diagonal one.
"""

from __future__ import annotations

from numba import njit, uint64

from ...layout import N_STATE
from .simd import LANE_KERNEL, LANES

__all__ = ["pivot_search", "interchange", "permute"]

_N = N_STATE


@njit(inline="always", **LANE_KERNEL)
def _at(i, j, lane):
    return uint64((i * _N + j) * LANES + lane)


@njit(inline="always", **LANE_KERNEL)
def pivot_search(k, ar, ai, piv, vmax, vw) -> bool:
    """Pivot row of column k in every lane (|re| + |im|; ai None for real matrices).

    A vectorised running maximum; the row index is kept as a float so the
    loop has one data type. Returns whether any lane needs a row interchange
    or has a zero column (the rare case handled lane by lane).
    """
    for j in range(vw):
        v = abs(ar[_at(k, k, j)])
        if ai is not None:
            v += abs(ai[_at(k, k, j)])
        vmax[j] = v
        piv[uint64(k * LANES + j)] = k
    for i in range(k + 1, _N):
        for j in range(vw):
            v = abs(ar[_at(i, k, j)])
            if ai is not None:
                v += abs(ai[_at(i, k, j)])
            better = v > vmax[j]
            piv[uint64(k * LANES + j)] = i if better else piv[uint64(k * LANES + j)]
            vmax[j] = v if better else vmax[j]
    rare = 0
    for j in range(vw):
        rare += (piv[uint64(k * LANES + j)] != k) | (vmax[j] == 0.0)
    return rare > 0


@njit(inline="always", **LANE_KERNEL)
def interchange(k, ar, ai, piv, vmax, ok, swapped, vw) -> None:
    """Row interchanges of column k, lane by lane, and the singular lanes."""
    for j in range(vw):
        if vmax[j] == 0.0:
            ok[j] = False
        r = int(piv[uint64(k * LANES + j)])
        if r != k:
            swapped[k] = True
            for c in range(_N):
                tr = ar[_at(k, c, j)]
                ar[_at(k, c, j)] = ar[_at(r, c, j)]
                ar[_at(r, c, j)] = tr
                if ai is not None:
                    ti = ai[_at(k, c, j)]
                    ai[_at(k, c, j)] = ai[_at(r, c, j)]
                    ai[_at(r, c, j)] = ti


@njit(inline="always", **LANE_KERNEL)
def permute(piv, swapped, b, vw) -> None:
    """Apply the row interchanges of the factorisation to b, lane by lane where any."""
    for k in range(_N):
        if swapped[k]:
            for j in range(vw):
                r = int(piv[uint64(k * LANES + j)])
                if r != k:
                    tmp = b[uint64(k * LANES + j)]
                    b[uint64(k * LANES + j)] = b[uint64(r * LANES + j)]
                    b[uint64(r * LANES + j)] = tmp
