"""One opening problem (:class:`Case`) and its state at release (:func:`initial_state`).

A :class:`Case` bundles the ball (:mod:`.geometry`), the torques
(:mod:`.torques`), the projectile spin and the release state, in SI units,
checked on construction. The thesis's built-in cases are made by
:mod:`.cases`; :mod:`obturator.solve` integrates them.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, replace

import numpy as np

from ..core.layout import N_STATE
from ..errors import InputError, check_range
from ..params import MIN_HOLE_FRACTION, PARAMS
from ..reference import TABLE1
from ..vocab import SPIN_MODES, Formulation, SpinMode, check_choice
from .geometry import BoredBall
from .torques import TorqueModel

__all__ = ["Case", "initial_state", "MAX_SPIN_RATE", "MAX_T_MAX"]

#: Longest integration horizon accepted [s].
MAX_T_MAX = 1e4
#: Largest projectile spin accepted [rad/s].
MAX_SPIN_RATE = 1e6


@dataclass(frozen=True)
class Case:
    """One obturator opening problem: ball, torques, projectile spin, release state.

    Parameters
    ----------
    ball : BoredBall
        Mass properties (A, C, beta_s).
    torque : TorqueModel
        Applied torques (viscous + sliding friction).
    spin_rate : float
        Projectile spin at release omega_p [rad/s], > 0.
    theta0 : float
        Initial nutation angle theta_0 [rad], in (0, pi/2].
    spin_mode : {"constant", "free", "thesis-energy"}
        Projectile spin held constant (driven rig), free with the total axial
        angular momentum conserved (needs I_p), or Appendix A's energy form.
    projectile_inertia : float
        I_p [kg m^2] (Table 1: 8.58e-6).
    theta_cr : float or None
        Opening angle [rad]; None uses beta_s = asin(r_s/R_s).
    t_max : float
        Give up (status 0) if the bore has not opened by this time [s].
    name : str
        Label carried into results.
    release_rate : (float, float, float)
        Relative rates at release (theta_dot_0, phi_dot_0, psi_dot_0 - omega_p)
        [rad/s]; default zero, the thesis's co-rotating release (p. 45). A
        release transient (plunger, holding jet) is a small non-zero value.
    release_phase : float
        psi_0 [rad], the azimuth of the line of nodes at release. It matters on
        the rig, where gravity (along -X) breaks the symmetry about Z.
    """

    ball: BoredBall
    torque: TorqueModel
    spin_rate: float
    theta0: float
    spin_mode: SpinMode = "constant"
    projectile_inertia: float = TABLE1["projectile_inertia"]
    theta_cr: float | None = None
    t_max: float = 5.0
    name: str = ""
    release_rate: tuple[float, float, float] = (0.0, 0.0, 0.0)
    release_phase: float = 0.0

    def __post_init__(self) -> None:
        # 1e6 rad/s: 80 times a 20 mm round's ~1.2e4 rad/s; a steel ball bursts far below;
        # from 1 rad/s (the registry's range, argued there: the integrators' step
        # control, scaled by the spin period, degenerates below it)
        spin = PARAMS["spin_rate"].range
        check_range("spin_rate", self.spin_rate, spin.lo, MAX_SPIN_RATE, unit="rad/s")
        r_min = MIN_HOLE_FRACTION * self.ball.radius
        if not self.ball.hole_radius >= r_min:
            raise InputError(
                "hole_radius",
                f"{self.ball.hole_radius:g} m is outside the allowed range [{r_min:g}, "
                f"{self.ball.radius / math.sqrt(2.0):g}) m of a case (from R_s/10: a smaller "
                "bore leaves the ball nearly a sphere, which never turns its hole to the "
                "spin; obturator.params.MIN_HOLE_FRACTION)",
            )
        check_range("theta0", math.degrees(self.theta0), 0.0, 90.0, lo_open=True, unit="deg")
        check_choice("spin_mode", self.spin_mode, SPIN_MODES)
        # from the smallest normal double on: free spin divides by it
        check_range(
            "projectile_inertia", self.projectile_inertia, sys.float_info.min, unit="kg m^2"
        )
        if self.theta_cr is not None:
            check_range(
                "theta_cr",
                math.degrees(self.theta_cr),
                0.0,
                math.degrees(self.theta0),
                hi_open=True,
                unit="deg",
            )
        elif self.ball.opening_angle >= self.theta0:
            raise InputError(
                "theta0",
                f"{math.degrees(self.theta0):g} deg must exceed the "
                f"opening angle beta_s = {math.degrees(self.ball.opening_angle):g} deg",
            )
        # 1e4 s: 230 times the slowest thesis case (40 rad/s: 43 s); bounds the run time
        check_range("t_max", self.t_max, 0.0, MAX_T_MAX, lo_open=True, unit="s")
        if len(self.release_rate) != 3:
            raise InputError("release_rate", "expected (theta_dot, phi_dot, psi_dot - omega_p)")
        for name, x in zip(("theta_dot0", "phi_dot0", "psi_dot0"), self.release_rate, strict=True):
            check_range(name, x, -self.spin_rate, self.spin_rate, unit="rad/s")
        check_range("release_phase", self.release_phase, -2 * math.pi, 2 * math.pi, unit="rad")

    def initial_state(self, formulation: Formulation = "quaternion") -> np.ndarray:
        """State at release (thesis p. 45, plus :attr:`release_rate` and :attr:`release_phase`)."""
        thd, phd, psd = self.release_rate
        return initial_state(
            self.theta0,
            self.spin_rate,
            formulation=formulation,
            psi_dot=self.spin_rate + psd,
            phi_dot=phd,
            theta_dot=thd,
            psi0=self.release_phase,
        )

    @property
    def opening_angle(self) -> float:
        """theta_cr [rad] (beta_s unless overridden)."""
        return self.ball.opening_angle if self.theta_cr is None else float(self.theta_cr)

    def with_(self, **changes: object) -> Case:
        """Return a copy with fields replaced (dataclasses.replace)."""
        return replace(self, **changes)


def initial_state(
    theta0: float,
    spin_rate: float,
    *,
    formulation: Formulation = "quaternion",
    psi_dot: float | None = None,
    phi_dot: float = 0.0,
    theta_dot: float = 0.0,
    psi0: float = 0.0,
    phi0: float = 0.0,
) -> np.ndarray:
    """State vector at release (thesis p. 45: theta_dot = phi_dot = 0, psi_dot = omega_p).

    Parameters
    ----------
    theta0 : float
        Initial nutation theta_0 [rad].
    spin_rate : float
        Projectile spin omega_p [rad/s] (stored as the spin state).
    formulation : {"quaternion", "euler"}
    psi_dot, phi_dot, theta_dot : float
        Euler-angle rates [rad/s]; psi_dot defaults to omega_p (co-rotation).
    psi0, phi0 : float
        Initial precession and spin angles [rad] (arbitrary by symmetry).

    Returns
    -------
    ndarray, shape (8,)
    """
    psd = spin_rate if psi_dot is None else psi_dot
    y = np.zeros(N_STATE)
    if formulation == "euler":
        y[:7] = (theta0, theta_dot, psi0, psd, phi0, phi_dot, spin_rate)
        return y
    # q = qz(psi) qx(theta) qz(phi), the z-x-z sequence of Fig. 7
    a, b, c = 0.5 * psi0, 0.5 * theta0, 0.5 * phi0
    y[0] = math.cos(b) * math.cos(a + c)
    y[1] = math.sin(b) * math.cos(a - c)
    y[2] = math.sin(b) * math.sin(a - c)
    y[3] = math.cos(b) * math.sin(a + c)
    st, ct = math.sin(theta0), math.cos(theta0)
    sp, cp = math.sin(phi0), math.cos(phi0)
    y[4] = psd * st * sp + theta_dot * cp  # Eq. (13a)
    y[5] = psd * st * cp - theta_dot * sp  # Eq. (13b)
    y[6] = phi_dot + psd * ct  # Eq. (13c)
    y[7] = spin_rate
    return y
