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

The Coulomb patch law (``torque_model="coulomb"``, :func:`obturator.core.dynamics.
applied_torque`): contact k (unit normal n_k, fixed in inertial axes, load N_k)
dissipates mu N_k g_k with g_k(omega_r) = sqrt(R_s^2 |omega_r x n_k|^2 +
eps^2 (omega_r . n_k)^2), eps = 3 pi a / 16 the pivot arm of a Hertzian patch of
radius a (Contensou's coupling of sliding and pivoting in the elliptic form of Leine
and Glocker, *Eur. J. Mech. A/Solids* 22, 2003, 193-216). Its moment in slip is
G_f = -grad D(omega_r), D = sum_k mu N_k g_k, a norm of omega_r for eps > 0: the law
is the subdifferential of a convex dissipation function (Moreau; Glocker 2001,
ch. 7), so its set at zero slip is the subdifferential there, the convex set

    F = -dD(0) = E_1 + ... + E_n  (Minkowski sum),
    E_k = {G : |G x n_k|^2 / (mu N_k R_s)^2 + (G . n_k)^2 / (mu N_k eps)^2 <= 1},

each E_k the moments a patch can transmit: up to mu N_k R_s from its friction force
(perpendicular to n_k), up to mu N_k eps of pivot moment about n_k, coupled
elliptically. Its support function is D itself, so G is in F iff its gauge
gamma(G) = max_d G . d / D(d) <= 1 (:func:`coulomb_gauge`, closed form for one
contact, an iteration for several). With a = 0 (point contacts) E_k degenerates
to a flat disc in the plane of n_k: the rig's single contact then holds no moment
about X at all, stick is a set of measure zero along the rigid turn, and the
regularised t_cr does not converge as its width shrinks; the set-valued solver
refuses that case.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .jit_cache import configure_cache
from .jit_flags import NO_REFCOUNT
from .layout import FRIC_COULOMB, FRIC_THESIS_FLIGHT, FRIC_THESIS_RIG, P_A, P_C, P_FRIC

configure_cache()

