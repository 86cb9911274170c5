"""The 8x8 LU routines of :mod:`.linalg`, for all lanes at once (structure of arrays).

Matrices are flat and lane-minor, ``a[(i * N_STATE + j) * LANES + lane]``, vectors
``b[i * LANES + lane]``, so every elimination step is one loop over lanes that
LLVM vectorises (offsets cast to unsigned, see :mod:`.lane_sums`). Pivoting
stays per lane: the pivot search is a vectorised running maximum, and the
row interchange, which differs between lanes and is rare in Radau's matrices
(gamma/h I - J is dominated by its diagonal for all but the longest steps), is
done lane by lane only where the pivot row is not the diagonal one.

Every routine takes ``vw``, the number of lanes its loops run over, which callers
pass at run time although it is always :data:`LANES`: with the constant trip
count LLVM unrolled the 16-lane loops into scalar code (it cannot prove the
arrays do not alias), with a runtime one it vectorises them behind a runtime
alias check (measured 2.5x faster elimination loops).

Per lane the operations are those of :func:`.linalg.lu_factor`,
:func:`.linalg.lu_factor_complex` and :func:`.linalg.lu_solve_pair`, in the
same order (the reciprocal pivot on the diagonal, |re| + |im| as the complex
pivot measure), with FMA contraction allowed as there.
"""

from __future__ import annotations

from numba import njit, uint64

from ..layout import N_STATE
from .lanes_layout import LANES

__all__ = ["lu_factor_lanes", "lu_factor_complex_lanes", "lu_solve_lanes", "lu_solve_pair_lanes"]

_N = N_STATE


@njit(cache=True, fastmath={"contract"}, error_model="numpy", inline="always")
def _at(i, j, lane):
    return uint64((i * _N + j) * LANES + lane)


@njit(cache=True, fastmath={"contract"}, error_model="numpy", inline="always")
def _pivot_search(k, ar, ai, piv, vmax, vw) -> bool:
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


@njit(cache=True, fastmath={"contract"}, error_model="numpy", inline="always")
def _interchange(k, ar, ai, piv, vmax, ok, swapped, vw) -> None:
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


@njit(cache=True, fastmath={"contract"}, error_model="numpy")
def lu_factor_lanes(m, piv, swapped, ok, vmax, vw) -> None:
    """In-place LU with partial pivoting of every lane's real matrix.

    Parameters
    ----------
    m : ndarray, shape (N_STATE * N_STATE * LANES,)
        The matrices; on return the factors, the diagonal of U as its reciprocal.
    piv : ndarray, shape (N_STATE * LANES,)
        Pivot rows as floats (``piv[k * LANES + lane]``).
    swapped : ndarray of bool, shape (N_STATE,)
        Whether any lane interchanged rows at column k (the solves skip the
        permutation where none did).
    ok : ndarray of bool, shape (LANES,)
        Set False for a lane whose matrix is singular (a zero pivot column;
        its factors are then meaningless); other lanes are left as they were.
    vmax : ndarray, shape (LANES,)
        Scratch.
    """
    for k in range(_N):
        swapped[k] = False
        if _pivot_search(k, m, None, piv, vmax, vw):
            _interchange(k, m, None, piv, vmax, ok, swapped, vw)
        for j in range(vw):
            m[_at(k, k, j)] = 1.0 / m[_at(k, k, j)]
        for i in range(k + 1, _N):
            for j in range(vw):
                m[_at(i, k, j)] = m[_at(i, k, j)] * m[_at(k, k, j)]
            for c in range(k + 1, _N):
                for j in range(vw):
                    m[_at(i, c, j)] -= m[_at(i, k, j)] * m[_at(k, c, j)]


