"""The result of one run: :class:`NutationResult` (time series, t_cr, status, inputs).

:func:`obturator.solve.simulate` builds it from the integrator's raw solution;
it renders itself as a JSON-ready summary, an :class:`xarray.Dataset` or CSV.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from ._docs import field_docs
from ._provenance import package_version
from .model.case import Case
from .model.torques import CoulombContactFriction
from .status import Status

if TYPE_CHECKING:  # pragma: no cover
    import xarray

    from .solve import SolverOptions

__all__ = ["NutationResult", "case_inputs"]


def case_inputs(case: Case, options: SolverOptions) -> dict[str, object]:
    """Every input a run used, in SI units with the unit in the key (JSON-ready)."""
    ball = case.ball
    tq = case.torque
    out: dict[str, object] = {
        "ball_radius_m": ball.radius,
        "hole_radius_m": ball.hole_radius,
        "density_kg_m3": ball.density,
        "axial_inertia_C_kg_m2": ball.axial_inertia,
        "transverse_inertia_A_kg_m2": ball.transverse_inertia,
        "theta0_deg": math.degrees(case.theta0),
        "theta_cr_deg": math.degrees(case.opening_angle),
        "spin_rate_rad_s": case.spin_rate,
        "spin_mode": case.spin_mode,
        "projectile_inertia_kg_m2": case.projectile_inertia,
        "release_rate_rad_s": list(case.release_rate),
        "release_phase_rad": case.release_phase,
        "t_max_s": case.t_max,
    }
    if tq.viscous is not None:
        out["viscous_model"] = type(tq.viscous).__name__
        out["gap_m"] = tq.viscous.gap
        out["gap_viscosity_Pa_s"] = tq.viscous.viscosity
        out["shear_constant_S_N_m_s"] = tq.viscous.coefficient
    fr = tq.friction
    if fr is not None:
        out["friction_model"] = type(fr).__name__
        out["mu_s"] = fr.mu_s
        for attr, key in (
            ("weight", "normal_load_W_N"),
            ("pressure_force", "pressure_force_F_p_N"),
            ("normal_force", "normal_force_N"),
            ("contact_angle", "contact_angle_beta_rad"),
            ("n_contacts", "n_contacts"),
            ("patch_radius", "patch_radius_m"),
        ):
            if hasattr(fr, attr):
                out[key] = getattr(fr, attr)
    out["slip_speed_law"] = {
        "kind": tq.speed_law.kind,
        "ratio": tq.speed_law.ratio,
        "speed_m_s": tq.speed_law.speed,
    }
    out["solver"] = {
        "method": options.method,
        "rtol": options.rtol,
        "atol": options.atol,
        "friction_width": options.friction_width,
        "friction_family": options.friction_family,
        "formulation": options.formulation,
        "event_tol_s": options.event_tol,
    }
    out["obturator_version"] = package_version()
    return out


@field_docs
@dataclass(frozen=True)
class NutationResult:
    """Time history of one run and its opening time."""

    #: Times [s].
    t: np.ndarray
    #: Nutation angle theta, the z-x-z Euler angle of Fig. 7 [rad].
    theta: np.ndarray
    #: Precession angle psi (z-x-z, Fig. 7) [rad], unwrapped.
    psi: np.ndarray
    #: Spin angle phi of the ball (z-x-z, Fig. 7) [rad], unwrapped.
    phi: np.ndarray
    #: |omega_r|, relative angular speed ball vs projectile [rad/s] (Eq. 35).
    omega_r: np.ndarray
    #: |G|, magnitude of the applied torque [N m] (Eq. 62).
    torque: np.ndarray
    #: Kinetic energy of the ball [J].
    kinetic_energy: np.ndarray
    #: Projectile spin omega_p(t) [rad/s].
    spin_rate: np.ndarray
    #: Ball angular momentum about Z, H_Z [kg m^2/s].
    axial_momentum: np.ndarray
    #: omega_r . G [W]; never positive for dissipative torques.
    power: np.ndarray
    #: t_cr [s]; NaN if the bore did not open.
    opening_time: float
    #: ``OPENED`` (1), ``T_MAX`` (0), ``STEP_LIMIT`` (2) or ``FAILED`` (-1).
    status: Status
    #: Readable status.
    message: str
    #: Right-hand-side evaluations.
    nfev: int
    #: Jacobian evaluations (0 for the explicit methods).
    njev: int
    #: Accepted steps.
    n_steps: int
    #: Rejected steps.
    n_rejected: int
    #: The case that was integrated (geometry, inertia, friction, spin).
    case: Case = field(repr=False)
    #: The solver settings the run used.
    options: SolverOptions = field(repr=False)
    #: Raw state rows (layout per formulation).
    state: np.ndarray = field(repr=False)

    @property
    def success(self) -> bool:
        """True unless the integrator failed or hit its step limit."""
        return self.status in (Status.OPENED, Status.T_MAX)

    @property
    def opened(self) -> bool:
        """True when theta reached theta_cr."""
        return math.isfinite(self.opening_time)

    @property
    def jacobi_energy(self) -> np.ndarray:
        """T - omega_p H_Z [J]: non-increasing under dissipative torques at constant spin."""
        return self.kinetic_energy - self.spin_rate * self.axial_momentum

    @property
    def solver(self) -> str:
        """The integrator that ran: ``options.method``, or under ``"auto"`` the one it
        chose for this case (``"set-valued"``, no width; or ``"regularised"``;
        :mod:`obturator.solve.dispatch`)."""
        from .solve.dispatch import method_of

        return method_of(self.case, self.options)

    def summary(self) -> dict[str, object]:
        """Scalar results as a JSON-ready dict."""
        c = self.case
        fr = c.torque.friction
        return {
            "case": c.name,
            "t_cr_s": self.opening_time if self.opened else None,
            "theta_cr_deg": math.degrees(c.opening_angle),
            "theta0_deg": math.degrees(c.theta0),
            "spin_rate_rad_s": c.spin_rate,
            "mu_s": None if fr is None else fr.mu_s,
            "torque_model": (
                "none"
                if fr is None
                else "coulomb"
                if isinstance(fr, CoulombContactFriction)
                else "thesis"
            ),
            "spin_mode": c.spin_mode,
            "formulation": self.options.formulation,
            "method": self.options.method,
            "solver": self.solver,
            "rtol": self.options.rtol,
            "atol": self.options.atol,
            "friction_width": self.options.friction_width,
            "friction_family": self.options.friction_family,
            "status": int(self.status),
            "message": self.message,
            "nfev": self.nfev,
            "n_steps": self.n_steps,
            "inputs": case_inputs(c, self.options),
        }

    def to_xarray(self) -> xarray.Dataset:
        """Time series as an :class:`xarray.Dataset` with units in attributes."""
        import xarray as xr

        units = {
            "theta": "rad",
            "psi": "rad",
            "phi": "rad",
            "omega_r": "rad/s",
            "torque": "N m",
            "kinetic_energy": "J",
            "spin_rate": "rad/s",
            "axial_momentum": "kg m^2/s",
            "power": "W",
        }
        data = {k: ("t", getattr(self, k), {"units": u}) for k, u in units.items()}
        attrs = {k: ("" if v is None else v) for k, v in self.summary().items()}
        attrs["t_cr_s"] = self.opening_time
        return xr.Dataset(data, coords={"t": ("t", self.t, {"units": "s"})}, attrs=attrs)

    def to_csv(self, path: str) -> None:
        """Write the time series as CSV (SI units in the header)."""
        cols = [
            "t",
            "theta",
            "psi",
            "phi",
            "omega_r",
            "torque",
            "kinetic_energy",
            "spin_rate",
            "axial_momentum",
            "power",
        ]
        units = ["s", "rad", "rad", "rad", "rad/s", "N m", "J", "rad/s", "kg m^2/s", "W"]
        header = ",".join(f"{c} [{u}]" for c, u in zip(cols, units, strict=True))
        data = np.column_stack([getattr(self, c) for c in cols])
        np.savetxt(path, data, delimiter=",", header=header, comments="", fmt="%.10g")
