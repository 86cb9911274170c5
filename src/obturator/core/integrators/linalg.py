"""Dense 8x8 linear algebra of the implicit integrators (LU with partial pivoting).

One real LU (:func:`lu_factor`, :func:`lu_solve`) serves Radau IIA and the
Rosenbrock pair; Radau's complex system has its own split-storage LU
(:func:`lu_factor_complex`) and a solve that runs the real and the complex
substitutions of a Newton iteration interleaved (:func:`lu_solve_pair`).

The routines are specialised to the fixed size N_STATE (loops with
compile-time trip counts, which LLVM unrolls): about half the time per
factorisation of a generic LU. The diagonal of U is stored as its reciprocal,
so the solves multiply (a division per row would lengthen the solve's
dependency chain). No fast-math (:mod:`obturator.core.jit_flags`); each multiply
that feeds an add or a subtraction is one fused operation (:func:`~obturator.core.fma.fma`),
written out.
"""

from __future__ import annotations

from numba import njit

from ..fma import fma
from ..jit_flags import NO_REFCOUNT
from ..layout import N_STATE

__all__ = ["lu_factor", "lu_solve", "lu_factor_complex", "lu_solve_pair"]


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
def lu_factor(m, piv) -> bool:
    """In-place LU with partial pivoting of the real N_STATE x N_STATE matrix m.

    The diagonal of U is stored as its reciprocal, so the solve multiplies
    (a division per row would lengthen the solve's dependency chain).
    """
    for k in range(N_STATE):
        imax = k
        vmax = abs(m[k, k])
        for i in range(k + 1, N_STATE):
            if abs(m[i, k]) > vmax:
                vmax = abs(m[i, k])
                imax = i
        piv[k] = imax
        if vmax == 0.0:
            return False
        if imax != k:
            for j in range(N_STATE):
                tmp = m[k, j]
                m[k, j] = m[imax, j]
                m[imax, j] = tmp
        inv = 1.0 / m[k, k]
        m[k, k] = inv
        for i in range(k + 1, N_STATE):
            f = m[i, k] * inv
            m[i, k] = f
            for j in range(k + 1, N_STATE):
                m[i, j] = fma(-f, m[k, j], m[i, j])
    return True


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="python")
def lu_solve(lu, piv, b) -> None:
    """Solve lu x = b in place with the factors of lu_factor."""
    for k in range(N_STATE):
        j = piv[k]
        if j != k:
            tmp = b[k]
            b[k] = b[j]
            b[j] = tmp
    for i in range(N_STATE):
        s = b[i]
        for j in range(i):
            s = fma(-lu[i, j], b[j], s)
        b[i] = s
    for i in range(N_STATE - 1, -1, -1):
        s = b[i]
        for j in range(i + 1, N_STATE):
            s = fma(-lu[i, j], b[j], s)
        b[i] = s * lu[i, i]  # reciprocal pivot


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
def lu_factor_complex(ar, ai, piv) -> bool:
    """In-place LU with partial pivoting of the complex matrix ar + i ai.

    Split real/imaginary storage, a |re| + |im| pivot measure (no hypot), and
    the reciprocal of each pivot stored on the diagonal (see lu_factor).
    """
    for k in range(N_STATE):
        imax = k
        vmax = abs(ar[k, k]) + abs(ai[k, k])
        for i in range(k + 1, N_STATE):
            v = abs(ar[i, k]) + abs(ai[i, k])
            if v > vmax:
                vmax = v
                imax = i
        piv[k] = imax
        if vmax == 0.0:
            return False
        if imax != k:
            for j in range(N_STATE):
                tr = ar[k, j]
                ar[k, j] = ar[imax, j]
                ar[imax, j] = tr
                ti = ai[k, j]
                ai[k, j] = ai[imax, j]
                ai[imax, j] = ti
        d = fma(ar[k, k], ar[k, k], ai[k, k] * ai[k, k])
        ir = ar[k, k] / d
        ii = -ai[k, k] / d
        ar[k, k] = ir
        ai[k, k] = ii
        for i in range(k + 1, N_STATE):
            fr = fma(ar[i, k], ir, -(ai[i, k] * ii))
            fi = fma(ar[i, k], ii, ai[i, k] * ir)
            ar[i, k] = fr
            ai[i, k] = fi
            for j in range(k + 1, N_STATE):
                ar[i, j] = fma(-fr, ar[k, j], fma(fi, ai[k, j], ar[i, j]))
                ai[i, j] = fma(-fr, ai[k, j], fma(-fi, ar[k, j], ai[i, j]))
    return True


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="numpy")
def lu_solve_pair(lu, piv, b, ar, ai, pivc, br, bi) -> None:
    """Solve lu x = b (real, factors of lu_factor) and (ar + i ai) x = br + i bi
    (complex, factors of lu_factor_complex) in place, in one pass.

    The two substitutions are independent; interleaving them lets their
    dependency chains overlap. Pivot swaps are unconditional (a swap with
    itself is a no-op), which avoids a data-dependent branch per row.
    """
    for k in range(N_STATE):
        j = piv[k]
        tmp = b[k]
        b[k] = b[j]
        b[j] = tmp
        j = pivc[k]
        tmp = br[k]
        br[k] = br[j]
        br[j] = tmp
        tmp = bi[k]
        bi[k] = bi[j]
        bi[j] = tmp
    for i in range(N_STATE):
        s = b[i]
        sr = br[i]
        si = bi[i]
        for j in range(i):
            s = fma(-lu[i, j], b[j], s)
            sr = fma(-ar[i, j], br[j], fma(ai[i, j], bi[j], sr))
            si = fma(-ar[i, j], bi[j], fma(-ai[i, j], br[j], si))
        b[i] = s
        br[i] = sr
        bi[i] = si
    for i in range(N_STATE - 1, -1, -1):
        s = b[i]
        sr = br[i]
        si = bi[i]
        for j in range(i + 1, N_STATE):
            s = fma(-lu[i, j], b[j], s)
            sr = fma(-ar[i, j], br[j], fma(ai[i, j], bi[j], sr))
            si = fma(-ar[i, j], bi[j], fma(-ai[i, j], br[j], si))
        b[i] = s * lu[i, i]  # times the reciprocal pivots
        br[i] = fma(sr, ar[i, i], -(si * ai[i, i]))
        bi[i] = fma(sr, ai[i, i], si * ar[i, i])