@njit(cache=True, fastmath={"contract"}, error_model="numpy")
def lu_factor_complex_lanes(ar, ai, piv, swapped, ok, vmax, vw) -> None:
    """In-place LU with partial pivoting of every lane's complex matrix ar + i ai.

    As :func:`lu_factor_lanes` (split storage, |re| + |im| pivot measure, the
    reciprocal pivot on the diagonal).
    """
    for k in range(_N):
        swapped[k] = False
        if _pivot_search(k, ar, ai, piv, vmax, vw):
            _interchange(k, ar, ai, piv, vmax, ok, swapped, vw)
        for j in range(vw):
            xr = ar[_at(k, k, j)]
            xi = ai[_at(k, k, j)]
            d = xr * xr + xi * xi
            ir = xr / d
            ii = -xi / d
            ar[_at(k, k, j)] = ir
            ai[_at(k, k, j)] = ii
        for i in range(k + 1, _N):
            for j in range(vw):
                ir = ar[_at(k, k, j)]
                ii = ai[_at(k, k, j)]
                pr = ar[_at(i, k, j)]
                pi = ai[_at(i, k, j)]
                ar[_at(i, k, j)] = pr * ir - pi * ii
                ai[_at(i, k, j)] = pr * ii + pi * ir
            for c in range(k + 1, _N):
                for j in range(vw):
                    fr = ar[_at(i, k, j)]
                    fi = ai[_at(i, k, j)]
                    ar[_at(i, c, j)] -= fr * ar[_at(k, c, j)] - fi * ai[_at(k, c, j)]
                    ai[_at(i, c, j)] -= fr * ai[_at(k, c, j)] + fi * ar[_at(k, c, j)]


@njit(cache=True, fastmath={"contract"}, error_model="numpy", inline="always")
def _permute(piv, swapped, b, vw) -> None:
    for k in range(_N):
        if swapped[k]:
            for j in range(vw):
                r = int(piv[uint64(k * LANES + j)])
                if r != k:
                    tmp = b[uint64(k * LANES + j)]
                    b[uint64(k * LANES + j)] = b[uint64(r * LANES + j)]
                    b[uint64(r * LANES + j)] = tmp


@njit(cache=True, fastmath={"contract"}, error_model="numpy")
def lu_solve_lanes(lu, piv, swapped, b, vw) -> None:
    """Solve lu x = b in place in every lane (factors of :func:`lu_factor_lanes`)."""
    _permute(piv, swapped, b, vw)
    for i in range(_N):
        for c in range(i):
            for j in range(vw):
                b[uint64(i * LANES + j)] -= lu[_at(i, c, j)] * b[uint64(c * LANES + j)]
    for i in range(_N - 1, -1, -1):
        for c in range(i + 1, _N):
            for j in range(vw):
                b[uint64(i * LANES + j)] -= lu[_at(i, c, j)] * b[uint64(c * LANES + j)]
        for j in range(vw):
            b[uint64(i * LANES + j)] *= lu[_at(i, i, j)]


@njit(cache=True, fastmath={"contract"}, error_model="numpy", inline="always")
def _eliminate(lu, b, ar, ai, br, bi, i, c, vw) -> None:
    """Row i of both systems minus its multiple of (solved) row c, every lane."""
    for j in range(vw):
        u = uint64(c * LANES + j)
        v = uint64(i * LANES + j)
        b[v] -= lu[_at(i, c, j)] * b[u]
        xr = br[u]
        xi = bi[u]
        br[v] -= ar[_at(i, c, j)] * xr - ai[_at(i, c, j)] * xi
        bi[v] -= ar[_at(i, c, j)] * xi + ai[_at(i, c, j)] * xr


@njit(cache=True, fastmath={"contract"}, error_model="numpy")
def lu_solve_pair_lanes(lu, piv, swapped, b, ar, ai, pivc, swapped_c, br, bi, vw) -> None:
    """Real and complex solves of a Newton iteration in every lane (as
    :func:`.linalg.lu_solve_pair`, per lane the same operations)."""
    _permute(piv, swapped, b, vw)
    _permute(pivc, swapped_c, br, vw)
    _permute(pivc, swapped_c, bi, vw)
    for i in range(_N):
        for c in range(i):
            _eliminate(lu, b, ar, ai, br, bi, i, c, vw)
    for i in range(_N - 1, -1, -1):
        for c in range(i + 1, _N):
            _eliminate(lu, b, ar, ai, br, bi, i, c, vw)
        for j in range(vw):
            sr = br[uint64(i * LANES + j)]
            si = bi[uint64(i * LANES + j)]
            b[uint64(i * LANES + j)] *= lu[_at(i, i, j)]
            dr = ar[_at(i, i, j)]
            di = ai[_at(i, i, j)]
            br[uint64(i * LANES + j)] = sr * dr - si * di
            bi[uint64(i * LANES + j)] = sr * di + si * dr
