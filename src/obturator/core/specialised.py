"""The specialised right-hand side: the thesis's torque model without branching on codes.

The generic :func:`obturator.core.dynamics.rhs` reads model codes from ``p`` on
every call and dispatches (formulation, spin mode, viscous branch, friction law,
regularisation family, slip-speed law). Sweeps and fits spend almost all of
their time in one combination, the thesis's (quaternion form, constant or free
spin, laminar/turbulent viscous torque, Eq. 39, thesis friction with the rig's
Eq. (61) arm or Appendix A's flight arm, algebraic regularisation, constant
mu_s), so that combination has its own kernel, :func:`thesis_rates`, used by
the scalar integrators (through ``rhs``) and by the batched lanes alike:

* both torques are collinear with omega_r (viscous -k omega_r, friction
  -M ARM s(x) omega_r/|omega_r|), so G = -c omega_r with one coefficient c,
  and in body axes G = -c (w - omega_p R^T Z): no back-rotation;
* friction as M ARM delta^-1 / sqrt(1 + x^2) with x = |omega_r|/delta (the
  algebraic family's s(x)/|omega_r|), which has no 0/0 at omega_r = 0;
* reciprocals 1/A, 1/C, 1/delta, 1/I_p and the arm coefficients precomputed
  once per case (:func:`specialise`, slots ``P_DERIVED``); the turbulent
  |omega_r|^0.75 as sqrt(x) sqrt(sqrt(x)) (vectorises; pow does not);
* FMA contraction allowed (``fastmath={"contract"}``) and the NumPy error
  model (a division never raises), so that loops over lanes vectorise.

The kernel agrees with the generic right-hand side to rounding
(``tests/test_lanes.py`` checks 1e-12 relative on random states) and is
chosen by :func:`specialise` only where it applies; everything else keeps the
generic code (``P_KERNEL = KERNEL_GENERIC``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .jit_cache import configure_cache
from .layout import (
    FAMILY_ALGEBRAIC,
    FORM_QUATERNION,
    FRIC_NONE,
    FRIC_THESIS_FLIGHT,
    FRIC_THESIS_RIG,
    KERNEL_GENERIC,
    KERNEL_THESIS,
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
    SPIN_CONSTANT,
    SPIN_FREE,
    VISC_NONE,
)

configure_cache()

__all__ = ["specialise", "thesis_rates", "rhs_thesis"]

# offsets in the P_DERIVED block
_INV_A, _INV_C, _C_MINUS_A, _FREE_INV_IP, _MOMENT, _INV_DELTA, _ARM_X, _ARM_Z = range(8)


def specialise(p: np.ndarray) -> np.ndarray:
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
        none, thesis friction or none, algebraic family, constant mu_s,
        delta > 0), else ``KERNEL_GENERIC``.
    """
    fric = p[P_FRIC]
    ok = (
        p[P_FORM] == FORM_QUATERNION
        and p[P_SPIN_MODE] in (SPIN_CONSTANT, SPIN_FREE)
        and fric in (FRIC_NONE, FRIC_THESIS_RIG, FRIC_THESIS_FLIGHT)
        and (
            fric == FRIC_NONE or (p[P_FAMILY] == FAMILY_ALGEBRAIC and p[P_SPEED] == SPEED_CONSTANT)
        )
        and p[P_WIDTH] > 0.0
    )
    d = P_DERIVED
    p[d : d + 8] = 0.0
    p[P_KERNEL] = KERNEL_THESIS if ok else KERNEL_GENERIC
    if not ok:
        return p
    p[d + _INV_A] = 1.0 / p[P_A]
    p[d + _INV_C] = 1.0 / p[P_C]
    p[d + _C_MINUS_A] = p[P_C] - p[P_A]
    p[d + _FREE_INV_IP] = 1.0 / p[P_IP] if p[P_SPIN_MODE] == SPIN_FREE else 0.0
    p[d + _INV_DELTA] = 1.0 / p[P_WIDTH]
    if fric != FRIC_NONE:
        p[d + _MOMENT] = p[P_FRIC + 1]
        if fric == FRIC_THESIS_RIG:  # Eq. (61): arm^2 = 1 - u_X^2
            p[d + _ARM_X] = 1.0
        else:  # Appendix A: arm^2 = 1 - sin^2(beta) u_X^2 - cos^2(beta) u_Z^2
            sb, cb = math.sin(p[P_FRIC + 3]), math.cos(p[P_FRIC + 3])
            p[d + _ARM_X] = sb * sb
            p[d + _ARM_Z] = cb * cb
    if p[P_VISC] == VISC_NONE:
        p[P_VISC + 1 : P_VISC + 4] = (0.0, 0.0, math.inf)
    return p


@njit(cache=True, fastmath={"contract"}, error_model="numpy", inline="always")
def thesis_rates(q0, q1, q2, q3, w1, w2, w3, wp, coef):
    """Time derivative of one quaternion-form state under the thesis torques.

    Parameters
    ----------
    q0, q1, q2, q3, w1, w2, w3, wp : float
        State (attitude quaternion, body rates [rad/s], spin omega_p [rad/s]).
    coef : tuple of float
        (S, K_turb, omega_transition, 1/A, 1/C, C - A, 1/I_p or 0, M, 1/delta,
        a_X, a_Z): the viscous slots and the derived block of ``p``.

    Returns
    -------
    tuple of float
        The eight derivatives (quaternion rates, body angular accelerations
        [rad/s^2] from Euler's equations, thesis Eqs. 5a-5c, spin acceleration).
    """
    visc_s, visc_k, visc_w, inv_a, inv_c, cma, free_inv_ip, moment, inv_delta, arm_x, arm_z = coef
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
    wn2 = wx * wx + wy * wy + wz * wz
    wn = math.sqrt(wn2)
    rw = math.sqrt(wn)
    k = visc_k * (rw * math.sqrt(rw)) if wn >= visc_w else visc_s  # Eq. (39) branch
    inv_wn2 = 1.0 / wn2 if wn2 > 0.0 else 0.0
    arm2 = 1.0 - (arm_x * wx * wx + arm_z * wz * wz) * inv_wn2
    arm = math.sqrt(arm2) if arm2 > 0.0 else 0.0
    x = wn * inv_delta
    c = k + moment * arm * inv_delta / math.sqrt(1.0 + x * x)
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
    )


@njit(cache=True, fastmath={"contract"}, error_model="numpy")
def rhs_thesis(y, p, dy) -> None:
    """:func:`thesis_rates` of one state `y` into `dy` (the scalar path's kernel)."""
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
        p[d + _INV_DELTA],
        p[d + _ARM_X],
        p[d + _ARM_Z],
    )
    r = thesis_rates(y[0], y[1], y[2], y[3], y[4], y[5], y[6], y[7], c)
    for i in range(8):
        dy[i] = r[i]
