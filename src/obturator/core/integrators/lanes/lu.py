"""The real and complex 8x8 LU factorisations over lanes (structure of arrays).

Matrices are flat and lane-minor, ``a[(i * N_STATE + j) * LANES + lane]``; pivoting is
per lane (:mod:`.pivot`); the solves are generated with their offsets written out
(:mod:`.solves`). Per lane the operations are those of
:func:`obturator.core.integrators.linalg.lu_factor` and
:func:`obturator.core.integrators.linalg.lu_factor_complex` in the same order (the
reciprocal pivot on the diagonal, |re| + |im| as the complex pivot measure), no
fast-math (:mod:`obturator.core.jit_flags`). ``vw`` is the lane count, passed at run time (always
``LANES``): with the constant LLVM unrolled the 16-lane loops into scalar code.

Written as loops over rows and columns on purpose: a generated form with every offset a
constant (as the solves in :mod:`.solves`) was no faster here (real 108 against
126 ns per lane, complex 203 against 173) and took 30 s instead of a few to compile.
Measured per lane on the 2-core AMD machine, real and complex factorisation plus three
pair solves: ~930 ns one lane at a time with :mod:`obturator.core.integrators.linalg`,
~470 ns in lanes.
"""

from __future__ import annotations

from numba import njit, uint64

from ...fma import fma
from ...layout import N_STATE
from .pivot import interchange, pivot_search
from .simd import LANE_KERNEL, LANES

__all__ = ["lu_factor_lanes", "lu_factor_complex_lanes"]

_N = N_STATE


@njit(inline="always", **LANE_KERNEL)
def _at(i, j, lane):
    return uint64((i * _N + j) * LANES + lane)


@njit(**LANE_KERNEL)
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
        if pivot_search(k, m, None, piv, vmax, vw):
            interchange(k, m, None, piv, vmax, ok, swapped, vw)
        for j in range(vw):
            m[_at(k, k, j)] = 1.0 / m[_at(k, k, j)]
        for i in range(k + 1, _N):
            for j in range(vw):
                m[_at(i, k, j)] = m[_at(i, k, j)] * m[_at(k, k, j)]
            for c in range(k + 1, _N):
                for j in range(vw):
                    m[_at(i, c, j)] = fma(-m[_at(i, k, j)], m[_at(k, c, j)], m[_at(i, c, j)])


@njit(**LANE_KERNEL)
def lu_factor_complex_lanes(ar, ai, piv, swapped, ok, vmax, vw) -> None:
    """In-place LU with partial pivoting of every lane's complex matrix ar + i ai.

    As :func:`lu_factor_lanes` (split storage, |re| + |im| pivot measure, the
    reciprocal pivot on the diagonal).
    """
    for k in range(_N):
        swapped[k] = False
        if pivot_search(k, ar, ai, piv, vmax, vw):
            interchange(k, ar, ai, piv, vmax, ok, swapped, vw)
        for j in range(vw):
            xr = ar[_at(k, k, j)]
            xi = ai[_at(k, k, j)]
            d = fma(xr, xr, xi * xi)
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
                ar[_at(i, k, j)] = fma(pr, ir, -(pi * ii))
                ai[_at(i, k, j)] = fma(pr, ii, pi * ir)
            for c in range(k + 1, _N):
                for j in range(vw):
                    fr = ar[_at(i, k, j)]
                    fi = ai[_at(i, k, j)]
                    kr = ar[_at(k, c, j)]
                    ki = ai[_at(k, c, j)]
                    ar[_at(i, c, j)] = fma(-fr, kr, fma(fi, ki, ar[_at(i, c, j)]))
                    ai[_at(i, c, j)] = fma(-fr, ki, fma(-fi, kr, ai[_at(i, c, j)]))