__all__ = [
    "arm_coefficients",
    "moment_scale",
    "coulomb_gauge",
    "exit_slip_direction",
    "required_reaction",
    "stick_margin",
    "breakaway_angle",
    "hold_stick",
    "turn_rigidly",
    "turn_by",
    "relative_rate",
]


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def arm_coefficients(p: np.ndarray) -> tuple[float, float]:
    """(b_X, b_Z) of ARM(u)^2 = b_X u_X^2 + u_Y^2 + b_Z u_Z^2 (rig Eq. 61; Appendix A)."""
    if p[P_FRIC] == FRIC_THESIS_FLIGHT:
        sb = math.sin(p[P_FRIC + 3])
        cb = math.cos(p[P_FRIC + 3])
        return cb * cb, sb * sb
    if p[P_FRIC] == FRIC_THESIS_RIG:
        return 0.0, 1.0
    return 1.0, 1.0  # no friction: the set is {0}; never used with stick


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def moment_scale(p: np.ndarray) -> float:
    """Largest friction moment scale [N m]: M of the thesis law, n mu N_k R_s of contacts."""
    if p[P_FRIC] == FRIC_COULOMB:
        return p[P_FRIC + 1] * p[P_FRIC + 2] * p[P_FRIC + 4]
    return p[P_FRIC + 1]


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _contact_normal(k: int, p: np.ndarray) -> tuple[float, float, float]:
    """Unit normal n_k of contact k, placed as :func:`~.dynamics.applied_torque` does."""
    gam = 2.0 * math.pi * k / p[P_FRIC + 4]
    beta = p[P_FRIC + 3]
    if beta >= 0.5 * math.pi - 1e-12:  # the rig: bottom of the socket, gravity along -X
        return -math.cos(gam), -math.sin(gam), 0.0
    sb = math.sin(beta)
    return sb * math.cos(gam), sb * math.sin(gam), math.cos(beta)


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _solve3(h00, h01, h02, h11, h12, h22, bx, by, bz) -> tuple[float, float, float]:
    """H^-1 b for a symmetric 3 x 3 H (cofactors); nan where H is singular."""
    c00 = h11 * h22 - h12 * h12
    c01 = h02 * h12 - h01 * h22
    c02 = h01 * h12 - h02 * h11
    c11 = h00 * h22 - h02 * h02
    c12 = h01 * h02 - h00 * h12
    c22 = h00 * h11 - h01 * h01
    det = h00 * c00 + h01 * c01 + h02 * c02
    if det == 0.0:
        return math.nan, math.nan, math.nan
    return (
        (c00 * bx + c01 * by + c02 * bz) / det,
        (c01 * bx + c11 * by + c12 * bz) / det,
        (c02 * bx + c12 * by + c22 * bz) / det,
    )


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _support_derivatives(dx: float, dy: float, dz: float, p: np.ndarray) -> tuple:
    """D(d) = sum_k mu N_k s_k, s_k = |d|_{Q_k} = sqrt(d^T Q_k d) (Q_k = R_s^2 (1 - n_k
    n_k^T) + eps^2 n_k n_k^T), its gradient sum_k mu N_k Q_k d / s_k, and the entries
    (00, 01, 02, 11, 12, 22) of two symmetric matrices: M = sum_k mu N_k Q_k / s_k,
    the Hessian of the quadratic that majorises D at d, and D's Hessian
    M - sum_k mu N_k (Q_k d)(Q_k d)^T / s_k^3. Returns (D, grad (3), M (6), Hessian (6))."""
    mu_n = p[P_FRIC + 1]
    r2 = p[P_FRIC + 2] * p[P_FRIC + 2]
    e2 = p[P_FRIC + 5] * p[P_FRIC + 5]
    d_norm = gx = gy = gz = 0.0
    m00 = m01 = m02 = m11 = m12 = m22 = 0.0
    k00 = k01 = k02 = k11 = k12 = k22 = 0.0
    for k in range(int(p[P_FRIC + 4])):
        nx, ny, nz = _contact_normal(k, p)
        dn = dx * nx + dy * ny + dz * nz
        qx = r2 * (dx - dn * nx) + e2 * dn * nx  # Q_k d
        qy = r2 * (dy - dn * ny) + e2 * dn * ny
        qz = r2 * (dz - dn * nz) + e2 * dn * nz
        s = math.sqrt(max(qx * dx + qy * dy + qz * dz, 1e-300))
        d_norm += mu_n * s
        f = mu_n / s
        gx += f * qx
        gy += f * qy
        gz += f * qz
        c = f * (e2 - r2)
        m00 += f * r2 + c * nx * nx
        m11 += f * r2 + c * ny * ny
        m22 += f * r2 + c * nz * nz
        m01 += c * nx * ny
        m02 += c * nx * nz
        m12 += c * ny * nz
        f3 = f / (s * s)
        k00 += f3 * qx * qx
        k11 += f3 * qy * qy
        k22 += f3 * qz * qz
        k01 += f3 * qx * qy
        k02 += f3 * qx * qz
        k12 += f3 * qy * qz
    return (
        d_norm,
        gx,
        gy,
        gz,
        m00,
        m01,
        m02,
        m11,
        m12,
        m22,
        m00 - k00,
        m01 - k01,
        m02 - k02,
        m11 - k11,
        m12 - k12,
        m22 - k22,
    )


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _form(h: tuple, ax: float, ay: float, az: float, bx: float, by: float, bz: float) -> float:
    """a^T H b for the symmetric 3 x 3 H given by its entries (00, 01, 02, 11, 12, 22)."""
    h00, h01, h02, h11, h12, h22 = h
    return (
        ax * (h00 * bx + h01 * by + h02 * bz)
        + ay * (h01 * bx + h11 * by + h12 * bz)
        + az * (h02 * bx + h12 * by + h22 * bz)
    )


#: Relative optimality residual |G - gamma grad D(d)| / |G| at which :func:`coulomb_gauge`
#: stops; gamma's relative error is then second order in it, below rounding.
GAUGE_RESIDUAL = 1e-13

