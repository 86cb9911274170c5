"""Step control of Radau IIA: RADAU5's constants and the decisions every Radau IIA driver
shares (:mod:`.radau`, :mod:`.stick_slip`, the lanes of :mod:`.lanes.radau`).

RADAU5's Newton convergence test, the step-size quotient with Gustafsson's
predictive controller, and the rule for the next step (Hairer & Wanner, *Solving
Ordinary Differential Equations II*, Sec. IV.8), as plain-float functions so that
the one-trajectory integrator and the lanes decide alike.
"""

from __future__ import annotations

import math
from typing import NamedTuple

from numba import njit

from ..._docs import field_docs

__all__ = [
    "newton_contraction",
    "step_quotient",
    "next_step",
    "RADAU5",
    "Radau5Settings",
    "radau5_tolerances",
]


@field_docs
class Radau5Settings(NamedTuple):
    """RADAU5's control constants (Hairer & Wanner, Sec. IV.8, and radau5.f), the one
    place they are written (defaults: :data:`RADAU5`); the tableau is
    :mod:`.radau_coefficients`."""

    #: Unit roundoff of float64 (radau5.f's UROUND).
    uround: float = 2.220446049250313e-16
    #: Newton iterations per step before the step is cut (radau5.f's NIT).
    nit: int = 7
    #: Keep the Jacobian while Newton contracts faster than this (radau5.f: 0.001; an
    #: 8-equation Jacobian costs 8 right-hand sides, so it is kept longer here).
    thet: float = 0.01
    #: Keep h, J and the LU when h_new / h falls in [quot1, quot2] (radau5.f) ...
    quot1: float = 1.0
    #: ... its upper end.
    quot2: float = 1.2
    #: Safety factor of the step-size controller (radau5.f's SAFE).
    safe: float = 0.9
    #: Smallest h_new / h (radau5.f's FACL = 5 as 1 / FACL).
    fac_min: float = 0.2
    #: Largest h_new / h (radau5.f's FACR = 1/8 as 1 / FACR).
    fac_max: float = 8.0
    #: Tolerance transformation rtol' = tol_scale rtol^tol_power: the embedded estimate is
    #: of order 3, the solution of order 5 (radau5.f) ...
    tol_scale: float = 0.1
    #: ... its exponent.
    tol_power: float = 2.0 / 3.0
    #: Newton stopping tolerance FNEWT = max(fnewt_uround UROUND / rtol', min(fnewt_max,
    #: sqrt(rtol'))) (radau5.f) ...
    fnewt_uround: float = 10.0
    #: ... its cap.
    fnewt_max: float = 0.03
    #: Exponent of the carried-over contraction estimate FACCON (radau5.f).
    faccon_power: float = 0.8
    #: Floor of the previous error in Gustafsson's controller (radau5.f's ERRACC floor).
    err_gus_min: float = 1e-2
    #: Step reduction after a Newton failure without a contraction estimate, and after a
    #: failed LU (radau5.f).
    newton_cut: float = 0.5
    #: Step reduction after a rejected first step (radau5.f).
    first_cut: float = 0.1
    #: Newton-limited regime (Coulomb sticking): after a Newton failure at h the step is
    #: capped at lim_shrink h, so the error controller does not retry steps that fail ...
    lim_shrink: float = 0.7
    #: ... and the cap grows by this per accepted step (1.2 met the keep-h window every
    #: other step and crept up ~1.1x per step where the error allowed 8x).
    lim_grow: float = 2.0


#: RADAU5's control constants every Radau IIA driver uses.
RADAU5 = Radau5Settings()

# module constants for the compiled code (numba freezes plain globals)
_UROUND = RADAU5.uround
_NIT = RADAU5.nit
_THET = RADAU5.thet
_QUOT1 = RADAU5.quot1
_QUOT2 = RADAU5.quot2
_SAFE = RADAU5.safe
_FAC_MIN = RADAU5.fac_min
_FAC_MAX = RADAU5.fac_max
_TOL_SCALE = RADAU5.tol_scale
_TOL_POWER = RADAU5.tol_power
_FNEWT_UROUND = RADAU5.fnewt_uround
_FNEWT_MAX = RADAU5.fnewt_max
FACCON_POWER = RADAU5.faccon_power
ERR_GUS_MIN = RADAU5.err_gus_min
NEWTON_CUT = RADAU5.newton_cut
FIRST_CUT = RADAU5.first_cut
_LIM_SHRINK = RADAU5.lim_shrink
_LIM_GROW = RADAU5.lim_grow


