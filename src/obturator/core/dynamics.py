"""Equations of motion of the ball: state, right-hand sides, events.

Everything here is plain-float numba code over a flat parameter vector, so the
hot path compiles once (cached on disk) and runs without Python in the loop.

Two formulations of Euler's equations for an axisymmetric body about its fixed
centre (thesis Eqs. 5a-5c) are provided:

* ``quaternion`` (main path, singularity-free): state
  ``[q0, q1, q2, q3, w1, w2, w3, omega_p]`` with the attitude quaternion q
  (body -> inertial) and the body rates w_i about the principal axes (z along
  the hole). The rotation matrix is built from q/|q|, so a drift of |q| never
  enters the physics.
* ``euler`` (the thesis's form, Eqs. 13-17; cross-check): state
  ``[theta, theta_dot, psi, psi_dot, phi, phi_dot, omega_p, 0]`` with z-x-z
  Euler angles (Fig. 7). Eq. (17) divides by sin(theta) and is singular at
  theta = 0; the thesis's printed right-hand side is garbled, so it is
  re-derived here from Eqs. (5), (13), (14).

The projectile spins about the inertial Z axis at omega_p. Its spin is either
held constant (driven rig), free with the total axial angular momentum
conserved (I_p omega_p_dot = -G_Z), or recomputed from the thesis's energy
balance (Appendix A: "conservation of kinetic energy", labelled as the
thesis's; it is not conserved with friction).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .jit_cache import configure_cache
from .jit_flags import NO_REFCOUNT, REFCOUNT
from .layout import (
    FAMILY_LINEAR,
    FAMILY_TANH,
    FORM_EULER,
    FORM_QUATERNION,
    FRIC_NONE,
    FRIC_THESIS_FLIGHT,
    FRIC_THESIS_RIG,
    KERNEL_GENERIC,
    P_A,
    P_C,
    P_FAMILY,
    P_FORM,
    P_FRIC,
    P_IP,
    P_KE0,
    P_KERNEL,
    P_SPEED,
    P_SPIN_MODE,
    P_VISC,
    P_WIDTH,
    SPEED_CONSTANT,
    SPIN_FREE,
    SPIN_THESIS_ENERGY,
)
from .specialised import rhs_thesis
from .thesis_law import (
    algebraic_spread_sq,
    arm_slip_sq,
    arm_weights,
    slip_speed_factor,
    viscous_coefficient,
)

configure_cache()  # before any @njit(cache=True) below or in the integrators

__all__ = [
    "applied_torque",
    "slip_saturation",
    "friction_speed_factor",
    "rhs",
    "nutation_angle_of_state",
    "observables",
]


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def slip_saturation(x: float, family: float) -> float:
    """Regularised magnitude factor s(x) of a Coulomb term, x = |slip| / width [-].

    Every family rises from s(0) = 0 to s -> 1 for x >> 1, so as the width
    shrinks each converges to the set-valued law's magnitude (1 while slipping,
    anything in [0, 1] at stick). They differ in shape, which is the point of
    having several: a t_cr that is the same for all of them is a property of
    the set-valued law, not of one smoothing.

    Parameters
    ----------
    x : float
        Slip magnitude over the regularisation width, >= 0 [-].
    family : float
        ``FAMILY_ALGEBRAIC`` x/sqrt(1 + x^2), ``FAMILY_TANH`` tanh(x) or
        ``FAMILY_LINEAR`` min(x, 1) (linear saturation).
    """
    if family == FAMILY_TANH:
        return math.tanh(x)
    if family == FAMILY_LINEAR:
        return x if x < 1.0 else 1.0
    if x > 1e150:  # zero width (x = inf): the unregularised law
        return 1.0
    return x / math.sqrt(algebraic_spread_sq(x * x, 1.0))


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def friction_speed_factor(v: float, code: float, ratio: float, speed: float) -> float:
    """mu(v) / mu_s for a slip speed v [m/s]: the law of
    :func:`obturator.core.thesis_law.slip_speed_factor`, as a function of its own (the
    generic code calls it; the specialised kernel inlines the law)."""
    return slip_speed_factor(v, code, ratio, speed)


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def applied_torque(wx: float, wy: float, wz: float, p: np.ndarray) -> tuple[float, float, float]:
    """Total torque on the ball in inertial axes [N m] (thesis Eqs. 62-64).

    Parameters
    ----------
    wx, wy, wz : float
        Relative angular velocity omega_r in inertial axes [rad/s].
    p : ndarray
        Packed parameters.

    Returns
    -------
    tuple of float
        (G_X, G_Y, G_Z) [N m].

    Notes
    -----
    The thesis's viscous coefficient and moment arm come from
    :mod:`obturator.core.thesis_law`, as in the specialised kernel.

    Thesis friction laws (rig Eq. 61, flight Appendix A): the moment arm is a
    function of the *true* slip direction u = omega_r/|omega_r|, as Appendix A
    computes it (``ARM = SQRT(1.-C(1)*(OMXR/OMR)**2-...)``); only the magnitude
    is regularised, G_f = -M ARM(u) s(|omega_r|/delta) u with s one of the
    :func:`slip_saturation` families and delta = ``p[P_WIDTH]`` [rad/s]. At
    omega_r = 0 exactly the friction torque is zero. The limit delta -> 0 is
    the set-valued law whose stick set is {-M s ARM(u) u : |u| = 1, 0 <= s <= 1}
    (every torque the law can exert in some slip direction, scaled down): on
    the rig ARM = 0 along X, so no torque about the gravity axis X can be held
    by the single bottom contact, in slip or at stick. Regularising the
    direction instead (omega_r/sqrt(|omega_r|^2 + delta^2) inside ARM) would
    give the near-stick ball an arm close to 1 in every direction, a different
    limit.

    Coulomb contacts (Contensou-type sliding + pivoting, elliptic form of Leine
    and Glocker 2003): at contact k (point P_k, unit normal n_k = P_k/R_s, load
    N_k) the generalised slip is g = sqrt(|v_k|^2 + (eps w_n)^2) with
    v_k = omega_r x P_k, w_n = omega_r . n_k and eps the pivot arm of the
    patch ``p[P_FRIC + 5]`` [m]; friction force -mu N_k s v_k/g and pivot
    torque -mu N_k s eps^2 w_n/g n_k with s = s(g/(delta R_s)). The dissipation
    mu N_k g is a norm of omega_r when eps > 0 (a well-posed, monotone law);
    eps = 0 is the point contact, which holds no torque about n_k.
    """
    tx = 0.0
    ty = 0.0
    tz = 0.0
    wx2, wy2, wz2 = wx * wx, wy * wy, wz * wz
    wn2 = wx2 + wy2 + wz2
    wn = math.sqrt(wn2)
    if p[P_VISC] != 0.0:  # Eqs. (39), (41), (42) (obturator.core.thesis_law)
        k, _ = viscous_coefficient(wn2, p[P_VISC + 1], p[P_VISC + 2], p[P_VISC + 3], True)
        tx -= k * wx
        ty -= k * wy
        tz -= k * wz
    code = p[P_FRIC]
    if code == FRIC_NONE:
        return tx, ty, tz
    m = p[P_FRIC + 1]
    delta = p[P_WIDTH]
    family = p[P_FAMILY]
    speed_code = p[P_SPEED]
    if code == FRIC_THESIS_RIG or code == FRIC_THESIS_FLIGHT:
        if wn == 0.0:
            return tx, ty, tz
        if speed_code != SPEED_CONSTANT:  # slip speed scale R_s |omega_r|
            m = m * friction_speed_factor(
                wn * p[P_FRIC + 2], speed_code, p[P_SPEED + 1], p[P_SPEED + 2]
            )
        # rig Eq. (61), flight Appendix A (obturator.core.thesis_law)
        b_x, b_z = arm_weights(code, p[P_FRIC + 3])
        arm2 = arm_slip_sq(wx2, wy2, wz2, b_x, b_z) / wn2
        arm = math.sqrt(arm2) if arm2 > 0.0 else 0.0
        f = m * arm * slip_saturation(wn / delta if delta > 0.0 else math.inf, family) / wn
        tx -= f * wx
        ty -= f * wy
        tz -= f * wz
        return tx, ty, tz
    # Coulomb contacts: F_k = -mu N_k s v_k/g, pivot -mu N_k s eps^2 w_n/g n_k;
    # G = sum P_k x F_k + pivot.
    r = p[P_FRIC + 2]
    beta = p[P_FRIC + 3]
    n = int(p[P_FRIC + 4])
    eps = p[P_FRIC + 5]
    rig = beta >= 0.5 * math.pi - 1e-12
    if rig and n == 1:
        # the rig's one contact P = -R_s X in closed form: v = R_s (0, -w_Z, w_Y),
        # w_n = -w_X, so G = -f (eps^2 w_X, R_s^2 w_Y, R_s^2 w_Z) (60 against 82 ns
        # through the loop below, which it agrees with to rounding)
        ex, ey, ez = eps * eps * wx, r * r * wy, r * r * wz
        g = math.sqrt(ey * wy + ez * wz + ex * wx)
        if g == 0.0:
            return tx, ty, tz
        x = g / (delta * r) if delta > 0.0 else math.inf
        f = m * slip_saturation(x, family) / g
        if speed_code != SPEED_CONSTANT:
            f *= friction_speed_factor(g, speed_code, p[P_SPEED + 1], p[P_SPEED + 2])
        return tx - f * ex, ty - f * ey, tz - f * ez
    # the polar angle's trig only off the rig, and none for the first contact (gam = 0,
    # cos and sin exactly 1 and 0)
    sb = 1.0 if rig else math.sin(beta)
    cb = 0.0 if rig else math.cos(beta)
    for k in range(n):
        gam = 2.0 * math.pi * k / n
        cg, sg = (1.0, 0.0) if k == 0 else (math.cos(gam), math.sin(gam))
        if rig:  # bottom of the socket, gravity along -X
            px, py, pz = -r * cg, -r * sg, 0.0
        else:
            px, py, pz = r * sb * cg, r * sb * sg, r * cb
        vx = wy * pz - wz * py
        vy = wz * px - wx * pz
        vz = wx * py - wy * px
        wnorm = (wx * px + wy * py + wz * pz) / r  # drilling rate about n_k
        g = math.sqrt(vx * vx + vy * vy + vz * vz + (eps * wnorm) ** 2)
        if g == 0.0:
            continue
        x = g / (delta * r) if delta > 0.0 else math.inf
        f = m * slip_saturation(x, family) / g
        if speed_code != SPEED_CONSTANT:
            f *= friction_speed_factor(g, speed_code, p[P_SPEED + 1], p[P_SPEED + 2])
        fx = -f * vx
        fy = -f * vy
        fz = -f * vz
        mp = -f * eps * eps * wnorm / r  # pivot torque along n_k = P_k / r
        tx += py * fz - pz * fy + mp * px
        ty += pz * fx - px * fz + mp * py
        tz += px * fy - py * fx + mp * pz
    return tx, ty, tz


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def _rotation_from_quaternion(y: np.ndarray) -> tuple:
    n = math.sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2] + y[3] * y[3])
    q0 = y[0] / n
    q1 = y[1] / n
    q2 = y[2] / n
    q3 = y[3] / n
    r00 = 1.0 - 2.0 * (q2 * q2 + q3 * q3)
    r01 = 2.0 * (q1 * q2 - q0 * q3)
    r02 = 2.0 * (q1 * q3 + q0 * q2)
    r10 = 2.0 * (q1 * q2 + q0 * q3)
    r11 = 1.0 - 2.0 * (q1 * q1 + q3 * q3)
    r12 = 2.0 * (q2 * q3 - q0 * q1)
    r20 = 2.0 * (q1 * q3 - q0 * q2)
    r21 = 2.0 * (q2 * q3 + q0 * q1)
    r22 = 1.0 - 2.0 * (q1 * q1 + q2 * q2)
    return r00, r01, r02, r10, r11, r12, r20, r21, r22


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def _rotation_from_euler(psi: float, theta: float, phi: float) -> tuple:
    # z-x-z: R = Rz(psi) Rx(theta) Rz(phi), body -> inertial (thesis Fig. 7, Appendix A)
    cps, sps = math.cos(psi), math.sin(psi)
    cth, sth = math.cos(theta), math.sin(theta)
    cph, sph = math.cos(phi), math.sin(phi)
    r00 = cph * cps - sph * cth * sps
    r01 = -sph * cps - cph * cth * sps
    r02 = sth * sps
    r10 = cph * sps + sph * cth * cps
    r11 = -sph * sps + cph * cth * cps
    r12 = -sth * cps
    r20 = sth * sph
    r21 = sth * cph
    r22 = cth
    return r00, r01, r02, r10, r11, r12, r20, r21, r22


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def _attitude_and_rates(y: np.ndarray, p: np.ndarray) -> tuple:
    """Rotation matrix entries and body rates (w1, w2, w3) of a state."""
    if p[P_FORM] == FORM_QUATERNION:
        r = _rotation_from_quaternion(y)
        return r, y[4], y[5], y[6]
    th, thd, ps, psd, ph, phd = y[0], y[1], y[2], y[3], y[4], y[5]
    r = _rotation_from_euler(ps, th, ph)
    sth, cth = math.sin(th), math.cos(th)
    sph, cph = math.sin(ph), math.cos(ph)
    w1 = psd * sth * sph + thd * cph  # Eq. (13a)
    w2 = psd * sth * cph - thd * sph  # Eq. (13b)
    w3 = phd + psd * cth  # Eq. (13c)
    return r, w1, w2, w3


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def _spin(y: np.ndarray, p: np.ndarray, w1: float, w2: float, w3: float) -> float:
    if p[P_SPIN_MODE] == SPIN_THESIS_ENERGY:
        # Appendix A: SPIN = SQRT((2 KE - A(w1^2 + w2^2) - C w3^2) / I_p)
        a = 2.0 * p[P_KE0] - p[P_A] * (w1 * w1 + w2 * w2) - p[P_C] * w3 * w3
        return math.sqrt(a / p[P_IP]) if a >= 0.0 else math.nan
    return y[6] if p[P_FORM] == FORM_EULER else y[7]


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def _torque_body(r: tuple, w1: float, w2: float, w3: float, wp: float, p: np.ndarray) -> tuple:
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = r
    wx = r00 * w1 + r01 * w2 + r02 * w3
    wy = r10 * w1 + r11 * w2 + r12 * w3
    wz = r20 * w1 + r21 * w2 + r22 * w3 - wp
    tx, ty, tz = applied_torque(wx, wy, wz, p)
    g1 = r00 * tx + r10 * ty + r20 * tz
    g2 = r01 * tx + r11 * ty + r21 * tz
    g3 = r02 * tx + r12 * ty + r22 * tz
    return g1, g2, g3, tz, wx, wy, wz


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def rhs(t: float, y: np.ndarray, p: np.ndarray, dy: np.ndarray) -> None:
    """Time derivative of the state, written into `dy` (both formulations).

    Parameters
    ----------
    t : float
        Time [s] (the system is autonomous).
    y : ndarray, shape (8,)
        State (layout depends on ``p[P_FORM]``; see module docstring).
    p : ndarray
        Packed parameters.
    dy : ndarray, shape (8,)
        Output.

    Notes
    -----
    Cases that the thesis's specialised kernel covers (``p[P_KERNEL]``, see
    :mod:`obturator.core.specialised`) run that kernel instead; it agrees
    with the code below to rounding.
    """
    if p[P_KERNEL] != KERNEL_GENERIC:
        rhs_thesis(y, p, dy)
        return
    r, w1, w2, w3 = _attitude_and_rates(y, p)
    wp = _spin(y, p, w1, w2, w3)
    g1, g2, g3, gz, _, _, _ = _torque_body(r, w1, w2, w3, wp, p)
    a = p[P_A]
    c = p[P_C]
    # Euler's equations, thesis Eqs. (5a)-(5c)
    dw1 = (g1 - (c - a) * w2 * w3) / a
    dw2 = (g2 + (c - a) * w1 * w3) / a
    dw3 = g3 / c
    dwp = -gz / p[P_IP] if p[P_SPIN_MODE] == SPIN_FREE else 0.0
    if p[P_FORM] == FORM_QUATERNION:
        q0, q1, q2, q3 = y[0], y[1], y[2], y[3]
        dy[0] = 0.5 * (-q1 * w1 - q2 * w2 - q3 * w3)
        dy[1] = 0.5 * (q0 * w1 + q2 * w3 - q3 * w2)
        dy[2] = 0.5 * (q0 * w2 + q3 * w1 - q1 * w3)
        dy[3] = 0.5 * (q0 * w3 + q1 * w2 - q2 * w1)
        dy[4] = dw1
        dy[5] = dw2
        dy[6] = dw3
        dy[7] = dwp
        return
    # Euler angles: invert the derivative of Eq. (13) (this is Eq. 17)
    th, thd, psd, ph, phd = y[0], y[1], y[3], y[4], y[5]
    sth, cth = math.sin(th), math.cos(th)
    sph, cph = math.sin(ph), math.cos(ph)
    e1 = psd * (thd * cth * sph + phd * sth * cph) - thd * phd * sph  # Eq. (14a) rest
    e2 = psd * (thd * cth * cph - phd * sth * sph) - thd * phd * cph  # Eq. (14b) rest
    a1 = dw1 - e1
    a2 = dw2 - e2
    psdd = (a1 * sph + a2 * cph) / sth
    thdd = a1 * cph - a2 * sph
    phdd = dw3 + psd * thd * sth - psdd * cth  # Eq. (14c)
    dy[0] = thd
    dy[1] = thdd
    dy[2] = psd
    dy[3] = psdd
    dy[4] = phd
    dy[5] = phdd
    dy[6] = dwp
    dy[7] = 0.0


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def slip_and_spin(y: np.ndarray, p: np.ndarray) -> tuple[float, float]:
    """Slip speed |omega_r| of the ball on its socket and the spin omega_p [rad/s].

    omega_r = omega_ball - omega_p Z is the ball's rate relative to the socket
    (thesis Eqs. 35-36); its direction sets the sliding-friction torque.
    """
    r, w1, w2, w3 = _attitude_and_rates(y, p)
    wp = _spin(y, p, w1, w2, w3)
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = r
    wx = r00 * w1 + r01 * w2 + r02 * w3
    wy = r10 * w1 + r11 * w2 + r12 * w3
    wz = r20 * w1 + r21 * w2 + r22 * w3 - wp
    return math.sqrt(wx * wx + wy * wy + wz * wz), wp


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def nutation_angle_of_state(y: np.ndarray, p: np.ndarray) -> float:
    """Nutation angle theta [rad] between the hole axis z and the spin axis Z."""
    if p[P_FORM] == FORM_EULER:
        return y[0]
    r = _rotation_from_quaternion(y)
    return math.atan2(math.sqrt(r[2] * r[2] + r[5] * r[5]), r[8])


@njit(cache=True, fastmath=False, error_model="python", **REFCOUNT)
def observables(ys: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Derived quantities for each state row.

    Returns
    -------
    ndarray, shape (n, 11)
        Columns: theta, psi, phi [rad]; |omega_r| [rad/s]; |G| [N m];
        ball kinetic energy T [J]; omega_p [rad/s]; H_Z, the ball's angular
        momentum about Z [kg m^2/s]; power omega_r . G [W]; omega_r X, Z
        components [rad/s].
    """
    n = ys.shape[0]
    out = np.empty((n, 11))
    a = p[P_A]
    c = p[P_C]
    for i in range(n):
        y = ys[i]
        r, w1, w2, w3 = _attitude_and_rates(y, p)
        wp = _spin(y, p, w1, w2, w3)
        g1, g2, g3, _, wx, wy, wz = _torque_body(r, w1, w2, w3, wp, p)
        r00, r01, r02, r10, r11, r12, r20, r21, r22 = r
        out[i, 0] = math.atan2(math.sqrt(r02 * r02 + r12 * r12), r22)
        out[i, 1] = math.atan2(r02, -r12)
        out[i, 2] = math.atan2(r20, r21)
        out[i, 3] = math.sqrt(wx * wx + wy * wy + wz * wz)
        out[i, 4] = math.sqrt(g1 * g1 + g2 * g2 + g3 * g3)
        out[i, 5] = 0.5 * (a * (w1 * w1 + w2 * w2) + c * w3 * w3)
        out[i, 6] = wp
        out[i, 7] = r20 * a * w1 + r21 * a * w2 + r22 * c * w3
        # G . omega_r in body axes: the relative rate is w - omega_p R^T Z
        out[i, 8] = g1 * (w1 - wp * r20) + g2 * (w2 - wp * r21) + g3 * (w3 - wp * r22)
        out[i, 9] = wx
        out[i, 10] = wz
    return out
