"""The specialised right-hand side: the thesis's torque model without branching on codes.

The generic :func:`obturator.core.dynamics.rhs` reads model codes from ``p`` on
every call and dispatches (formulation, spin mode, viscous branch, friction law,
regularisation family, slip-speed law). Sweeps and fits spend almost all of
their time in one combination, the thesis's (quaternion form, constant or free
spin, laminar/turbulent viscous torque, Eq. 39, thesis friction with the rig's
Eq. (61) arm or Appendix A's flight arm, algebraic regularisation, constant
mu_s), so that combination has its own kernel, :func:`thesis_rates`, used by
the scalar integrators (through ``rhs``) and by the batched lanes alike. The slip-speed
laws of mu (weakening, strengthening: :class:`obturator.model.torques.SlipSpeedLaw`,
the validation study's candidates) have a variant each, compiled apart
(``KERNEL_THESIS_WEAKENING``, ``KERNEL_THESIS_STRENGTHENING``), so the constant mu_s
pays nothing for them:

* both torques are collinear with omega_r (viscous -k omega_r, friction
  -M ARM s(x) omega_r/|omega_r|), so G = -c omega_r with one coefficient c,
  and in body axes G = -c (w - omega_p R^T Z): no back-rotation;
* friction as M ARM / (delta sqrt(1 + x^2)) with x = |omega_r|/delta (the
  algebraic family's s(x)/|omega_r|), written as
  M sqrt(P / (|omega_r|^2 (delta^2 + |omega_r|^2))) with ARM^2 |omega_r|^2 = P =
  b_X w_X^2 + w_Y^2 + b_Z w_Z^2 (b = 1 - the arm coefficients): one square root
  and one division where the textbook form takes four and two, and no
  cancellation in ARM^2 = 1 - u_X^2 near the arm's minimum; at omega_r = 0 it
  is M / delta (ARM = 1, as the textbook form's limit with 0/0 taken as 0), and at
  zero width (the set-valued solver's slip phases, delta = 0) 0, as the generic law;
* reciprocals 1/A, 1/C, 1/I_p, delta^2 and the arm coefficients precomputed
  once per case (:func:`specialise`, slots ``P_DERIVED``); the turbulent
  |omega_r|^0.75 as sqrt(x) sqrt(sqrt(x)) (vectorises; pow does not), and only
  where asked (``turbulent``): the lanes evaluate the laminar branch, whose
  Reynolds number the rig and flight cases of Table 1 never leave (transition
  at ~5.7e4 rad/s of slip), and redo a batch with it only when a lane crossed;
* measured on 16 lanes (AVX2): 4.3 ns per lane and evaluation, against 8.0 ns with
  the textbook form (five square roots and three divisions);
* a slip-speed law multiplies M by mu(v)/mu_s at v = R_s |omega_r|
  (:func:`~obturator.core.thesis_law.slip_speed_factor`, one more square root);
  measured on the 54 spin-rig runs at the validation tolerances (2-vCPU Zen 4, the
  fitted values of ``obturator validate``), one evaluation of the strengthening model
  took 25 ms in this kernel against 56 ms in the generic code, of the weakening
  (Stribeck) model 131 ms against 188 ms (its exp does not vectorise, and most of its
  runs are stiff; ``python -m benchmarks.speed_law_kernel`` compares the two on the
  same points in one run);
* no fast-math (:mod:`obturator.core.jit_flags`: every operation rounded as written)
  and the NumPy error model (a division never raises), so that loops over lanes
  vectorise.

The law itself (viscous coefficient, arm weights, regularisation, slip-speed factor)
is not written here: the kernel and the generic code take it from
:mod:`obturator.core.thesis_law` (``tests/core/test_thesis_law.py`` edits it there and
sees every path move). The kernel agrees with the generic right-hand side to rounding
(``tests/core/test_lanes.py`` checks 1e-12 relative on random states, every variant)
and is chosen by :func:`specialise` only where it applies; everything else keeps the
generic code (``P_KERNEL = KERNEL_GENERIC``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .jit_cache import configure_cache
from .jit_flags import NO_REFCOUNT
from .layout import (
    FAMILY_ALGEBRAIC,
    FORM_QUATERNION,
    FRIC_NONE,
    FRIC_THESIS_FLIGHT,
    FRIC_THESIS_RIG,
    KERNEL_GENERIC,
    KERNEL_THESIS,
    KERNEL_THESIS_STRENGTHENING,
    KERNEL_THESIS_WEAKENING,
    P_A,
    P_C,
    P_DERIVED,
    P_FAMILY,
    P_FORM,
    P_FRIC,
    P_IP,
    P_KERNEL,
    P_SPEED,
    P_SPIN_MODE,
    P_VISC,
    P_WIDTH,
    SPEED_CONSTANT,
    SPEED_STRENGTHENING,
    SPEED_WEAKENING,
    SPIN_CONSTANT,
    SPIN_FREE,
    VISC_NONE,
)
from .thesis_law import (
    algebraic_spread_sq,
    arm_slip_sq,
    arm_weights,
    slip_speed_factor,
    viscous_coefficient,
)

configure_cache()

__all__ = ["specialise", "thesis_rates", "rhs_thesis"]

# offsets in the P_DERIVED block
_INV_A, _INV_C, _C_MINUS_A, _FREE_INV_IP, _MOMENT, _DELTA_SQ, _ARM_BX, _ARM_BZ = range(8)


def specialise(p: np.ndarray, zero_width: bool = False) -> np.ndarray:
    """Choose the kernel of a packed parameter vector and fill its derived slots (in place).

    Parameters
    ----------
    p : ndarray
        Packed parameters (:mod:`obturator.core.layout`), model slots filled.

    Returns
    -------
    ndarray
        `p`, with ``p[P_KERNEL]`` = ``KERNEL_THESIS`` where the thesis kernel
        applies (quaternion form, constant or free spin, viscous torque or
        none, thesis friction or none, algebraic family, delta > 0), its
        ``KERNEL_THESIS_WEAKENING`` or ``KERNEL_THESIS_STRENGTHENING`` variant
        for thesis friction with a slip-speed law of mu, else ``KERNEL_GENERIC``.
    zero_width : bool
        Take delta = 0 too: the law at full magnitude, for the set-valued solver,
        whose slip phases never reach zero slip (there the kernel, like the generic
        law, exerts no friction). Its slip phases are then ~18 % faster than on the
        generic code (rig, 78 and 150 rad/s, rtol 1e-9; t_cr within 6e-10).
    """
    fric = p[P_FRIC]
    ok = (
        p[P_FORM] == FORM_QUATERNION
        and p[P_SPIN_MODE] in (SPIN_CONSTANT, SPIN_FREE)
        and fric in (FRIC_NONE, FRIC_THESIS_RIG, FRIC_THESIS_FLIGHT)
        and (fric == FRIC_NONE or p[P_FAMILY] == FAMILY_ALGEBRAIC)
        and (p[P_WIDTH] > 0.0 or zero_width)
    )
    d = P_DERIVED
    p[d : d + 8] = 0.0
    speed = p[P_SPEED] if fric != FRIC_NONE else SPEED_CONSTANT
    p[P_KERNEL] = _KERNEL_OF_SPEED_LAW[speed] if ok else KERNEL_GENERIC
    if not ok:
        return p
    p[d + _INV_A] = 1.0 / p[P_A]
    p[d + _INV_C] = 1.0 / p[P_C]
    p[d + _C_MINUS_A] = p[P_C] - p[P_A]
    p[d + _FREE_INV_IP] = 1.0 / p[P_IP] if p[P_SPIN_MODE] == SPIN_FREE else 0.0
    p[d + _DELTA_SQ] = p[P_WIDTH] * p[P_WIDTH]
    # b_X, b_Z: arm^2 |omega_r|^2 = b_X w_X^2 + w_Y^2 + b_Z w_Z^2 (rig Eq. 61, flight
    # Appendix A), the law's own function run as Python (same floats as compiled)
    p[d + _ARM_BX], p[d + _ARM_BZ] = arm_weights.py_func(fric, p[P_FRIC + 3])
    if fric != FRIC_NONE:
        p[d + _MOMENT] = p[P_FRIC + 1]
    if p[P_VISC] == VISC_NONE:
        p[P_VISC + 1 : P_VISC + 4] = (0.0, 0.0, math.inf)
    return p


_KERNEL_OF_SPEED_LAW = {
    SPEED_CONSTANT: KERNEL_THESIS,
    SPEED_WEAKENING: KERNEL_THESIS_WEAKENING,
    SPEED_STRENGTHENING: KERNEL_THESIS_STRENGTHENING,
}

#: Below this |omega_r|^2 [rad^2/s^2] the slip direction is taken as undefined (the
#: friction coefficient's limit M / delta; at zero width no friction, as the generic
#: law at omega_r = 0): the form M sqrt(P / (|w|^2 (delta^2 + |w|^2))) would underflow
#: to 0/0 near 1e-300, and the torque c omega_r is < 1e-120 N m here.
_SLIP_SQ_MIN = 1e-250


@njit(cache=True, fastmath=False, error_model="numpy", inline="always", **NO_REFCOUNT)
def thesis_rates(q0, q1, q2, q3, w1, w2, w3, wp, coef, turbulent, speed):
    """Time derivative of one quaternion-form state under the thesis torques.

    Parameters
    ----------
    q0, q1, q2, q3, w1, w2, w3, wp : float
        State (attitude quaternion, body rates [rad/s], spin omega_p [rad/s]).
    coef : tuple of float
        (S, K_turb, omega_transition, 1/A, 1/C, C - A, 1/I_p or 0, M, delta^2,
        b_X, b_Z, r, R_s [m], v_s [m/s]): the viscous slots, the derived block of
        ``p``, the slip-speed law's ratio and speed and the ball radius.
    turbulent : bool
        Evaluate the turbulent branch of Eq. (39) where |omega_r| reaches the
        transition; with False the laminar coefficient S is used throughout (the
        last output says whether that was wrong).
    speed : int
        Slip-speed law code (``SPEED_CONSTANT``: the thesis's mu_s; callers pass a
        constant, so each law compiles to its own code).

    Returns
    -------
    tuple
        The eight derivatives (quaternion rates, body angular accelerations
        [rad/s^2] from Euler's equations, thesis Eqs. 5a-5c, spin acceleration),
        then whether |omega_r| is at or above the turbulent transition.
    """
    visc_s, visc_k, visc_w, inv_a, inv_c, cma, free_inv_ip, moment, delta_sq, b_x, b_z = coef[:11]
    s = 2.0 / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)  # rotation from q / |q|
    r00 = 1.0 - s * (q2 * q2 + q3 * q3)
    r01 = s * (q1 * q2 - q0 * q3)
    r02 = s * (q1 * q3 + q0 * q2)
    r10 = s * (q1 * q2 + q0 * q3)
    r11 = 1.0 - s * (q1 * q1 + q3 * q3)
    r12 = s * (q2 * q3 - q0 * q1)
    r20 = s * (q1 * q3 - q0 * q2)
    r21 = s * (q2 * q3 + q0 * q1)
    r22 = 1.0 - s * (q1 * q1 + q2 * q2)
    wx = r00 * w1 + r01 * w2 + r02 * w3  # omega_r in inertial axes
    wy = r10 * w1 + r11 * w2 + r12 * w3
    wz = r20 * w1 + r21 * w2 + r22 * w3 - wp
    wx2, wy2, wz2 = wx * wx, wy * wy, wz * wz
    wn2 = wx2 + wy2 + wz2
    k, above = viscous_coefficient(wn2, visc_s, visc_k, visc_w, turbulent)  # Eqs. 39, 41
    # friction M ARM s(x) / |omega_r| = M sqrt(ARM^2 |w|^2 / (|w|^2 (delta^2 + |w|^2)))
    if wn2 > _SLIP_SQ_MIN:
        num = arm_slip_sq(wx2, wy2, wz2, b_x, b_z)
        den = wn2 * algebraic_spread_sq(wn2, delta_sq)
    elif delta_sq > 0.0:  # the regularised law's limit M / delta
        num, den = 1.0, delta_sq
    else:  # zero width (set-valued solver): no friction at zero slip, as the generic law
        num, den = 0.0, 1.0
    if speed != SPEED_CONSTANT:  # mu(v) at the slip speed v = R_s |omega_r|
        ratio, radius, v_ref = coef[11:]
        moment = moment * slip_speed_factor(math.sqrt(wn2) * radius, speed, ratio, v_ref)
    c = k + moment * math.sqrt(num / den)
    # G = -c omega_r; in body axes -c (w - omega_p R^T Z)
    g1 = -c * (w1 - wp * r20)
    g2 = -c * (w2 - wp * r21)
    g3 = -c * (w3 - wp * r22)
    return (
        0.5 * (-q1 * w1 - q2 * w2 - q3 * w3),
        0.5 * (q0 * w1 + q2 * w3 - q3 * w2),
        0.5 * (q0 * w2 + q3 * w1 - q1 * w3),
        0.5 * (q0 * w3 + q1 * w2 - q2 * w1),
        (g1 - cma * w2 * w3) * inv_a,
        (g2 + cma * w1 * w3) * inv_a,
        g3 * inv_c,
        c * wz * free_inv_ip,  # I_p omega_p_dot = -G_Z (free spin), else 0
        above,
    )


@njit(cache=True, fastmath=False, error_model="numpy", **NO_REFCOUNT)
def rhs_thesis(y, p, dy) -> None:
    """:func:`thesis_rates` of one state `y` into `dy` (the scalar path's kernel), in the
    variant of ``p[P_KERNEL]``."""
    kernel = p[P_KERNEL]
    if kernel == KERNEL_THESIS:
        _rates_into(y, p, dy, SPEED_CONSTANT)
    elif kernel == KERNEL_THESIS_STRENGTHENING:
        _rates_into(y, p, dy, SPEED_STRENGTHENING)
    else:
        _rates_into(y, p, dy, SPEED_WEAKENING)


@njit(cache=True, fastmath=False, error_model="numpy", inline="always", **NO_REFCOUNT)
def _rates_into(y, p, dy, speed) -> None:
    d = P_DERIVED
    c = (
        p[P_VISC + 1],
        p[P_VISC + 2],
        p[P_VISC + 3],
        p[d + _INV_A],
        p[d + _INV_C],
        p[d + _C_MINUS_A],
        p[d + _FREE_INV_IP],
        p[d + _MOMENT],
        p[d + _DELTA_SQ],
        p[d + _ARM_BX],
        p[d + _ARM_BZ],
        p[P_SPEED + 1],
        p[P_FRIC + 2],
        p[P_SPEED + 2],
    )
    r0, r1, r2, r3, r4, r5, r6, r7, _ = thesis_rates(
        y[0], y[1], y[2], y[3], y[4], y[5], y[6], y[7], c, True, speed
    )
    dy[0], dy[1], dy[2], dy[3], dy[4], dy[5], dy[6], dy[7] = r0, r1, r2, r3, r4, r5, r6, r7
