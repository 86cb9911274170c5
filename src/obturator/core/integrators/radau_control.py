"""Step control of Radau IIA: the decisions shared by :mod:`.radau` and :mod:`.radau_lanes`.

RADAU5's Newton convergence test, the step-size quotient with Gustafsson's
predictive controller, and the rule for the next step (Hairer & Wanner, *Solving
Ordinary Differential Equations II*, Sec. IV.8), as plain-float functions so that
the one-trajectory integrator and the lanes decide alike.
"""

from __future__ import annotations

import math

from numba import njit

__all__ = [
    "newton_contraction",
    "step_quotient",
    "next_step",
    "sliding_resumed",
    "radau5_tolerances",
]

_UROUND = 2.220446049250313e-16

_NIT = 7  # Newton iterations per step before the step is cut (RADAU5 default)
_THET = 0.01  # keep the Jacobian while Newton contracts faster than this (RADAU5: 0.001)
_QUOT1 = 1.0  # keep h, J and the LU when h_new / h falls in [_QUOT1, _QUOT2] (RADAU5)
_QUOT2 = 1.2
_SAFE = 0.9
_FAC_MIN = 0.2  # h_new / h bounds
_FAC_MAX = 8.0
# Newton-limited regime (Coulomb sticking): after a Newton failure at h, cap the
# step at _LIM_SHRINK h and let the cap grow by _LIM_GROW per accepted step, so
# the error-based controller does not keep proposing steps that fail again. A growth
# of 1.2 met the keep-h window [_QUOT1, _QUOT2] every other step, so after a stick
# transition the step crept up ~1.1x per step while the error allowed 8x (at 100
# rad/s, 1,100 of 2,690 steps sat at the cap with errors ~1e-8); 2 took 17 % fewer
# steps and 10 % less time on 1,786 near-stick rig points (1.5: 6 %, 3: 9 %).
_LIM_SHRINK = 0.7
_LIM_GROW = 2.0
#: Hand-back to DOP853 (``auto``): a slip speed above this many regularisation widths
#: delta leaves the regularised Coulomb magnitude saturated (1 - 5e-9 for the algebraic
#: family), so the stiffness that sticking brings is gone. Sticking stretches reach
#: |omega_r| ~ 1e-8..1e-7 omega_p0, i.e. ~0.1..1 delta, clean sliding >= 1e-2 omega_p0
#: (measured on rig points at 100-207 rad/s), far on either side of 1e4 delta = 1e-3 omega_p0.
SLIDING_WIDTHS = 1e4
#: Revolutions of uninterrupted sliding before the hand-back: sticking recurs twice per
#: revolution in the stick-slip phase, so half a revolution without it means the phase
#: is over (on the rig it does not come back). Measured on 44 rig points at 100-207
#: rad/s, Radau IIA's right-hand sides fell by 15 % (1: 16 % fewer, 0.25: DOP853 and
#: Radau IIA took turns within the stick-slip phase).
SLIDING_REVOLUTIONS = 0.5


@njit(cache=True, fastmath={"contract"}, inline="always")
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
            return True, theta, thqold, faccon, 0.5
    return False, theta, thqold, faccon, 1.0


@njit(cache=True, fastmath={"contract"}, inline="always")
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


@njit(cache=True, fastmath={"contract"}, inline="always")
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


@njit(cache=True, fastmath={"contract"}, inline="always")
def sliding_resumed(t, t_stick, slip, spin, width):
    """After an accepted step at time t: (hand back, t_stick).

    t_stick is the last time the slip speed `slip` [rad/s] was below
    :data:`SLIDING_WIDTHS` regularisation widths `width` [rad/s]; the run hands back
    when the time since then covers :data:`SLIDING_REVOLUTIONS` revolutions at the
    spin `spin` [rad/s]. Shared by :func:`.radau.integrate` and the Radau lanes.
    """
    if slip < SLIDING_WIDTHS * width:
        return False, t
    return (t - t_stick) * abs(spin) >= 2.0 * math.pi * SLIDING_REVOLUTIONS, t_stick


@njit(cache=True, fastmath={"contract"}, inline="always")
def radau5_tolerances(rtol: float, atol: float) -> tuple[float, float, float]:
    """RADAU5's tolerance transformation and its Newton stopping tolerance FNEWT.

    The embedded estimate is of order 3 while the solution is of order 5, so the
    estimate is compared with a looser tolerance (rtol' = 0.1 rtol^(2/3), atol in
    proportion); this keeps the achieved accuracy roughly proportional to rtol.
    Returns (rtol', atol', fnewt), fnewt relative to the error weights.
    """
    quot_tol = atol / rtol
    rtol = 0.1 * rtol ** (2.0 / 3.0)
    atol = rtol * quot_tol
    fnewt = max(10.0 * _UROUND / rtol, min(0.03, math.sqrt(rtol)))
    return rtol, atol, fnewt
