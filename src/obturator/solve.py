"""Solving the equations of motion: the only place integrators live.

:func:`simulate` integrates one :class:`Case` to the opening event
theta = theta_cr (thesis: theta_cr = beta_s) and returns a
:class:`NutationResult`; :func:`opening_time` returns t_cr alone (no time
series stored), which is what sweeps and fits call.

Numerics: at release the ball co-rotates, omega_r = 0, and the sliding-friction
direction is 0/0; near sticking the friction torque is extremely stiff. Only
the magnitude of the friction torque is regularised (width delta [rad/s], one
of three families; see :func:`obturator.dynamics.applied_torque`); the thesis's
moment arm always uses the true slip direction. Integration is compiled: an
explicit Dormand-Prince 8(5,3) pair by default, which hands the run to a
fifth-order Radau IIA method when it detects stiffness (Radau's Newton
iterations cope with the strongly nonlinear stiffness of near-stick phases);
Radau alone or an L-stable Rosenbrock pair can be chosen; the opening event
is located by re-stepping to 1e-12 s. :func:`convergence_check` reruns a case
with tighter tolerances, a narrower width and another regularisation family.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Literal

import numpy as np

from . import _rosenbrock as ros
from .dynamics import (
    FAMILY_ALGEBRAIC,
    FAMILY_LINEAR,
    FAMILY_TANH,
    FORM_EULER,
    FORM_QUATERNION,
    N_PARAM,
    N_STATE,
    P_FAMILY,
    P_SPEED,
    SPIN_CONSTANT,
    SPIN_FREE,
    SPIN_THESIS_ENERGY,
    observables,
)
from .errors import InputError, SolverError, check_range
from .geometry import BoredBall
from .torques import CoulombContactFriction, TorqueModel

if TYPE_CHECKING:  # pragma: no cover
    import xarray

__all__ = [
    "Case",
    "SolverOptions",
    "NutationResult",
    "simulate",
    "opening_time",
    "convergence_check",
    "ConvergenceCheck",
    "FRICTION_FAMILIES",
    "alternative_family",
    "case_inputs",
    "initial_state",
    "pack_parameters",
    "TABLE1_PROJECTILE_INERTIA",
]

#: Longest integration horizon accepted [s].
MAX_T_MAX = 1e4
#: Largest projectile spin accepted [rad/s].
MAX_SPIN_RATE = 1e6
#: Projectile moment of inertia about its axis I_p [kg m^2], thesis Table 1.
TABLE1_PROJECTILE_INERTIA = 8.58e-6

SpinMode = Literal["constant", "free", "thesis-energy"]
_SPIN_CODES = {"constant": SPIN_CONSTANT, "free": SPIN_FREE, "thesis-energy": SPIN_THESIS_ENERGY}
_FORMS = {"quaternion": FORM_QUATERNION, "euler": FORM_EULER}
_METHODS = ("auto", "radau", "rosenbrock")
FrictionFamily = Literal["algebraic", "tanh", "linear"]
#: Regularisation families of the Coulomb magnitude (see dynamics.slip_saturation).
FRICTION_FAMILIES: dict[str, int] = {
    "algebraic": FAMILY_ALGEBRAIC,
    "tanh": FAMILY_TANH,
    "linear": FAMILY_LINEAR,
}


def _auto_integrate(*args):
    """DOP853 first; if it reports stiffness, the whole run again with Radau IIA."""
    from . import _dop853, _radau

    out = _dop853.integrate(*args)
    if int(out[0]) != _dop853.STATUS_STIFF:
        return out
    rad = _radau.integrate(*args)
    return (*rad[:5], rad[5] + out[5], *rad[6:])


def _integrator(method: str):
    if method == "auto":
        return _auto_integrate
    if method == "radau":
        from . import _radau

        return _radau.integrate
    return ros.integrate


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
    projectile_inertia: float = TABLE1_PROJECTILE_INERTIA
    theta_cr: float | None = None
    t_max: float = 5.0
    name: str = ""
    release_rate: tuple[float, float, float] = (0.0, 0.0, 0.0)
    release_phase: float = 0.0

    def __post_init__(self) -> None:
        # 1e6 rad/s: 80 times a 20 mm round's ~1.2e4 rad/s; a steel ball bursts far below
        check_range("spin_rate", self.spin_rate, 0.0, MAX_SPIN_RATE, lo_open=True, unit="rad/s")
        check_range("theta0", math.degrees(self.theta0), 0.0, 90.0, lo_open=True, unit="deg")
        if self.spin_mode not in _SPIN_CODES:
            raise InputError("spin_mode", f"{self.spin_mode!r}; allowed: {', '.join(_SPIN_CODES)}")
        check_range(
            "projectile_inertia",
            self.projectile_inertia,
            0.0,
            math.inf,
            lo_open=True,
            unit="kg m^2",
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

    def initial_state(self, formulation: str = "quaternion") -> np.ndarray:
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


@dataclass(frozen=True)
class SolverOptions:
    """Integrator settings.

    Parameters
    ----------
    rtol : float
        Relative tolerance, in [1e-12, 0.1) (smaller values cannot be honoured
        in double precision by the integrators' error norms).
    atol : float
        Absolute tolerance on the quaternion components and on rates measured
        in units of the initial spin omega_p0 (so it is scale-free).
    friction_width : float
        Regularisation width of the Coulomb magnitude, relative to the initial
        spin: delta = friction_width * omega_p0 [rad/s]. Default 1e-7: t_cr
        converges about linearly in delta, and at low spin (long near-stick
        phases, e.g. 40-100 rad/s on the rig) 1e-6 still leaves ~1e-3
        relative; 1e-7 leaves <= 2e-4 there (tests/test_convergence.py). Keep
        ``atol`` well below the width (both are in units of omega_p0): the
        integrator must resolve slip speeds of order delta.
    friction_family : {"algebraic", "tanh", "linear"}
        Shape of the regularised magnitude s(|omega_r|/delta):
        x/sqrt(1+x^2) (default), tanh(x) or min(x, 1). Only the magnitude is
        regularised; the thesis's moment arm always uses the true slip
        direction. :func:`convergence_check` reruns with another family.
    formulation : {"quaternion", "euler"}
        Singularity-free quaternion form (default) or the thesis's Euler angles.
    max_steps : int
        Step limit (status 2 when reached).
    event_tol : float
        Bracket width at which the opening time is accepted [s].
    max_step : float or None
        Largest step [s]; default a tenth of a spin period.
    method : {"auto", "radau", "rosenbrock"}
        Compiled integrator. ``"auto"`` (default): the explicit eighth-order
        Dormand-Prince pair DOP853 (no Jacobian; the problem is not stiff
        outside sticking; t_cr errors ~1e-9 relative at rtol 1e-8), rerun from
        the start with Radau IIA when DOP853 reports stiffness (more than 200
        steps per spin period plus 1000, as in sticking phases, or a step size
        collapse); nfev then counts both runs. ``"radau"``: the fifth-order
        Radau IIA collocation method (Newton iterations follow the nonlinear
        stiffness of sticking, 8-15x faster than Rosenbrock on the thesis cases
        and ~1e2-1e4x fewer steps in long sticking phases). ``"rosenbrock"``:
        the L-stable Rosenbrock pair of Shampine (ode23s). Radau transforms rtol as RADAU5 does
        (0.1 rtol^(2/3)); t_cr errors stay below ~3e-7 relative at rtol 1e-8.
    """

    rtol: float = 1e-8
    atol: float = 1e-10
    friction_width: float = 1e-7
    friction_family: FrictionFamily = "algebraic"
    formulation: Literal["quaternion", "euler"] = "quaternion"
    max_steps: int = 20_000_000
    event_tol: float = 1e-12
    max_step: float | None = None
    method: Literal["auto", "radau", "rosenbrock"] = "auto"

    def __post_init__(self) -> None:
        # DOP853 works at 0.01 rtol, floored at 1e-14: a smaller rtol would be clamped.
        check_range("rtol", self.rtol, 1e-12, 0.1, hi_open=True)
        check_range("atol", self.atol, 0.0, 1.0, lo_open=True)
        check_range("friction_width", self.friction_width, 0.0, 1.0, lo_open=True)
        if self.friction_family not in FRICTION_FAMILIES:
            raise InputError(
                "friction_family",
                f"{self.friction_family!r}; allowed: {', '.join(FRICTION_FAMILIES)}",
            )
        if self.formulation not in _FORMS:
            raise InputError("formulation", f"{self.formulation!r}; allowed: quaternion, euler")
        if int(self.max_steps) < 1:
            raise InputError("max_steps", f"{self.max_steps} is outside the allowed range >= 1")
        check_range("event_tol", self.event_tol, 0.0, 1e-3, lo_open=True, unit="s")
        if self.method not in _METHODS:
            raise InputError("method", f"{self.method!r}; allowed: {', '.join(_METHODS)}")
        if self.max_step is not None:
            check_range("max_step", self.max_step, 0.0, math.inf, lo_open=True, unit="s")

    def tighter(self, factor: float = 10.0) -> SolverOptions:
        """Both tolerances divided by `factor` (for convergence studies)."""
        return replace(self, rtol=self.rtol / factor, atol=self.atol / factor)


def initial_state(
    theta0: float,
    spin_rate: float,
    *,
    formulation: str = "quaternion",
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


def pack_parameters(case: Case, options: SolverOptions, y0: np.ndarray | None = None) -> np.ndarray:
    """Flat float parameter vector for the compiled right-hand side."""
    ball = case.ball
    a, c = ball.transverse_inertia, ball.axial_inertia
    form = _FORMS[options.formulation]
    if y0 is None:
        y0 = case.initial_state(options.formulation)
    p = np.zeros(N_PARAM)
    p[0], p[1], p[2] = a, c, case.projectile_inertia
    p[3] = _SPIN_CODES[case.spin_mode]
    p[5] = form
    p[6] = options.friction_width * case.spin_rate
    p[7] = case.opening_angle
    p[8:18] = case.torque.pack()
    p[P_SPEED : P_SPEED + 3] = case.torque.speed_law.pack()
    p[P_FAMILY] = FRICTION_FAMILIES[options.friction_family]
    # total kinetic energy for the thesis's energy form (Appendix A, C(4))
    p[4] = 0.0
    obs = observables(y0[None, :], p)
    p[4] = obs[0, 5] + 0.5 * case.projectile_inertia * case.spin_rate**2
    return p


def _scale(case: Case, formulation: str) -> np.ndarray:
    w = case.spin_rate
    if formulation == "euler":
        return np.array([1.0, w, 1.0, w, 1.0, w, w, 1.0])
    return np.array([1.0, 1.0, 1.0, 1.0, w, w, w, w])


_STATUS_MESSAGES = {
    ros.STATUS_OPENED: "The bore opened: theta reached theta_cr.",
    ros.STATUS_T_MAX: "Reached t_max before the bore opened.",
    ros.STATUS_MAX_STEPS: "Step limit reached before the bore opened or t_max.",
    ros.STATUS_FAILED: "Integration failed: step size underflow or non-finite state.",
}


def case_inputs(case: Case, options: SolverOptions) -> dict[str, object]:
    """Every input a run used, in SI units with the unit in the key (JSON-ready)."""
    from importlib.metadata import PackageNotFoundError, version

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
    try:
        out["obturator_version"] = version("obturator")
    except PackageNotFoundError:  # pragma: no cover
        out["obturator_version"] = "0+unknown"
    return out


@dataclass(frozen=True)
class NutationResult:
    """Time history of one run and its opening time.

    Attributes
    ----------
    t : ndarray
        Times [s].
    theta, psi, phi : ndarray
        Euler angles (z-x-z, Fig. 7) [rad]; psi and phi unwrapped.
    omega_r : ndarray
        |omega_r|, relative angular speed ball vs projectile [rad/s] (Eq. 35).
    torque : ndarray
        |G|, magnitude of the applied torque [N m] (Eq. 62).
    kinetic_energy : ndarray
        Kinetic energy of the ball [J].
    spin_rate : ndarray
        Projectile spin omega_p(t) [rad/s].
    axial_momentum : ndarray
        Ball angular momentum about Z, H_Z [kg m^2/s].
    power : ndarray
        omega_r . G [W]; never positive for dissipative torques.
    opening_time : float
        t_cr [s]; NaN if the bore did not open.
    status : int
        1 opened, 0 reached t_max, 2 step limit, -1 failure.
    message : str
        Readable status.
    nfev, njev, n_steps, n_rejected : int
        Right-hand-side and Jacobian evaluations, accepted and rejected steps.
    case : Case
    options : SolverOptions
    state : ndarray
        Raw state rows (layout per formulation).
    """

    t: np.ndarray
    theta: np.ndarray
    psi: np.ndarray
    phi: np.ndarray
    omega_r: np.ndarray
    torque: np.ndarray
    kinetic_energy: np.ndarray
    spin_rate: np.ndarray
    axial_momentum: np.ndarray
    power: np.ndarray
    opening_time: float
    status: int
    message: str
    nfev: int
    njev: int
    n_steps: int
    n_rejected: int
    case: Case = field(repr=False)
    options: SolverOptions = field(repr=False)
    state: np.ndarray = field(repr=False)

    @property
    def success(self) -> bool:
        """True unless the integrator failed or hit its step limit."""
        return self.status in (ros.STATUS_OPENED, ros.STATUS_T_MAX)

    @property
    def opened(self) -> bool:
        """True when theta reached theta_cr."""
        return math.isfinite(self.opening_time)

    @property
    def jacobi_energy(self) -> np.ndarray:
        """T - omega_p H_Z [J]: non-increasing under dissipative torques at constant spin."""
        return self.kinetic_energy - self.spin_rate * self.axial_momentum

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
            "rtol": self.options.rtol,
            "atol": self.options.atol,
            "friction_width": self.options.friction_width,
            "friction_family": self.options.friction_family,
            "status": self.status,
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


def _run(
    case: Case,
    options: SolverOptions,
    y0: np.ndarray | None,
    record: bool,
    t_eval: np.ndarray | None,
    terminal: bool,
):
    if y0 is None:
        y0 = case.initial_state(options.formulation)
    y0 = np.asarray(y0, dtype=float)
    if y0.shape != (N_STATE,):
        raise InputError("y0", f"expected shape ({N_STATE},), got {y0.shape}")
    p = pack_parameters(case, options, y0)
    period = 2.0 * math.pi / case.spin_rate
    h_max = options.max_step if options.max_step is not None else 0.1 * period
    h0 = 1e-4 * period
    te = np.empty(0) if t_eval is None else np.asarray(t_eval, dtype=float)
    if te.size and (np.any(np.diff(te) < 0) or te[0] < 0):
        raise InputError("t_eval", "times must be non-negative and increasing")
    out = _integrator(options.method)(
        y0,
        p,
        float(case.t_max),
        options.rtol,
        options.atol,
        _scale(case, options.formulation),
        h0,
        h_max,
        int(options.max_steps),
        te,
        record,
        terminal,
        options.event_tol,
    )
    return p, out


def simulate(
    case: Case,
    options: SolverOptions | None = None,
    *,
    y0: np.ndarray | None = None,
    t_eval: np.ndarray | None = None,
    terminal: bool = True,
) -> NutationResult:
    """Integrate one case and return its time history and opening time t_cr.

    Parameters
    ----------
    case : Case
    options : SolverOptions, optional
    y0 : ndarray, optional
        Initial state (see :func:`initial_state`); default: co-rotating release.
    t_eval : array_like, optional
        Output times [s] (dense output); default: every accepted step.
    terminal : bool
        Stop at the opening event (default) or continue to ``case.t_max``.

    Returns
    -------
    NutationResult
    """
    options = options or SolverOptions()
    p, out = _run(case, options, y0, True, t_eval, terminal)
    status, t_event, _, ts, ys, nfev, njev, n_steps, n_rej, _, _ = out
    obs = observables(ys, p) if len(ts) else np.empty((0, 11))
    return NutationResult(
        t=ts,
        theta=obs[:, 0],
        psi=np.unwrap(obs[:, 1]),
        phi=np.unwrap(obs[:, 2]),
        omega_r=obs[:, 3],
        torque=obs[:, 4],
        kinetic_energy=obs[:, 5],
        spin_rate=obs[:, 6],
        axial_momentum=obs[:, 7],
        power=obs[:, 8],
        opening_time=float(t_event),
        status=int(status),
        message=_STATUS_MESSAGES[int(status)],
        nfev=int(nfev),
        njev=int(njev),
        n_steps=int(n_steps),
        n_rejected=int(n_rej),
        case=case,
        options=options,
        state=ys,
    )


def opening_time(case: Case, options: SolverOptions | None = None) -> float:
    """Opening time t_cr [s] of a case (NaN if it does not open by ``case.t_max``).

    Stores no time series; this is the call sweeps and fits make.

    Raises
    ------
    SolverError
        If the integrator fails or reaches its step limit (a RuntimeError).
    """
    options = options or SolverOptions()
    _, out = _run(case, options, None, False, None, True)
    status = int(out[0])
    if status in (ros.STATUS_FAILED, ros.STATUS_MAX_STEPS):
        raise SolverError(f"{case.name or 'case'}: {_STATUS_MESSAGES[status]}")
    return float(out[1])


def alternative_family(family: str) -> str:
    """The family a convergence check compares with: "linear" for the smooth
    families (the most different shape: it reaches full friction at a finite
    slip), "algebraic" for "linear"."""
    return "algebraic" if family == "linear" else "linear"


@dataclass(frozen=True)
class ConvergenceCheck:
    """t_cr re-computed with tighter tolerances, a narrower width and another family.

    A width study alone cannot reveal a regularisation that converges to the
    wrong limit (each family looks converged as its own width shrinks); a
    second family with a different shape can. t_cr counts as converged only
    when all three reruns agree with it.

    Attributes
    ----------
    opening_time : float
        t_cr with the given options [s] (NaN if it did not open).
    tighter_tolerance : float
        t_cr with rtol and atol divided by `factor` [s].
    narrower_width : float
        t_cr with ``friction_width`` divided by `factor` [s] (tolerances
        divided by `factor` too, so slip speeds of order delta stay resolved).
    other_family : float
        t_cr with ``friction_family`` replaced by `family` [s].
    family : str
        The family of that rerun.
    factor : float
        Refinement factor (10 by default).
    threshold : float
        Largest relative change accepted as converged.
    """

    opening_time: float
    tighter_tolerance: float
    narrower_width: float
    other_family: float
    family: str
    factor: float
    threshold: float

    @staticmethod
    def _rel(a: float, b: float) -> float:
        if math.isnan(a) and math.isnan(b):
            return 0.0  # both "did not open by t_max"
        if math.isnan(a) or math.isnan(b):
            return math.inf
        return abs(b - a) / abs(a)

    @property
    def tolerance_change(self) -> float:
        """|t_tight - t| / t [-] (0 when neither run opened, inf when only one did)."""
        return self._rel(self.opening_time, self.tighter_tolerance)

    @property
    def width_change(self) -> float:
        """|t_narrow - t| / t [-]."""
        return self._rel(self.opening_time, self.narrower_width)

    @property
    def family_change(self) -> float:
        """|t_family - t| / t [-]."""
        return self._rel(self.opening_time, self.other_family)

    @property
    def converged(self) -> bool:
        """All three changes below the threshold."""
        return max(self.tolerance_change, self.width_change, self.family_change) < self.threshold

    def to_dict(self) -> dict[str, object]:
        """JSON-ready summary (None for NaN/inf)."""

        def clean(x: float) -> float | None:
            return x if math.isfinite(x) else None

        return {
            "converged": self.converged,
            "tolerance_rel_change": clean(self.tolerance_change),
            "width_rel_change": clean(self.width_change),
            "family_rel_change": clean(self.family_change),
            "t_cr_tighter_tolerance_s": clean(self.tighter_tolerance),
            "t_cr_narrower_width_s": clean(self.narrower_width),
            "t_cr_other_family_s": clean(self.other_family),
            "other_family": self.family,
            "factor": self.factor,
            "threshold": self.threshold,
        }


def convergence_check(
    case: Case,
    options: SolverOptions | None = None,
    *,
    factor: float = 10.0,
    threshold: float = 1e-3,
    opening_time_s: float | None = None,
    family: str | None = None,
) -> ConvergenceCheck:
    """Recompute t_cr with tighter tolerances, a narrower width and another family.

    Parameters
    ----------
    case : Case
    options : SolverOptions, optional
        The options whose result is being checked.
    factor : float
        Refinement factor for (rtol, atol) and for ``friction_width``.
    threshold : float
        Relative change below which t_cr counts as converged.
    opening_time_s : float, optional
        t_cr already computed with `options` [s] (saves one run).
    family : str, optional
        Regularisation family of the third rerun; default
        :func:`alternative_family` of ``options.friction_family``.
    """
    options = options or SolverOptions()
    family = alternative_family(options.friction_family) if family is None else family
    if family not in FRICTION_FAMILIES:
        raise InputError("family", f"{family!r}; allowed: {', '.join(FRICTION_FAMILIES)}")
    t0 = opening_time(case, options) if opening_time_s is None else float(opening_time_s)
    t1 = opening_time(case, options.tighter(factor))
    narrow = replace(options.tighter(factor), friction_width=options.friction_width / factor)
    t2 = opening_time(case, narrow)
    t3 = opening_time(case, replace(options, friction_family=family))
    return ConvergenceCheck(t0, t1, t2, t3, family, factor, threshold)