#: Most steps of :func:`coulomb_gauge` (the flight ring: ~5 on average, at most ~40).
GAUGE_STEPS = 200


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _gauge_residual(gx: float, gy: float, gz: float, g: float, der: tuple) -> float:
    """|G - gamma grad D(d)| / |G| at d on the plane G . d = 1 (gamma = 1 / D(d))."""
    rx = gx - der[1] / der[0]
    ry = gy - der[2] / der[0]
    rz = gz - der[3] / der[0]
    return math.sqrt(rx * rx + ry * ry + rz * rz) / g


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _lowers(d_norm: float, res: float, new_norm: float, new_res: float) -> bool:
    """A step is progress: D falls, or (near the minimum, where D's change is below its
    rounding while the residual's is not) D holds to 1e-14 and the residual falls."""
    return new_norm < d_norm or (new_norm <= d_norm * (1.0 + 1e-14) and new_res < res)


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def coulomb_gauge(gx: float, gy: float, gz: float, p: np.ndarray) -> tuple:
    """Gauge gamma(G) = max_d G . d / D(d) of the Coulomb patch set F, and its maximiser.

    G [N m] is in F iff gamma <= 1; F's radius along G is |G| / gamma, and the
    maximiser d (returned unit) is F's outward normal at G / gamma. D(d) = sum_k
    mu N_k sqrt(d^T Q_k d), Q_k = R_s^2 (1 - n_k n_k^T) + eps^2 n_k n_k^T, is convex
    and, for eps > 0, smooth, so gamma = 1 / min D(d) over the plane G . d = 1, whose minimiser
    satisfies grad D(d) = D(d) G: the optimality residual
    r = |G - gamma grad D(d)| / |G| (scale-free) vanishes at the maximiser alone.

    The minimisation runs in two tangent coordinates of that plane from d = G / |G|^2:
    a Newton step (D's Hessian is a sum over contacts) where it lowers D, else a
    majorise-minimise step d <- (sum_k mu N_k Q_k / |d|_{Q_k})^-1 G rescaled to the
    plane, which always does (exact at once for one contact). Majorise-minimise alone
    converges linearly and slowly for a ring of thin patches (eps << R_s): 200 steps of
    it, stopped on the change of gamma, left gamma up to 1.6e-6 low on the flight ring.
    Newton overshoots where D is nearly a kink (d near a normal n_k of a thin patch),
    so after a rejected Newton step 1, 3, 7, 15, then 16 majorise-minimise steps run
    before the next try. The iteration stops on the optimality residual, at r <=
    :data:`GAUGE_RESIDUAL` (1e-13), or where no step lowers D or (with D held to
    1e-14) r: the rounding floor, measured r <= 4.1e-13 on the rig's patch and the
    flight ring (20,000 random G each); or after :data:`GAUGE_STEPS`. Stated tolerance
    (tests/core/test_stick_slip_coulomb.py checks both): r <= 1e-12 at the returned d,
    and gamma, attained there (G . d / D(d)), is the maximum to a relative 1e-12 (its
    error is second order in r).

    Returns
    -------
    tuple of float
        (gamma [-], d_X, d_Y, d_Z).
    """
    # gamma is homogeneous of degree one in G: work with G / max|G_i| so that no
    # square of a component under- or overflows (a G of 1e-158 N m made g2 = 0)
    scale = max(abs(gx), abs(gy), abs(gz))
    if scale == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    gx, gy, gz = gx / scale, gy / scale, gz / scale
    g2 = gx * gx + gy * gy + gz * gz
    g = math.sqrt(g2)
    # orthonormal tangents t, u of the plane: t = G x (the axis G is least along)
    if abs(gx) <= abs(gy) and abs(gx) <= abs(gz):
        tx, ty, tz = 0.0, gz, -gy
    elif abs(gy) <= abs(gz):
        tx, ty, tz = -gz, 0.0, gx
    else:
        tx, ty, tz = gy, -gx, 0.0
    t = math.sqrt(tx * tx + ty * ty + tz * tz)
    tx, ty, tz = tx / t, ty / t, tz / t
    ux = (gy * tz - gz * ty) / g
    uy = (gz * tx - gx * tz) / g
    uz = (gx * ty - gy * tx) / g
    dx, dy, dz = gx / g2, gy / g2, gz / g2
    der = _support_derivatives(dx, dy, dz, p)
    res = _gauge_residual(gx, gy, gz, g, der)
    wait = skip = 0  # after a rejected Newton step, majorise-minimise steps before the next
    for _ in range(GAUGE_STEPS):
        if res <= GAUGE_RESIDUAL:
            break
        accepted = False
        if wait > 0:
            wait -= 1
        else:
            hess = der[10:16]
            a_t = tx * der[1] + ty * der[2] + tz * der[3]
            a_u = ux * der[1] + uy * der[2] + uz * der[3]
            h_tt = _form(hess, tx, ty, tz, tx, ty, tz)
            h_tu = _form(hess, tx, ty, tz, ux, uy, uz)
            h_uu = _form(hess, ux, uy, uz, ux, uy, uz)
            det = h_tt * h_uu - h_tu * h_tu
            if det > 0.0 and h_tt > 0.0:
                st = (h_tu * a_u - h_uu * a_t) / det
                su = (h_tu * a_t - h_tt * a_u) / det
                nx, ny, nz = dx + st * tx + su * ux, dy + st * ty + su * uy, dz + st * tz + su * uz
                new = _support_derivatives(nx, ny, nz, p)
                new_res = _gauge_residual(gx, gy, gz, g, new)
                accepted = _lowers(der[0], res, new[0], new_res)
            # thin patches (eps << R_s) near a normal n_k: D is almost a kink there and
            # Newton overshoots until majorise-minimise has come close; back off
            skip = 0 if accepted else min(2 * skip + 1, 16)
            wait = skip
        if not accepted:  # majorise-minimise: monotone in D
            m = der[4:10]
            ex, ey, ez = _solve3(m[0], m[1], m[2], m[3], m[4], m[5], gx, gy, gz)
            ge = gx * ex + gy * ey + gz * ez
            if not ge > 0.0:
                break
            nx, ny, nz = ex / ge, ey / ge, ez / ge
            new = _support_derivatives(nx, ny, nz, p)
            new_res = _gauge_residual(gx, gy, gz, g, new)
            if not _lowers(der[0], res, new[0], new_res):
                break  # rounding: no step lowers D or the residual
        dx, dy, dz, der, res = nx, ny, nz, new, new_res
    d = math.sqrt(dx * dx + dy * dy + dz * dz)
    return scale * (gx * dx + gy * dy + gz * dz) / der[0], dx / d, dy / d, dz / d


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def exit_slip_direction(y: np.ndarray, gx: float, gy: float, gz: float, p: np.ndarray) -> tuple:
    """Unit direction u in which a slip leaves zero slip at state `y` where the reaction
    G [N m] that stick needs is outside F (or on its boundary).

    Near zero slip omega_r' = I^-1 (G_f(u) - G) with G_f depending on u alone, so a
    slip leaves zero along a ray: I^-1 (G_f(u) - G) = lambda u, lambda > 0.
    Thesis law, G_f = -M ARM(u) u and G perpendicular to the hole axis (I^-1 G = G / A):
    u = -G / |G|. Coulomb patch law, G_f = -grad D(u): the ray is the direction of the
    minimiser omega* of the strictly convex 1/2 omega^T I omega + D(omega) + G . omega
    (its stationarity is I omega + grad D(omega) = -G), unique, and zero iff G is in F;
    found by majorise-minimise steps omega <- -(I + sum_k Q_k / |omega|_{Q_k})^-1 G. On
    the boundary of F it tends to minus the outward normal (:func:`coulomb_gauge`).
    (0, 0, 0) for G = 0.
    """
    g = math.sqrt(gx * gx + gy * gy + gz * gz)
    if g == 0.0:
        return 0.0, 0.0, 0.0
    if p[P_FRIC] != FRIC_COULOMB:
        return -gx / g, -gy / g, -gz / g
    zx, zy, zz = _hole_axis(y)
    a, dc = p[P_A], p[P_C] - p[P_A]
    _, dx, dy, dz = coulomb_gauge(gx, gy, gz, p)
    wx, wy, wz = -dx, -dy, -dz  # the boundary's ray, scaled below
    scale = 0.0
    for it in range(500):
        _, _, _, _, h00, h01, h02, h11, h12, h22 = _support_derivatives(wx, wy, wz, p)[:10]
        h00 += a + dc * zx * zx
        h11 += a + dc * zy * zy
        h22 += a + dc * zz * zz
        h01 += dc * zx * zy
        h02 += dc * zx * zz
        h12 += dc * zy * zz
        vx, vy, vz = _solve3(h00, h01, h02, h11, h12, h22, -gx, -gy, -gz)
        v = math.sqrt(vx * vx + vy * vy + vz * vz)
        if not v > 0.0:
            break
        change = math.sqrt((vx - wx) ** 2 + (vy - wy) ** 2 + (vz - wz) ** 2)
        wx, wy, wz = vx, vy, vz
        scale = v
        if it > 0 and change <= 1e-13 * v:
            break
    if not scale > 0.0:
        return -dx, -dy, -dz
    # Newton's method polishes what majorise-minimise leaves (it slows near F's boundary)
    res = _departure_residual(wx, wy, wz, gx, gy, gz, zx, zy, zz, p)
    for _ in range(30):
        ox, oy, oz = _solve3(res[3], res[4], res[5], res[6], res[7], res[8], res[0], res[1], res[2])
        nx, ny, nz = wx - ox, wy - oy, wz - oz
        new = _departure_residual(nx, ny, nz, gx, gy, gz, zx, zy, zz, p)
        if not (new[9] < res[9]):
            break
        wx, wy, wz, res = nx, ny, nz, new
    scale = math.sqrt(wx * wx + wy * wy + wz * wz)
    return wx / scale, wy / scale, wz / scale


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _departure_residual(wx, wy, wz, gx, gy, gz, zx, zy, zz, p) -> tuple:
    """Gradient I w + grad D(w) + G of the departure's convex function, its Hessian
    I + sum_k mu N_k (Q_k / s_k - Q_k w w^T Q_k / s_k^3) (Q_k = R^2 (1 - n n^T) +
    eps^2 n n^T, s_k = |w|_{Q_k}) and the gradient's norm: (r_X, r_Y, r_Z, h00, h01,
    h02, h11, h12, h22, |r|)."""
    a, dc = p[P_A], p[P_C] - p[P_A]
    der = _support_derivatives(wx, wy, wz, p)
    zw = zx * wx + zy * wy + zz * wz
    rx = a * wx + dc * zx * zw + gx + der[1]
    ry = a * wy + dc * zy * zw + gy + der[2]
    rz = a * wz + dc * zz * zw + gz + der[3]
    h00 = a + dc * zx * zx + der[10]
    h01 = dc * zx * zy + der[11]
    h02 = dc * zx * zz + der[12]
    h11 = a + dc * zy * zy + der[13]
    h12 = dc * zy * zz + der[14]
    h22 = a + dc * zz * zz + der[15]
    return rx, ry, rz, h00, h01, h02, h11, h12, h22, math.sqrt(rx * rx + ry * ry + rz * rz)


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _hole_axis(y: np.ndarray) -> tuple[float, float, float]:
    """Hole axis z in inertial axes: third column of R(q / |q|)."""
    q0, q1, q2, q3 = y[0], y[1], y[2], y[3]
    s = 2.0 / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    return s * (q1 * q3 + q0 * q2), s * (q2 * q3 - q0 * q1), 1.0 - s * (q1 * q1 + q2 * q2)


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def required_reaction(y: np.ndarray, p: np.ndarray, wp: float) -> tuple[float, float, float]:
    """Friction moment [N m] (inertial axes) that keeps omega_r = 0 at state `y`.

    G_req = omega_p^2 (C - A) z_Z (Z x z), from Euler's equations (Eqs. 5a-5c) with the
    ball turning rigidly at omega_p = `wp` [rad/s] about Z.
    """
    zx, zy, zz = _hole_axis(y)
    g = wp * wp * (p[P_C] - p[P_A]) * zz
    return -g * zy, g * zx, 0.0


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def stick_margin(gx: float, gy: float, gz: float, p: np.ndarray) -> float:
    """Radius of F along the moment G minus |G| [N m]: > 0 inside F.

    Thesis law: ARM is even in u, so the radius along G is M ARM(G / |G|). Coulomb
    patch law: |G| / gamma(G) (:func:`coulomb_gauge`).
    """
    scale = max(abs(gx), abs(gy), abs(gz))  # no square under- or overflows
    if scale == 0.0:
        return moment_scale(p)
    ux, uy, uz = gx / scale, gy / scale, gz / scale
    u = math.sqrt(ux * ux + uy * uy + uz * uz)  # |G| = scale u
    if p[P_FRIC] == FRIC_COULOMB:
        return u / coulomb_gauge(ux, uy, uz, p)[0] - scale * u
    m = p[P_FRIC + 1]
    b_x, b_z = arm_coefficients(p)
    arm2 = (b_x * ux * ux + uy * uy + b_z * uz * uz) / (u * u)
    return m * math.sqrt(max(arm2, 0.0)) - scale * u


