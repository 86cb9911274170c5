"""One Radau IIA collocation step: the LU of the Newton matrices, the simplified Newton
iterations and the collocation polynomial (Hairer & Wanner, *Solving Ordinary
Differential Equations II*, Sec. IV.8; see :mod:`.radau` for the method's notes).

Shared by :func:`.radau.integrate` and :mod:`.stick_slip`.
"""

from __future__ import annotations

import math

from numba import njit

from ..dynamics import rhs
from ..jit_flags import NO_REFCOUNT
from ..layout import N_STATE
from .linalg import lu_factor, lu_factor_complex, lu_solve_pair
from .radau_coefficients import (
    ALPHA,
    BETA,
    C1,
    C2,
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
from .radau_control import _NIT, _THET, _UROUND, newton_contraction

__all__ = ["_colloc_weights", "_factor", "_newton", "_dense"]


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _colloc_weights(s: float) -> tuple[float, float, float]:
    """Weights of Z1, Z2, Z3 in the collocation polynomial at t0 + s h (s may exceed 1)."""
    l1 = s * (s - C2) * (s - 1.0) * RD1
    l2 = s * (s - C1) * (s - 1.0) * RD2
    l3 = s * (s - C1) * (s - C2) * RD3
    return l1, l2, l3


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _factor(h, jac, lu) -> bool:
    """LU of gamma/h I - J (real) and (alpha + i beta)/h I - J (complex, split storage).

    `lu` holds the factors: (lu_r, piv_r, lu_cr, lu_ci, piv_c).
    """
    lu_r, piv_r, lu_cr, lu_ci, piv_c = lu
    n = N_STATE
    fr = GAMMA / h
    ar = ALPHA / h
    br = BETA / h
    for i in range(n):
        for j in range(n):
            lu_r[i, j] = -jac[i, j]
            lu_cr[i, j] = -jac[i, j]
            lu_ci[i, j] = 0.0
        lu_r[i, i] += fr
        lu_cr[i, i] += ar
        lu_ci[i, i] = br
    if not lu_factor(lu_r, piv_r):
        return False
    return lu_factor_complex(lu_cr, lu_ci, piv_c)


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _newton(t, y, h, p, scal, stage, lu, scratch, faccon0, fnewt):
    """Simplified Newton iterations for the stage increments Z (initial guess in z).

    scal holds the reciprocal error weights 1 / (atol scale_i + rtol |y_i|);
    stage = (z, w, f): the stage increments Z, their transform W and the stage
    derivatives; lu the factors of :func:`_factor`; scratch = (work, cbr, cbi).

    Returns
    -------
    tuple
        (converged, n_iter, theta, faccon, h_factor): theta is the observed
        contraction rate (_THET when one iteration sufficed), h_factor the step
        reduction to apply when not converged.
    """
    z, w, f = stage
    work, cbr, cbi = scratch
    lu_r, piv_r, lu_cr, lu_ci, piv_c = lu
    n = N_STATE
    for i in range(n):  # W = (T^-1 x I) Z
        w[0, i] = TI00 * z[0, i] + TI01 * z[1, i] + TI02 * z[2, i]
        w[1, i] = TI10 * z[0, i] + TI11 * z[1, i] + TI12 * z[2, i]
        w[2, i] = TI20 * z[0, i] + TI21 * z[1, i] + TI22 * z[2, i]
    faccon = max(faccon0, _UROUND) ** 0.8
    theta = _THET
    dynold = 1.0
    thqold = 1.0
    fr = GAMMA / h
    ar = ALPHA / h
    br = BETA / h
    newt = 0
    while True:
        if newt >= _NIT:
            return False, newt, theta, faccon, 0.5
        for k in range(3):
            ck = C1 if k == 0 else (C2 if k == 1 else 1.0)
            for i in range(n):
                work[i] = y[i] + z[k, i]
            rhs(t + ck * h, work, p, f[k])
        newt += 1
        finite = True
        for i in range(n):
            # residual G - (Lambda/h) W in the transformed variables
            g1 = TI00 * f[0, i] + TI01 * f[1, i] + TI02 * f[2, i]
            g2 = TI10 * f[0, i] + TI11 * f[1, i] + TI12 * f[2, i]
            g3 = TI20 * f[0, i] + TI21 * f[1, i] + TI22 * f[2, i]
            r1 = g1 - fr * w[0, i]
            r2 = g2 - (ar * w[1, i] - br * w[2, i])
            r3 = g3 - (br * w[1, i] + ar * w[2, i])
            if not (r1 == r1 and r2 == r2 and r3 == r3):
                finite = False
            work[i] = r1
            cbr[i] = r2
            cbi[i] = r3
        if not finite:
            return False, newt, theta, faccon, 0.5
        lu_solve_pair(lu_r, piv_r, work, lu_cr, lu_ci, piv_c, cbr, cbi)
        dyno = 0.0
        for i in range(n):
            d1 = work[i] * scal[i]
            d2 = cbr[i] * scal[i]
            d3 = cbi[i] * scal[i]
            dyno += d1 * d1 + d2 * d2 + d3 * d3
        dyno = math.sqrt(dyno / (3 * n))
        failed, theta, thqold, faccon, hfac = newton_contraction(
            newt, dyno, dynold, thqold, theta, faccon, fnewt
        )
        if failed:
            return False, newt, theta, faccon, hfac
        dynold = max(dyno, _UROUND)
        for i in range(n):
            w[0, i] += work[i]
            w[1, i] += cbr[i]
            w[2, i] += cbi[i]
            z[0, i] = T00 * w[0, i] + T01 * w[1, i] + T02 * w[2, i]
            z[1, i] = T10 * w[0, i] + T11 * w[1, i] + T12 * w[2, i]
            z[2, i] = T20 * w[0, i] + T21 * w[1, i] + T22 * w[2, i]
        if faccon * dyno <= fnewt:
            return True, newt, theta, faccon, 1.0


@njit(cache=True, fastmath={"contract"}, **NO_REFCOUNT, error_model="numpy")
def _dense(y, z, s, out) -> None:
    """Collocation polynomial of the step (y, z) at t0 + s h, written into out."""
    l1, l2, l3 = _colloc_weights(s)
    for i in range(N_STATE):
        out[i] = y[i] + l1 * z[0, i] + l2 * z[1, i] + l3 * z[2, i]