@njit(cache=True, fastmath=False, inline="always")
def newton_contraction(newt, dyno, dynold, thqold, theta, faccon, fnewt):
    """RADAU5's convergence test after Newton iteration `newt` with correction norm dyno.

    From the second iteration on, the contraction rate theta (geometric mean of the last
    two ratios) predicts the size of the last iterate after _NIT iterations; the step
    fails when that stays above the Newton tolerance, or when theta >= 0.99. Shared by
    :func:`_newton` and the Radau lanes.

    Returns
    -------
    tuple
        (failed, theta, thqold, faccon, h_factor): h_factor the step reduction after a
        failure.
    """
    if newt > 1 and newt < _NIT:
        thq = dyno / dynold
        theta = thq if newt == 2 else math.sqrt(thq * thqold)
        thqold = thq
        if theta < 0.99:
            faccon = theta / (1.0 - theta)
            # predicted size of the last iterate after _NIT iterations
            dyth = faccon * dyno * theta ** (_NIT - 1 - newt) / fnewt
            if dyth >= 1.0:
                qnewt = max(1e-4, min(20.0, dyth))
                return True, theta, thqold, faccon, 0.8 * qnewt ** (-1.0 / (4 + _NIT - 1 - newt))
        else:
            return True, theta, thqold, faccon, NEWTON_CUT
    return False, theta, thqold, faccon, 1.0


@njit(cache=True, fastmath=False, inline="always")
def step_quotient(err, newt, h, first, h_gus, err_gus):
    """h / h_new after a step with scaled error err (H&W IV.8): the standard factor with
    RADAU5's Newton-dependent safety, and after the first step Gustafsson's predictive
    controller (Eq. 8.21) where it asks for less. Returns (quot, quot_standard); a
    rejected step uses the standard one. Shared by :func:`integrate` and the Radau lanes.
    """
    fac = min(_SAFE, (2 * _NIT + 1.0) / (2 * _NIT + newt))
    quot = max(1.0 / _FAC_MAX, min(1.0 / _FAC_MIN, math.sqrt(math.sqrt(err)) / fac))
    if first or err >= 1.0:
        return quot, quot
    facgus = (h_gus / h) * math.sqrt(math.sqrt(err * err / err_gus)) / fac
    facgus = max(1.0 / _FAC_MAX, min(1.0 / _FAC_MIN, facgus))
    return max(quot, facgus), quot


@njit(cache=True, fastmath=False, inline="always")
def next_step(h, h_new, h_lim, h_max, rejected, theta):
    """After an accepted step of length h: (h_next, h_lim, need_jac).

    The proposal is capped by the Newton-failure cap (which then relaxes by _LIM_GROW)
    and h_max, and does not grow right after a rejection; h, the Jacobian and the LU are
    kept when Newton contracted fast and the change would be within [_QUOT1, _QUOT2];
    a slow contraction asks for a new Jacobian. Shared by :func:`integrate` and the
    Radau lanes.
    """
    h_new = min(h_new, h_lim, h_max)
    h_lim *= _LIM_GROW
    if rejected:
        h_new = min(h_new, h)  # no growth right after a rejection
    qt = h_new / h
    if theta <= _THET and _QUOT1 <= qt <= _QUOT2:
        return h, h_lim, False  # keep h, the Jacobian and the LU factors
    return h_new, h_lim, theta > _THET


@njit(cache=True, fastmath=False, inline="always")
def radau5_tolerances(rtol: float, atol: float) -> tuple[float, float, float]:
    """RADAU5's tolerance transformation and its Newton stopping tolerance FNEWT.

    The embedded estimate is of order 3 while the solution is of order 5, so the
    estimate is compared with a looser tolerance (rtol' = 0.1 rtol^(2/3), atol in
    proportion); this keeps the achieved accuracy roughly proportional to rtol.
    Returns (rtol', atol', fnewt), fnewt relative to the error weights.
    """
    quot_tol = atol / rtol
    rtol = _TOL_SCALE * rtol**_TOL_POWER
    atol = rtol * quot_tol
    fnewt = max(_FNEWT_UROUND * _UROUND / rtol, min(_FNEWT_MAX, math.sqrt(rtol)))
    return rtol, atol, fnewt