#: Samples per half turn of the rigid-turn scan for the exits of a Coulomb set of
#: several contacts (no closed form); an exit window narrower than pi / this is missed.
EXIT_SCAN = 512


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _exit_level(k_req: float, p: np.ndarray) -> float:
    """c^2 such that G_req (magnitude `k_req` [N m]) is in F while cos^2 psi >= c^2;
    nan where F has no such closed form (Coulomb contacts other than the rig's one).

    Thesis law: b_X sin^2 psi + cos^2 psi >= kappa^2, kappa = k_req / M. The rig's one
    Coulomb patch (n = -X; moment K cos psi in its tangent plane, K sin psi about n):
    K^2 cos^2 psi / M_t^2 + K^2 sin^2 psi / M_e^2 <= 1, M_t = mu N R_s, M_e = mu N eps.
    """
    if p[P_FRIC] == FRIC_COULOMB:
        if p[P_FRIC + 4] != 1.0 or p[P_FRIC + 3] < 0.5 * math.pi - 1e-12:
            return math.nan
        inv_t = 1.0 / (p[P_FRIC + 1] * p[P_FRIC + 2]) ** 2
        m_e = p[P_FRIC + 1] * p[P_FRIC + 5]
        if m_e == 0.0:  # point contact: a flat disc, G_req must lie in it
            return 1.0
        inv_e = 1.0 / (m_e * m_e)
        return (inv_e - 1.0 / (k_req * k_req)) / (inv_e - inv_t)
    kappa = k_req / p[P_FRIC + 1]
    b_x, _ = arm_coefficients(p)
    if b_x >= 1.0:
        return -math.inf
    return (kappa * kappa - b_x) / (1.0 - b_x)


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _outside(k_req: float, psi: float, p: np.ndarray) -> bool:
    """G_req = k_req (-sin psi, cos psi, 0) outside F (Coulomb set, by its gauge)."""
    return k_req * coulomb_gauge(-math.sin(psi), math.cos(psi), 0.0, p)[0] > 1.0


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _scanned_exit(k_req: float, psi: float, p: np.ndarray) -> float:
    """:func:`breakaway_angle` by sampling the gauge along the turn (period pi: F = -F)
    and bisecting the first change to the last bit."""
    out0 = _outside(k_req, psi, p)
    step = math.pi / EXIT_SCAN
    lo = 0.0
    for i in range(1, EXIT_SCAN + 1):
        hi = i * step
        if _outside(k_req, psi + hi, p) != out0:
            for _ in range(64):
                mid = 0.5 * (lo + hi)
                if mid <= lo or mid >= hi:
                    break
                if _outside(k_req, psi + mid, p) == out0:
                    lo = mid
                else:
                    hi = mid
            return -hi if out0 else lo
        lo = hi
    return 0.0 if out0 else math.inf


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def breakaway_angle(y: np.ndarray, p: np.ndarray, wp: float) -> float:
    """Rotation angle [rad] of rigid stick from `y` after which G_req leaves F.

    With G_req = g (-z_Y, z_X, 0), |G_req| = K = |g| sin(theta) and
    z_X = sin(theta) cos(psi), G_req is in F while cos^2 psi >= c^2 with c^2 from the
    law (:func:`_exit_level`; the thesis law: c^2 = (kappa^2 - b_X) / (1 - b_X),
    kappa = K / M). Returns inf when stick is never lost (c^2 < 0, or theta = 0 / 90
    deg exactly), 0 when G_req is outside F everywhere, and minus the angle to the end
    of the window when `y` is in one. A Coulomb set of several contacts has no closed
    form: its exits are sampled (:data:`EXIT_SCAN`) and bisected.
    """
    zx, zy, zz = _hole_axis(y)
    sin_th = math.sqrt(zx * zx + zy * zy)
    k_req = abs(wp * wp * (p[P_C] - p[P_A]) * zz) * sin_th
    if k_req == 0.0:
        return math.inf
    psi = math.atan2(zy, zx)
    if wp < 0.0:  # the azimuth decreases: mirror (F is symmetric about the X-Z plane)
        psi = -psi
    c2 = _exit_level(k_req, p)
    if c2 != c2:
        return _scanned_exit(k_req, psi, p)
    if c2 < 0.0:
        return math.inf
    if c2 >= 1.0:
        return 0.0
    psi1 = math.acos(math.sqrt(c2))  # |cos psi| = c at psi1 and pi - psi1 (mod pi)
    psi = psi % math.pi
    if psi <= psi1:
        return psi1 - psi
    if psi >= math.pi - psi1:
        return math.pi - psi + psi1
    return -(math.pi - psi1 - psi)  # inside the window: minus the angle to its end


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
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


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
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


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
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


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
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
