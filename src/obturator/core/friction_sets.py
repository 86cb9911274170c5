"""The stick mode of the thesis friction laws: admissible set, reaction, rigid motion.

The thesis law (rig Eq. 61, flight Appendix A; inertial axes X, Y, Z) exerts, while
the ball slips at omega_r = |omega_r| u, the moment G_f = -M ARM(u) u with
ARM(u)^2 = b_X u_X^2 + u_Y^2 + b_Z u_Z^2 (rig: b_X = 0, b_Z = 1; flight:
b_X = cos^2 beta, b_Z = sin^2 beta, Appendix A's
ARM = sqrt(1 - sin^2 beta u_X^2 - cos^2 beta u_Z^2) rewritten with |u| = 1). At
zero slip the law is set-valued: its admissible moments are the limit set of the
true-direction law,

    F = {-s M ARM(u) u : |u| = 1, 0 <= s <= 1},

the star-shaped set whose radius in direction u is M ARM(u) (``docs/stick_slip.md``).
On the rig it is the horn torus G_X^2 + rho^2 <= M rho, rho = sqrt(G_Y^2 + G_Z^2): not
convex, and it holds no moment about the gravity axis X without one about Y or Z.

In stick (omega_r = 0) the ball turns rigidly with the socket at omega_p about Z, so
its attitude is a rotation about Z and its body rates are constant; Euler's equation
(thesis Eqs. 5a-5c, inertial form I dw/dt + w x I w = G with w = omega_p Z constant)
gives the reaction the friction must supply,

    G_req = omega_p^2 Z x (I Z) = omega_p^2 (C - A) z_Z (Z x z),

with z the hole axis; viscous torque vanishes at zero slip (Eq. 42). G_req lies in the
X-Y plane (so a free projectile's spin does not change in stick either:
I_p omega_p' = -G_Z = 0) and turns with the ball at omega_p, so stick is kept while
G_req is in F and ends when |cos(psi)| falls to the closed-form level of
:func:`breakaway_angle` (psi the azimuth of z about Z).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .jit_cache import configure_cache
from .jit_flags import NO_REFCOUNT
from .layout import FRIC_THESIS_FLIGHT, FRIC_THESIS_RIG, P_A, P_C, P_FRIC

configure_cache()

__all__ = [
    "arm_coefficients",
    "required_reaction",
    "stick_margin",
    "breakaway_angle",
    "hold_stick",
    "turn_rigidly",
    "turn_by",
    "relative_rate",
]


@njit(cache=True, **NO_REFCOUNT, fastmath={"contract"}, error_model="python")
def arm_coefficients(p: np.ndarray) -> tuple[float, float]:
    """(b_X, b_Z) of ARM(u)^2 = b_X u_X^2 + u_Y^2 + b_Z u_Z^2 (rig Eq. 61; Appendix A)."""
    if p[P_FRIC] == FRIC_THESIS_FLIGHT:
        sb = math.sin(p[P_FRIC + 3])
        cb = math.cos(p[P_FRIC + 3])
        return cb * cb, sb * sb
    if p[P_FRIC] == FRIC_THESIS_RIG:
        return 0.0, 1.0
    return 1.0, 1.0  # no friction: the set is {0}; never used with stick


@njit(cache=True, **NO_REFCOUNT, fastmath={"contract"}, error_model="python")
def _hole_axis(y: np.ndarray) -> tuple[float, float, float]:
    """Hole axis z in inertial axes: third column of R(q / |q|)."""
    q0, q1, q2, q3 = y[0], y[1], y[2], y[3]
    s = 2.0 / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    return s * (q1 * q3 + q0 * q2), s * (q2 * q3 - q0 * q1), 1.0 - s * (q1 * q1 + q2 * q2)


@njit(cache=True, **NO_REFCOUNT, fastmath={"contract"}, error_model="python")
def required_reaction(y: np.ndarray, p: np.ndarray, wp: float) -> tuple[float, float, float]:
    """Friction moment [N m] (inertial axes) that keeps omega_r = 0 at state `y`.

    G_req = omega_p^2 (C - A) z_Z (Z x z), from Euler's equations (Eqs. 5a-5c) with the
    ball turning rigidly at omega_p = `wp` [rad/s] about Z.
    """
    zx, zy, zz = _hole_axis(y)
    g = wp * wp * (p[P_C] - p[P_A]) * zz
    return -g * zy, g * zx, 0.0


@njit(cache=True, **NO_REFCOUNT, fastmath={"contract"}, error_model="python")
def stick_margin(gx: float, gy: float, gz: float, p: np.ndarray) -> float:
    """M ARM(u) - |G| [N m] for the moment G with u = -G / |G|: > 0 inside F.

    ARM is even in u, so the radius of F along G is M ARM(G / |G|).
    """
    g = math.sqrt(gx * gx + gy * gy + gz * gz)
    m = p[P_FRIC + 1]
    if g == 0.0:
        return m
    b_x, b_z = arm_coefficients(p)
    arm2 = (b_x * gx * gx + gy * gy + b_z * gz * gz) / (g * g)
    return m * math.sqrt(max(arm2, 0.0)) - g


@njit(cache=True, **NO_REFCOUNT, fastmath={"contract"}, error_model="python")
def breakaway_angle(y: np.ndarray, p: np.ndarray, wp: float) -> float:
    """Rotation angle [rad] of rigid stick from `y` after which G_req leaves F.

    With G_req = g (-z_Y, z_X, 0), |G_req| = |g| sin(theta) and z_X = sin(theta) cos(psi),
    G_req is in F while b_X sin^2 psi + cos^2 psi >= kappa^2, kappa = |g| sin(theta) / M,
    i.e. while cos^2 psi >= c^2 = (kappa^2 - b_X) / (1 - b_X). Returns inf when stick is
    never lost (c^2 < 0, or theta = 0 / 90 deg exactly), 0 when G_req is outside F
    everywhere, and minus the angle to the end of the window when `y` is in one.
    """
    zx, zy, zz = _hole_axis(y)
    sin_th = math.sqrt(zx * zx + zy * zy)
    g = abs(wp * wp * (p[P_C] - p[P_A]) * zz)
    kappa = g * sin_th / p[P_FRIC + 1]
    b_x, _ = arm_coefficients(p)
    if kappa == 0.0 or b_x >= 1.0:
        return math.inf
    c2 = (kappa * kappa - b_x) / (1.0 - b_x)
    if c2 < 0.0:
        return math.inf
    if c2 >= 1.0:
        return 0.0
    psi1 = math.acos(math.sqrt(c2))  # |cos psi| = c at psi1 and pi - psi1 (mod pi)
    psi = math.atan2(zy, zx)
    if wp < 0.0:  # the azimuth decreases: mirror (|cos| is even)
        psi = -psi
    psi = psi % math.pi
    if psi <= psi1:
        return psi1 - psi
    if psi >= math.pi - psi1:
        return math.pi - psi + psi1
    return -(math.pi - psi1 - psi)  # inside the window: minus the angle to its end


@njit(cache=True, **NO_REFCOUNT, fastmath={"contract"}, error_model="python")
def relative_rate(y: np.ndarray, wp: float) -> tuple[float, float, float]:
    """omega_r = R w - omega_p Z in inertial axes [rad/s] (Eqs. 35-36, 69)."""
    q0, q1, q2, q3 = y[0], y[1], y[2], y[3]
    w1, w2, w3 = y[4], y[5], y[6]
    s = 2.0 / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    wx = (1.0 - s * (q2 * q2 + q3 * q3)) * w1 + s * (q1 * q2 - q0 * q3) * w2
    wx += s * (q1 * q3 + q0 * q2) * w3
    wy = s * (q1 * q2 + q0 * q3) * w1 + (1.0 - s * (q1 * q1 + q3 * q3)) * w2
    wy += s * (q2 * q3 - q0 * q1) * w3
    wz = s * (q1 * q3 - q0 * q2) * w1 + s * (q2 * q3 + q0 * q1) * w2
    wz += (1.0 - s * (q1 * q1 + q2 * q2)) * w3 - wp
    return wx, wy, wz


@njit(cache=True, **NO_REFCOUNT, fastmath={"contract"}, error_model="python")
def hold_stick(y: np.ndarray, wp: float) -> None:
    """Set omega_r = 0 in place: body rates w = omega_p R^T Z, |q| = 1."""
    n = math.sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3])
    for i in range(4):
        y[i] /= n
    zz = _hole_axis(y)[2]
    q0, q1, q2, q3 = y[0], y[1], y[2], y[3]
    # R^T Z = third row of R
    y[4] = wp * 2.0 * (q1 * q3 - q0 * q2)
    y[5] = wp * 2.0 * (q2 * q3 + q0 * q1)
    y[6] = wp * zz


@njit(cache=True, **NO_REFCOUNT, fastmath={"contract"}, error_model="python")
def turn_by(y: np.ndarray, vx: float, vy: float, vz: float) -> None:
    """Turn the attitude of `y` in place by the inertial rotation vector v [rad]."""
    a = math.sqrt(vx * vx + vy * vy + vz * vz)
    if a == 0.0:
        return
    c = math.cos(0.5 * a)
    s = math.sin(0.5 * a) / a
    ax, ay, az = s * vx, s * vy, s * vz
    q0, q1, q2, q3 = y[0], y[1], y[2], y[3]
    y[0] = c * q0 - ax * q1 - ay * q2 - az * q3
    y[1] = c * q1 + q0 * ax + ay * q3 - az * q2
    y[2] = c * q2 + q0 * ay + az * q1 - ax * q3
    y[3] = c * q3 + q0 * az + ax * q2 - ay * q1


@njit(cache=True, **NO_REFCOUNT, fastmath={"contract"}, error_model="python")
def turn_rigidly(y: np.ndarray, angle: float, out: np.ndarray) -> None:
    """`out` = `y` turned by `angle` [rad] about Z (q <- q_Z(angle) q; body rates kept)."""
    c = math.cos(0.5 * angle)
    s = math.sin(0.5 * angle)
    q0, q1, q2, q3 = y[0], y[1], y[2], y[3]
    out[0] = c * q0 - s * q3
    out[1] = c * q1 - s * q2
    out[2] = c * q2 + s * q1
    out[3] = c * q3 + s * q0
    for i in range(4, y.shape[0]):
        out[i] = y[i]
