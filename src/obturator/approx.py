"""Approximate (linearised) solution for the nutation angle (thesis chapter II.C).

Bloomer perturbs the torque-free steady precession (Eq. 66),

    lambda psi0_dot cos(theta0) + (lambda + 1) phi0_dot = 0,

keeps first-order terms and obtains a damped second-order system for the
nutation perturbation driven by a step D and a ramp R t (Eqs. 82-88). The
closed-form response is Eq. (65); for large zeta omega_n t the ramp dominates
and the time to nutate to theta_cr is Eq. (92). At large spin, with the
viscous term dropped, Eq. (92) becomes t = T1 / omega_p^3 + T2 omega_p
(Eqs. 93-94), the form fitted to the spin-rig data in chapter IV.

Derivation (re-done here, because the printed text is OCR-garbled)
-------------------------------------------------------------------
Write theta = theta0 + x, psi_dot = psi0_dot + p, phi_dot = phi0_dot + q and
take the torque of Eq. (80): a constant magnitude M (Eq. 81) acting against the
relative rate, whose leading part is phi0_dot e_3, plus the damping
-M theta_dot / |phi0_dot| about the line of nodes. Linearising Lagrange's
equations for the axisymmetric body (C = (lambda + 1) A):

    p_dot = -(psi0_dot cot theta0) x_dot                                 (82)
    q_dot = (psi0_dot csc theta0) x_dot - (M/C) sgn(phi0_dot)            (83)
    x_ddot = -M x_dot / (A |phi0_dot|)
             - psi0_dot sin theta0 [(1 + lambda) q - lambda psi0_dot sin theta0 x
                                    + lambda p cos theta0]               (84)

Eqs. (82)-(84) are printed correctly. The ball starts co-rotating, so
x(0) = x_dot(0) = p(0) = 0 and q(0) = -phi0_dot. Integrating:

    p = -(psi0_dot cot theta0) x                                         (85)
    q = -phi0_dot + (psi0_dot csc theta0) x - (M/C) sgn(phi0_dot) t      (86)

The print of Eq. (86) shows ``cos theta0`` for ``csc theta0`` and drops the
``t``. Substituting into Eq. (84), the x-terms collapse to psi0_dot^2 x:

    x_ddot = -M x_dot / (A |phi0_dot|) - psi0_dot^2 x
             + (1 + lambda) psi0_dot sin theta0 [phi0_dot + (M/C) sgn(phi0_dot) t]   (87)

The print of Eq. (87) has ``psi0_dot sin theta0 [psi0_dot theta ...]`` (an
extra sin theta0 on the restoring term) and ``+ (M/C) t`` (the sign of the
ramp; with sgn(phi0_dot) = -1 it is ``- (M/C) t``). Dividing by omega_n^2 gives
Eq. (88), x_ddot/omega_n^2 + 2 zeta x_dot/omega_n + x = D + R t, with

    omega_n = psi0_dot = omega_p
    zeta    = M / (2 A |phi0_dot| psi0_dot)                              (89)
    D       = (1 + lambda) phi0_dot sin(theta0) / psi0_dot = -(lambda/2) sin(2 theta0)
    R       = (1 + lambda) (M/C) sin(theta0) sgn(phi0_dot) / psi0_dot
            = -(lambda / (lambda + 1)) psi0_dot sin(2 theta0) zeta       (90)

all as printed (for 0 < theta0 < pi/2, where sgn(phi0_dot) = -1). The
solution with x(0) = x_dot(0) = 0 is Eq. (65) with phi_D = atan(sqrt(1 -
zeta^2)/zeta) and phi_R = 2 phi_D (Eq. 91, printed correctly). For
zeta >= 1 (reached on the spin rig below about 200 rad/s) Eq. (65) is replaced
by the over-damped (or critically damped) homogeneous solution with the same
particular part; Eq. (92) is the large-time asymptote in either case.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import ellipe

from ._docs import field_docs
from .errors import InputError, check_range
from .model.geometry import BoredBall

__all__ = [
    "DEFAULT_VALIDITY_THRESHOLD",
    "ApproximateSolution",
    "ApproximationWarning",
    "LargeSpinCoefficients",
    "approximate_solution",
    "approximation_parameter",
    "check_validity",
    "large_spin_coefficients",
    "mean_moment_arm",
    "rig_approximation",
    "rig_sliding_moment",
    "steady_phi_rate",
]

#: Default upper limit for M / (C omega_p^2) before :func:`check_validity` warns.
#: The linearisation's damping ratio is zeta = (lambda+1)^2 / (2 lambda cos theta0)
#: * M / (C omega_p^2), i.e. about 50 M/(C omega_p^2) for the Table 1 ball at
#: theta0 = 87.25 deg: the 1/cos(theta0) amplification makes "<< 1" much
#: stricter than an order of magnitude. 0.02 puts the limit where zeta ~ 1, at
#: omega_p ~ 190 rad/s on the rig (mu_s = 0.5473), matching the thesis's remark
#: that the approximation fails below about 200 rad/s (chapter IV).
DEFAULT_VALIDITY_THRESHOLD = 0.02


class ApproximationWarning(UserWarning):
    """The small-torque assumption M / (C omega_p^2) << 1 of chapter II.C is not met."""


def _transverse_inertia(value: float) -> float:
    """The transverse moment of inertia A [kg m^2], checked positive and finite."""
    return check_range(
        "transverse_inertia", value, 0.0, math.inf, lo_open=True, hi_open=True, unit="kg m^2"
    )


def mean_moment_arm(theta0: ArrayLike) -> float | NDArray[np.float64]:
    """Mean sliding-friction moment arm r_bar / R_s = (2/pi) E(theta0), thesis Eq. (78).

    Parameters
    ----------
    theta0 : float or array_like
        Initial nutation angle theta0 [rad], the modular angle of the complete
        elliptic integral of the second kind E.

    Returns
    -------
    float or ndarray
        (2/pi) E(theta0) [-], between 2/pi (theta0 = pi/2) and 1 (theta0 = 0).

    Notes
    -----
    scipy's :func:`scipy.special.ellipe` takes the parameter m = sin^2(theta0),
    not the modular angle. E(87.25 deg) = 1.00452; the thesis text prints
    1.00458 and Table 1 prints 1.0063 (the latter belongs to theta0 ~ 86.67 deg).
    """
    m = np.sin(np.asarray(theta0, dtype=float)) ** 2
    arm = 2.0 / math.pi * ellipe(m)
    return float(arm) if np.ndim(arm) == 0 else arm


def steady_phi_rate(spin_rate: float, theta0: float, inertia_ratio: float) -> float:
    """Body spin rate phi0_dot of torque-free steady precession, thesis Eq. (66).

    Parameters
    ----------
    spin_rate : float
        Precession rate psi0_dot = omega_p [rad/s].
    theta0 : float
        Nutation angle [rad].
    inertia_ratio : float
        lambda = C/A - 1 [-].

    Returns
    -------
    float
        phi0_dot = -(lambda / (lambda + 1)) psi0_dot cos(theta0) [rad/s].
    """
    return -inertia_ratio / (inertia_ratio + 1.0) * spin_rate * math.cos(theta0)


def rig_sliding_moment(*, mu_s: float, weight: float, ball_radius: float, theta0: float) -> float:
    """Mean gravity-loaded sliding-friction moment mu_s W R_s (2/pi) E(theta0), Eq. (81).

    Parameters
    ----------
    mu_s : float
        Sliding friction coefficient [-].
    weight : float
        Ball weight W [N].
    ball_radius : float
        Ball radius R_s [m].
    theta0 : float
        Initial nutation angle [rad].

    Returns
    -------
    float
        Sliding part of M [N m]; the thesis's mu_bar W R_s with
        mu_bar = mu_s (2/pi) E(theta0) (chapter IV).
    """
    mu_s = check_range("mu_s", mu_s, 0.0, math.inf, hi_open=True)
    weight = check_range("weight", weight, 0.0, math.inf, hi_open=True, unit="N")
    ball_radius = check_range(
        "ball_radius", ball_radius, 0.0, math.inf, lo_open=True, hi_open=True, unit="m"
    )
    return mu_s * weight * ball_radius * mean_moment_arm(theta0)


@field_docs
@dataclass(frozen=True)
class ApproximateSolution:
    """Linearised nutation response, thesis Eqs. (65) and (88)-(92)."""

    #: Initial nutation angle [rad].
    theta0: float
    #: Opening angle [rad] at which the bore opens.
    theta_cr: float
    #: Natural frequency omega_n = omega_p [rad/s] (Eq. 88).
    omega_n: float
    #: Damping ratio [-] (Eq. 89).
    zeta: float
    #: Step height [rad] (Eq. 89), -(lambda/2) sin(2 theta0), negative.
    D: float
    #: Ramp slope [rad/s] (Eq. 90), negative (zero without applied torque).
    R: float
    #: Phase angle phi_D = atan(sqrt(1 - zeta^2) / zeta) [rad] of the step term of Eq. (65);
    #: NaN when zeta >= 1, where Eq. (65) has no oscillatory form.
    phi_D: float
    #: Phase angle phi_R = 2 phi_D [rad] of the ramp term of Eq. (65) (Eq. 91); NaN when
    #: zeta >= 1.
    phi_R: float
    #: Total linearised torque magnitude M = S |phi0_dot| + M_sg [N m] (Eq. 81).
    moment: float
    #: C [kg m^2], for the validity parameter.
    axial_inertia: float
    #: Steady body spin rate [rad/s] (Eq. 66).
    phi0_dot: float

    @property
    def approximation_parameter(self) -> float:
        """M / (C omega_p^2) [-]; the linearisation assumes it is << 1 (chapter II.C)."""
        return approximation_parameter(self.moment, self.axial_inertia, self.omega_n)

    def asymptote(self, t: ArrayLike) -> float | NDArray[np.float64]:
        """Ramp asymptote theta0 + D + (R/omega_n)(omega_n t - 2 zeta) [rad] (text above Eq. 92)."""
        t = np.asarray(t, dtype=float)
        out = self.theta0 + self.D + self.R / self.omega_n * (self.omega_n * t - 2.0 * self.zeta)
        return float(out) if out.ndim == 0 else out

    def nutation_angle(self, t: ArrayLike) -> float | NDArray[np.float64]:
        """Nutation angle theta(t) [rad], thesis Eq. (65) (vectorised over t [s]).

        For zeta < 1 this is Eq. (65) as printed. For zeta >= 1 the
        homogeneous part is the over-damped (critically damped at zeta = 1)
        solution meeting the same initial conditions theta(0) = theta0,
        theta_dot(0) = 0; it is written with the slow decay rate
        omega_n / (zeta + sqrt(zeta^2 - 1)) so that it neither overflows nor
        loses precision at large zeta.
        """
        t = np.asarray(t, dtype=float)
        if np.any(t < 0.0):
            raise InputError("t", "times must lie in the allowed range [0, inf) s")
        wn, z, d, r = self.omega_n, self.zeta, self.D, self.R
        ramp = d + r / wn * (wn * t - 2.0 * z)
        if z < 1.0:
            root = math.sqrt(1.0 - z * z)
            wd = wn * root
            trans = (
                np.exp(-z * wn * t)
                / root
                * (r / wn * np.sin(wd * t + self.phi_R) - d * np.sin(wd * t + self.phi_D))
            )
        else:
            # x_h = exp(-zeta wn t) [a cosh(wh t) + b sinh(wh t)/wh] with
            # a = -x_p(0) and b = zeta wn a - R (from x(0) = x_dot(0) = 0).
            wh = wn * math.sqrt(z * z - 1.0)
            slow = wn / (z + math.sqrt(z * z - 1.0))
            a = -(d - 2.0 * z * r / wn)
            b = z * wn * a - r
            e_slow = np.exp(-slow * t)
            e_diff = np.exp(-2.0 * wh * t)
            sinh_term = -np.expm1(-2.0 * wh * t) / (2.0 * wh) if wh > 0.0 else t
            trans = e_slow * (a * 0.5 * (1.0 + e_diff) + b * sinh_term)
        out = self.theta0 + ramp + trans
        return float(out) if out.ndim == 0 else out

    def opening_time(self) -> float:
        """Time to nutate to theta_cr from the ramp asymptote, thesis Eq. (92) [s].

        t = 2 zeta / omega_n - (theta0 - theta_cr) / R - D / R. Valid for large
        zeta omega_n t (the transient of Eq. 65 has died out); returns ``inf``
        when R = 0 (no applied torque: the ball never settles).
        """
        if self.R == 0.0:
            return math.inf
        return (
            2.0 * self.zeta / self.omega_n
            - (self.theta0 - self.theta_cr) / self.R
            - self.D / self.R
        )

    def crossing_time(self, theta: float | None = None, t_max: float | None = None) -> float:
        """First time [s] at which Eq. (65) reaches `theta` (default theta_cr), by root finding.

        Parameters
        ----------
        theta : float, optional
            Target angle [rad], below theta0.
        t_max : float, optional
            Search horizon [s]; defaults to twice the Eq. (92) estimate plus
            20 natural periods. Returns ``inf`` if no crossing before it.
        """
        target = self.theta_cr if theta is None else float(theta)
        if target >= self.theta0:
            return 0.0
        period = 2.0 * math.pi / self.omega_n
        if t_max is None:
            t92 = self.opening_time()
            t_max = (2.0 * t92 if math.isfinite(t92) else 0.0) + 20.0 * period
        from scipy.optimize import brentq  # on use: kept out of start-up (docs/benchmarks.md)

        # Sample finely enough to resolve both the oscillation and the fast
        # overdamped decay, then polish the first sign change with brentq.
        dt = min(period, 1.0 / (max(self.zeta, 1.0) * self.omega_n)) / 50.0
        n = int(min(max(t_max / dt, 100), 2_000_000)) + 1
        ts = np.linspace(0.0, t_max, n)
        g = np.asarray(self.nutation_angle(ts)) - target
        idx = np.flatnonzero(g <= 0.0)
        if idx.size == 0:
            return math.inf
        i = int(idx[0])
        if g[i] == 0.0:
            return float(ts[i])
        return float(
            brentq(lambda s: self.nutation_angle(s) - target, ts[i - 1], ts[i], xtol=1e-14)
        )


def approximate_solution(
    *,
    transverse_inertia: float,
    axial_inertia: float,
    sliding_moment: float,
    viscous_coefficient: float,
    theta0: float,
    spin_rate: float,
    theta_cr: float,
) -> ApproximateSolution:
    """Build the linearised solution, thesis Eqs. (66), (81) and (88)-(91).

    Parameters
    ----------
    transverse_inertia : float
        A [kg m^2].
    axial_inertia : float
        C [kg m^2], C > A (an oblate ball, lambda > 0).
    sliding_moment : float
        Mean sliding-friction moment M_sg [N m], e.g. mu_s W R_s (2/pi) E(theta0)
        on the rig (:func:`rig_sliding_moment`).
    viscous_coefficient : float
        S [N m s] of the viscous torque -S omega_r (Eq. 42).
    theta0 : float
        Initial nutation angle [rad], in (0, pi/2): at pi/2 the steady body
        spin phi0_dot vanishes and the linearisation (which divides by it) fails.
    spin_rate : float
        Projectile spin omega_p = psi0_dot [rad/s], > 0.
    theta_cr : float
        Opening angle [rad], in [0, theta0).

    Returns
    -------
    ApproximateSolution
        With M = S |phi0_dot| + M_sg (Eq. 81).
    """
    a = _transverse_inertia(transverse_inertia)
    c = check_range(
        "axial_inertia", axial_inertia, a, math.inf, lo_open=True, hi_open=True, unit="kg m^2"
    )
    m_sg = check_range("sliding_moment", sliding_moment, 0.0, math.inf, hi_open=True, unit="N m")
    s = check_range(
        "viscous_coefficient", viscous_coefficient, 0.0, math.inf, hi_open=True, unit="N m s"
    )
    th0 = check_range("theta0", theta0, 0.0, math.pi / 2, lo_open=True, hi_open=True, unit="rad")
    wp = check_range(
        "spin_rate", spin_rate, 0.0, math.inf, lo_open=True, hi_open=True, unit="rad/s"
    )
    th_cr = check_range("theta_cr", theta_cr, 0.0, th0, hi_open=True, unit="rad")

    lam = c / a - 1.0
    phi0 = steady_phi_rate(wp, th0, lam)
    moment = s * abs(phi0) + m_sg  # Eq. (81)
    zeta = moment / (2.0 * a * abs(phi0) * wp)  # Eq. (89)
    d = -0.5 * lam * math.sin(2.0 * th0)  # Eq. (89)
    r = -(lam + 1.0) / wp * moment / c * math.sin(th0)  # Eq. (89); sgn(phi0_dot) = -1
    if zeta < 1.0:
        phi_d = math.atan2(math.sqrt(1.0 - zeta * zeta), zeta)  # Eq. (91)
        phi_r = 2.0 * phi_d
    else:
        phi_d = phi_r = math.nan
    return ApproximateSolution(
        theta0=th0,
        theta_cr=th_cr,
        omega_n=wp,
        zeta=zeta,
        D=d,
        R=r,
        phi_D=phi_d,
        phi_R=phi_r,
        moment=moment,
        axial_inertia=c,
        phi0_dot=phi0,
    )


def rig_approximation(
    ball: BoredBall,
    *,
    mu_s: float,
    spin_rate: float,
    theta0: float,
    viscous_coefficient: float,
    weight: float | None = None,
    theta_cr: float | None = None,
    check: bool = True,
) -> ApproximateSolution:
    """Linearised solution for the gravity-loaded spin rig, thesis Eqs. (66), (81), (88)-(91).

    Parameters
    ----------
    ball : BoredBall
        Supplies A, C, R_s, and by default W and theta_cr = beta_s.
    mu_s : float
        Sliding friction coefficient [-].
    spin_rate : float
        Rig spin omega_p [rad/s].
    theta0 : float
        Initial nutation angle [rad].
    viscous_coefficient : float
        S [N m s] (Table 1: 12.38e-9).
    weight : float, optional
        Normal load W [N]; defaults to ``ball.weight`` (the thesis used the
        measured 0.0798-0.07987 N).
    theta_cr : float, optional
        Opening angle [rad]; defaults to ``ball.opening_angle``.
    check : bool
        Call :func:`check_validity` (may emit :class:`ApproximationWarning`).

    Returns
    -------
    ApproximateSolution
        With M = S |phi0_dot| + mu_s W R_s (2/pi) E(theta0) (Eq. 81) and
        phi0_dot = -(lambda/(lambda+1)) omega_p cos(theta0) (Eq. 66).
    """
    w = ball.weight if weight is None else weight
    sol = approximate_solution(
        transverse_inertia=ball.transverse_inertia,
        axial_inertia=ball.axial_inertia,
        sliding_moment=rig_sliding_moment(
            mu_s=mu_s, weight=w, ball_radius=ball.radius, theta0=theta0
        ),
        viscous_coefficient=viscous_coefficient,
        theta0=theta0,
        spin_rate=spin_rate,
        theta_cr=ball.opening_angle if theta_cr is None else theta_cr,
    )
    if check:
        check_validity(sol)
    return sol


def approximation_parameter(moment: float, axial_inertia: float, spin_rate: float) -> float:
    """Small parameter M / (C omega_p^2) [-] of the linearisation (chapter II.C).

    Parameters
    ----------
    moment : float
        Torque magnitude M [N m] (Eq. 81).
    axial_inertia : float
        C [kg m^2].
    spin_rate : float
        omega_p [rad/s].
    """
    return moment / (axial_inertia * spin_rate**2)


def check_validity(
    solution: ApproximateSolution, *, threshold: float = DEFAULT_VALIDITY_THRESHOLD
) -> float:
    """Return M / (C omega_p^2) and warn if it is not small.

    Parameters
    ----------
    solution : ApproximateSolution
        The linearised solution to check.
    threshold : float
        Largest accepted M / (C omega_p^2) [-]; see
        :data:`DEFAULT_VALIDITY_THRESHOLD` for why the default is 0.02.

    Returns
    -------
    float
        The approximation parameter.

    Warns
    -----
    ApproximationWarning
        If the parameter exceeds `threshold`.
    """
    eps = solution.approximation_parameter
    if eps > threshold:
        warnings.warn(
            f"M/(C omega_p^2) = {eps:.3g} exceeds {threshold:g} at omega_p = "
            f"{solution.omega_n:g} rad/s (zeta = {solution.zeta:.3g}): the linearised "
            "solution (thesis Eqs. 65-92) assumes small applied torques",
            ApproximationWarning,
            stacklevel=2,
        )
    return eps


@field_docs
@dataclass(frozen=True)
class LargeSpinCoefficients:
    """Coefficients of t = T1 / omega_p^3 + T2 omega_p, thesis Eqs. (93)-(94)."""

    #: [rad^3 / s^2]: ((lambda+1)/lambda) M / (A cos theta0).
    T1: float
    #: [s^2 / rad]: A / (M sin theta0) [(theta0 - theta_cr) - (lambda/2) sin(2 theta0)].
    T2: float

    def opening_time(self, spin_rate: ArrayLike) -> float | NDArray[np.float64]:
        """t_cr = T1 / omega_p^3 + T2 omega_p [s] (Eq. 94); omega_p in rad/s."""
        w = np.asarray(spin_rate, dtype=float)
        out = self.T1 / w**3 + self.T2 * w
        return float(out) if out.ndim == 0 else out


def large_spin_coefficients(
    *,
    transverse_inertia: float,
    inertia_ratio: float,
    moment: float,
    theta0: float,
    theta_cr: float,
) -> LargeSpinCoefficients:
    """T1, T2 of the large-spin, no-viscosity form of Eq. (92), thesis Eqs. (93)-(95).

    With S = 0, 2 zeta / omega_n = T1 / omega_p^3 and
    -(theta0 - theta_cr + D) / R = T2 omega_p, where

        T1 = ((lambda + 1) / lambda) M / (A cos theta0)
        T2 = A / (M sin theta0) [(theta0 - theta_cr) - (lambda/2) sin(2 theta0)]

    The printed Eq. (93) shows ``(A/2) sin theta0`` for the last term; the
    derivation from Eq. (92) gives ``(lambda/2) sin(2 theta0)``.

    Parameters
    ----------
    transverse_inertia : float
        A [kg m^2].
    inertia_ratio : float
        lambda = C/A - 1 [-], > 0.
    moment : float
        Sliding moment M = mu_bar W R_s [N m] (pass W R_s to get T1/mu_bar and
        T2 mu_bar).
    theta0, theta_cr : float
        Initial and opening nutation angles [rad].

    Notes
    -----
    The thesis's printed T1 = 2.039e5 mu_bar and T2 = 3.03e-4 / mu_bar are
    reproduced with M = W R_s mu_bar = 0.0798 N x 7.899 mm = 6.303e-4 mu_bar N m,
    not the printed M = 6.34e-4 mu_bar (which gives 2.051e5 and 3.016e-4).
    """
    a = _transverse_inertia(transverse_inertia)
    lam = check_range("inertia_ratio", inertia_ratio, 0.0, math.inf, lo_open=True, hi_open=True)
    m = check_range("moment", moment, 0.0, math.inf, lo_open=True, hi_open=True, unit="N m")
    th0 = check_range("theta0", theta0, 0.0, math.pi / 2, lo_open=True, hi_open=True, unit="rad")
    th_cr = check_range("theta_cr", theta_cr, 0.0, th0, hi_open=True, unit="rad")
    t1 = (lam + 1.0) / lam * m / (a * math.cos(th0))
    t2 = a / (m * math.sin(th0)) * ((th0 - th_cr) - 0.5 * lam * math.sin(2.0 * th0))
    return LargeSpinCoefficients(T1=t1, T2=t2)
