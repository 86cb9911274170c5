"""One registry of the physical parameters: name, unit, long name, range, config key, fit.

Every table that used to list parameters with their units (config schema, case
factory arguments, sweep axes, command-line flags, calibration parameters) is
read from :data:`PARAMS`. Units are written as in CF/UDUNITS (``"1"`` for a pure
number, ``"Pa s"``); :attr:`Param.pint_unit` is the same unit for
:func:`obturator.units.parse_quantity`.

>>> PARAMS["theta0_deg"].unit, PARAMS["theta0_deg"].config
('deg', 'theta0')
>>> sorted(SWEEP_PARAMS)[:3]
['altitude_m', 'density', 'gap']
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Literal

from ._docs import field_docs
from .reference import TABLE1

__all__ = [
    "Range",
    "MIN_HOLE_FRACTION",
    "FitSpec",
    "Transform",
    "Param",
    "PARAMS",
    "SWEEP_PARAMS",
    "FIT_PARAMS",
    "FIT_SPECS",
    "CONFIG_SECTIONS",
    "config_schema",
]


@dataclass(frozen=True)
class Range:
    """Allowed values lo .. hi (each end open or closed)."""

    lo: float = -math.inf
    hi: float = math.inf
    lo_open: bool = False
    hi_open: bool = False

    def contains(self, x: float) -> bool:
        """True when x lies in the range."""
        above = x > self.lo if self.lo_open else x >= self.lo
        below = x < self.hi if self.hi_open else x <= self.hi
        return above and below

    def __str__(self) -> str:
        left, right = "(" if self.lo_open else "[", ")" if self.hi_open else "]"
        return f"{left}{self.lo:g}, {self.hi:g}{right}"


Transform = Literal["linear", "log10"]


@field_docs
@dataclass(frozen=True)
class FitSpec:
    """How a fit treats a parameter: start, bounds, transform, and why the bounds."""

    #: Default starting value of a fit [the parameter's unit].
    start: float
    #: Hard bounds of every fit (calibration and validation alike): where the model is still defined
    #: and cheap, argued in `reason`.
    bounds: tuple[float, float]
    #: The physically argued range inside `bounds`; a fitted value outside it is reported as the
    #: data asking for more than the mechanism can give.
    plausible: tuple[float, float]
    #: Why the bounds and the plausible range are what they are (physics and the thesis's chapter,
    #: page, figure or equation).
    reason: str
    #: The optimiser's variable, ``"linear"`` (value / scale) or ``"log10"`` (log10(value), for
    #: scale parameters spanning decades).
    transform: Transform = "linear"
    #: Typical size (linear transform): the optimiser's variable is O(1).
    scale: float = 1.0


@field_docs
@dataclass(frozen=True)
class Param:
    """One physical parameter."""

    #: Canonical field name (config files, Python keywords, ``--flag-name``).
    name: str
    #: SI unit, CF style (``"1"``: a pure number).
    unit: str
    #: Description with the thesis's symbol (NetCDF ``long_name``, help texts).
    long_name: str
    #: Key in a TOML config, ``"section.key"`` or a top-level ``"key"``.
    config: str | None = None
    #: Allowed values of a swept or sampled input (the case factories check combined limits, such as
    #: theta_0 above the opening angle, themselves).
    range: Range | None = None
    #: May be swept or sampled by :mod:`obturator.sweeps`.
    sweep: bool = False
    #: Applies to the flight case only.
    flight_only: bool = False
    #: Fittable (by :mod:`obturator.fitting`, in calibration and validation): start, bounds and
    #: their reason, transform (table :data:`FIT_SPECS`).
    fit: FitSpec | None = None

    @property
    def pint_unit(self) -> str:
        """The unit in pint syntax (``""`` for a pure number)."""
        return "" if self.unit == "1" else self.unit.replace(" ", "*")


_R_S = TABLE1["ball_radius"]
_POSITIVE = Range(0.0, math.inf, True, True)

#: Smallest hole radius over ball radius, r_s / R_s, of a case that is run. The bore is
#: what makes the ball's inertia unequal: lambda = C/A - 1 = 1.25 (r_s/R_s)^2 to first
#: order (Eqs. 10b, 11 expanded in r_s^2; Table 1: 0.41), and the gyroscopic moment
#: that turns the hole towards the spin axis vanishes with lambda (a solid sphere has
#: no preferred axis, Eq. 5). The large-spin opening time's low-spin term grows as
#: (lambda + 1)/lambda (T1 of Eq. 93): at r_s = R_s/10 it is 81, 24 times Table 1's
#: 3.4; below it the ball sticks to its seat for ever longer, the set-valued solver
#: steps through ever more stick-slip cycles (a 0.1 mm or 4 um hole ran for minutes
#: past 1 GB), and the bore passes under 1 % of the ball's cross-section, no longer an
#: obturator's bore. Geometry (:class:`obturator.model.geometry.BoredBall`) still takes
#: any hole from 0 (the solid sphere); a case refuses one below this.
MIN_HOLE_FRACTION = 0.1

_PHYSICAL: tuple[Param, ...] = (
    # 1 rad/s to the case factories' 1e6 rad/s: below ~1 rad/s the integrators' step
    # control, scaled by the spin period, degenerates (a run stalls; far below, Radau
    # IIA divides by zero); the rig's slowest run is 42 rad/s (Appendix B)
    Param("spin_rate", "rad/s", "projectile spin rate omega_p", "spin_rate", Range(1.0, 1e6), True),
    Param("mu_s", "1", "sliding friction coefficient mu_s", "mu_s", Range(0.0, 2.0), True),
    Param(
        "theta0_deg",
        "deg",
        "initial nutation angle theta_0",
        "theta0",
        Range(0.0, 90.0, True, False),
        True,
    ),
    Param("density", "kg/m^3", "ball density rho", "ball.density", _POSITIVE, True),
    Param(
        "hole_radius",
        "m",
        "ball hole radius r_s",
        "ball.hole_radius",
        Range(MIN_HOLE_FRACTION * _R_S, _R_S / math.sqrt(2.0), False, True),
        True,
    ),
    Param("gap", "m", "ball-socket gap h", "gap.width", Range(0.0, _R_S, True, True), True),
    Param(
        "mach",
        "1",
        "flight Mach number M_1",
        "flight.mach",
        Range(1.0, math.inf, False, True),
        True,
        True,
    ),
    Param(
        "altitude_m",
        "m",
        "flight altitude (US 1976 atmosphere)",
        "flight.altitude",
        Range(0.0, 86_000.0),
        True,
        True,
    ),
    Param("ball_radius", "m", "ball radius R_s", "ball.radius", _POSITIVE),
    Param("viscosity", "Pa s", "gap-fluid viscosity mu_f", "gap.viscosity", _POSITIVE),
    Param("weight", "N", "normal load on the rig W", "rig.weight"),
    Param("patch_radius", "m", "contact patch radius a", "contact.patch_radius"),
    Param("p1", "Pa", "free-stream pressure P_1", "flight.p1"),
    Param("bore_radius", "m", "bore radius r_p", "flight.bore_radius", _POSITIVE),
    # launch inputs of the envelope studies (obturator.envelope: trajectory.Launch);
    # spin_factor scales the nominal muzzle spin (the rifling's twist): 0-10 covers any
    # dispersion of muzzle velocity; the temperature offset spans the cold and hot
    # standard days of MIL-STD-210 around the US 1976 atmosphere
    Param("spin_factor", "1", "muzzle spin / nominal muzzle spin", None, Range(0.0, 10.0, True)),
    Param(
        "temperature_offset_k",
        "K",
        "off-standard temperature Delta T",
        None,
        Range(-80.0, 60.0),
    ),
    Param("elevation_deg", "deg", "elevation angle", None, Range(-90.0, 90.0)),
    Param("pressure_force", "N", "pressure force on the ball F_p"),
    Param("t_max", "s", "integration horizon t_max", "t_max"),
    Param("rtol", "1", "relative tolerance", "solver.rtol"),
    Param("atol", "1", "absolute tolerance (rates in omega_p0)", "solver.atol"),
    Param("fixed_step", "s", "step of method moreau-jean", "solver.fixed_step"),
    Param(
        "friction_width",
        "1",
        "friction regularisation width / omega_p0",
        "solver.friction_width",
    ),
    Param("shear_constant", "N m s", "viscous shear constant S (Eq. 42)"),
    # mechanisms of the validation study (obturator.validation): release
    # transient, slip-speed law of mu, release phase (ranges argued in FIT_SPECS)
    Param(
        "theta_dot0",
        "rad/s",
        "release rate theta_dot_0 (spin rig)",
        "release.theta_dot",
        Range(-1e3, 1e3),
        True,
    ),
    Param(
        "speed_ratio",
        "1",
        "slip-speed law ratio r (spin rig, with speed_law)",
        "friction.speed_ratio",
        Range(0.0, 1.0, True, False),
        True,
    ),
    Param(
        "slip_speed",
        "m/s",
        "slip-speed law reference speed v_s (spin rig, with speed_law)",
        "friction.slip_speed",
        Range(0.0, 100.0, True, False),
        True,
    ),
    Param(
        "release_phase",
        "rad",
        "release phase psi_0 (spin rig)",
        "release.phase",
        Range(-2.0 * math.pi, 2.0 * math.pi),
        True,
    ),
    Param("phi_dot0", "rad/s", "release spin rate phi_dot_0 about the hole axis (spin rig)"),
    # contact ageing of the lucite seat (obturator.model.ageing)
    Param("ageing_rate", "1", "contact ageing rate b of the static friction (spin rig)"),
    Param("ageing_time", "s", "contact ageing cut-off time tau (spin rig)"),
    # a run's ball mass (spin-rig data files): the load W = m g
    Param("ball_mass", "kg", "ball mass m (spin rig: load W = m g)", None, _POSITIVE),
    Param("psi_dot0", "rad/s", "release precession rate psi_dot_0 - omega_p (spin rig)"),
)

_RATE_BOUND = 20.0  # rad/s, fit bounds of the three release rates (argued at theta_dot0)
_RATE_PLAUSIBLE = (-1.5, 1.5)  # rad/s

#: Fit start, bounds, physical range and transform of every fittable parameter,
#: one row each, with the argument for the bounds. Calibration
#: (:func:`obturator.calibration.fit_exact`) and validation
#: (:mod:`obturator.validation`) both fit through :mod:`obturator.fitting`,
#: which reads this table only.
FIT_SPECS: dict[str, FitSpec] = {
    "mu_s": FitSpec(
        0.55,
        (0.1, 1.5),
        (0.2, 1.0),
        "Dry sliding of the steel ball on the rig's lucite (PMMA) seat. The thesis "
        "started from 0.35 for laminated plastic on steel (chapter V, ref. [27]) and "
        "fitted 0.5473 (chapter IV, Eqs. 95-96); handbook values for PMMA or laminated "
        "plastics on steel span about 0.2-0.8 (static values at the top). Plausible: "
        "0.2-1.0. Bounds 0.1-1.5: below 0.1 no dry polymer-on-steel pair slides, and the "
        "rig would open after T2 omega_p = 3.03e-4 / mu omega_p (Eq. 95) > 1.3 s at "
        "446 rad/s, near the calibration's 5 s horizon at the slow runs; 1.5 is twice "
        "the highest handbook static value.",
    ),
    "theta0_deg": FitSpec(
        TABLE1["theta0_deg"],
        (80.0, 89.9),
        (86.25, 88.25),
        "Initial nutation set by centring the laser reflection from a polished spot on "
        "the ball (chapter III.B, Figs. 29-31); the thesis states theta_0 = 87.25 deg "
        "'could only vary by +-1 deg' (chapter IV, p. 97). Plausible: the stated "
        "86.25-88.25 deg. The reflection measures the spot's normal, not the hole axis, "
        "so a larger offset is conceivable but undocumented; the fit is allowed 80 deg "
        "(7 times the stated tolerance) to show what the data want, and at most 89.9 deg: "
        "at 90 deg the hole axis is square to the spin axis, an equilibrium from which "
        "t_cr grows without bound.",
        scale=10.0,
    ),
    "theta_dot0": FitSpec(
        -1.0,
        (-_RATE_BOUND, _RATE_BOUND),
        _RATE_PLAUSIBLE,
        "Nutation rate at release (negative: towards opening). The holding jet "
        "(chapter III.B, Figs. 26-27) is cut by the retracting plunger; the plunger "
        "never touches the ball. Upper bound: a jet force of about 0.04 N (air at "
        "~100 m/s through a ~2 mm nozzle) acting fully tangentially at R_s for a 10 ms "
        "decay gives 0.04 x 7.9e-3 x 0.01 / A = 14 rad/s (A = 2.2e-7 kg m^2): bounds "
        "+-20 rad/s. A jet on a sphere pushes along the normal, through the centre: only "
        "surface shear and the hole edge give a moment, of order 10 % of that. "
        "Plausible: |theta_dot_0| <= 1.5 rad/s.",
    ),
    "phi_dot0": FitSpec(
        1.0,
        (-_RATE_BOUND, _RATE_BOUND),
        _RATE_PLAUSIBLE,
        "Spin about the hole axis at release, left by the holding jet (chapter III.B); "
        "bounds and range as theta_dot0.",
    ),
    "psi_dot0": FitSpec(
        1.0,
        (-_RATE_BOUND, _RATE_BOUND),
        _RATE_PLAUSIBLE,
        "Precession rate relative to the rig at release, psi_dot_0 - omega_p, left by "
        "the holding jet (chapter III.B); bounds and range as theta_dot0.",
    ),
    "release_phase": FitSpec(
        1.0,
        (0.0, math.pi),
        (0.0, math.pi),
        "psi_0, azimuth of the line of nodes relative to gravity (-X) at release. The "
        "switch is thrown at an arbitrary instant (chapter III.B), so psi_0 is really "
        "uniform per run; a single fitted psi_0 tests whether the data prefer a phase at "
        "all. The rig friction depends on (w_X)^2 (Eq. 61), so psi_0 and psi_0 + pi are "
        "alike: 0-pi covers all phases.",
    ),
    "speed_ratio": FitSpec(
        0.5,
        (0.02, 1.0),
        (0.2, 1.0),
        "r of SlipSpeedLaw: friction at one end of the slip-speed range over mu_s at the "
        "other (weakening: kinetic/static; strengthening: at-rest/fast); 1 is the "
        "thesis's one mu at every slip speed (Eq. 61), 0.02 a fifty-fold change. "
        "Polymer-on-steel friction changes by up "
        "to a factor of a few over several decades of sliding speed (viscoelastic and "
        "ploughing contributions; Stribeck curves of boundary lubrication likewise). "
        "Plausible: 0.2-1.",
    ),
    "slip_speed": FitSpec(
        0.1,
        (1e-3, 5.0),
        (0.01, 1.0),
        "v_s of SlipSpeedLaw, the slip speed of the transition. The rig's slip speeds "
        "R_s |omega_r| run from 0 at stick to about R_s omega_p = 0.6-3.5 m/s "
        "(78-446 rad/s, Appendix B); bounds 1 mm/s-5 m/s span them with margin, and a "
        "transition the data can see lies inside 0.01-1 m/s. Fitted in log10.",
        transform="log10",
    ),
    "patch_radius": FitSpec(
        2.7867796851585276e-4,
        (5e-5, 2e-3),
        (1.5e-4, 6e-4),
        "Radius a of the contact patch of the Coulomb model (pivot friction "
        "3 pi a / 16 mu N). Start: the Hertz radius of the steel ball in the lucite seat "
        "under W with the Table 1 gap, 0.279 mm (chapter III, Fig. 22; "
        "model.torques.hertz_patch_radius); a ~ (R*/E*)^(1/3) moves by +-15 % for "
        "E(PMMA) 2.4-3.3 GPa and by +-25 % for a gap 50 % off; roughness and seat "
        "out-of-roundness spread it further. Plausible: 0.15-0.6 mm; bounds 0.05-2 mm, "
        "a sixth to seven times Hertz.",
        scale=1e-4,
    ),
    "ageing_rate": FitSpec(
        0.02,
        (0.0, 0.1),
        (0.0, 0.05),
        "b of the contact ageing law mu_static = mu_s + b ln(1 + t_d/tau) "
        "(obturator.model.ageing) of the steel ball on the rig's lucite seat (chapter "
        "III.A): static friction of a dry contact grows with the "
        "logarithm of its age as the asperity contacts creep (Dieterich 1972, J. Geophys. "
        "Res. 77; for PMMA, the rig's lucite: Dieterich and Kilgore 1994, Pure Appl. "
        "Geophys. 143; Berthoud et al. 1999, Phys. Rev. B 59), with b of order 1e-2. "
        "Plausible 0-0.05 (up to five times that for a loaded, rough seat); bounds 0 (no "
        "ageing: the thesis's law) to 0.1, where the friction at rest would exceed mu_s "
        "by 0.75 at 38 rad/s with tau = 1 us.",
    ),
    "ageing_time": FitSpec(
        1e-4,
        (1e-6, 10.0),
        (1e-5, 1e-1),
        "tau of the contact ageing law, the cut-off time below which a contact has not "
        "aged. The seat's contact time per pass of the patch, t_d = 2 a / (R_s omega_p) "
        "with a the Hertz radius of the bottom contact (chapter III, Fig. 22), "
        "is 0.16-0.9 ms over the rig's 78-446 rad/s, so a tau far above it leaves only "
        "b t_d/tau (b and tau then not separately identified) and one far below it a "
        "spin-independent offset of mu. Published cut-off times of polymer ageing are "
        "short and poorly constrained; plausible 10 us-0.1 s, bounds 1 us-10 s. "
        "Fitted in log10.",
        transform="log10",
    ),
    "shear_constant": FitSpec(
        TABLE1["shear_constant"],
        (0.0, 2e-7),
        (6e-9, 2.5e-8),
        "S of the viscous torque, Eq. (42): Table 1 gives 12.38e-9 N m s (air, "
        "mu_f = 1.917e-5 Pa s, h = 50.8 um). S is proportional to mu_f (1.7-2.0e-5 "
        "Pa s for air at 0-60 C) and grows as the gap narrows; plausible: half to twice "
        "Table 1. Bounds 0 (no viscous torque) to 2e-7, 16 times Table 1, where the "
        "viscous torque would rival the friction at the slow runs.",
        scale=1e-8,
    ),
}

#: Every physical parameter, by name (fittable ones carry their row of FIT_SPECS).
PARAMS: dict[str, Param] = {p.name: replace(p, fit=FIT_SPECS.get(p.name)) for p in _PHYSICAL}

#: Parameters a sweep or Monte Carlo study may vary (in this order).
SWEEP_PARAMS: dict[str, Param] = {k: p for k, p in PARAMS.items() if p.sweep}
#: Parameters a fit may vary (calibration and validation).
FIT_PARAMS: dict[str, Param] = {k: p for k, p in PARAMS.items() if p.fit is not None}

#: Config-file keys that are words or whole numbers, not quantities: key -> field.
_WORD_KEYS = {
    "case": "case",
    "torque_model": "torque_model",
    "spin_mode": "spin_mode",
    "flight.n_contacts": "n_contacts",
    "friction.speed_law": "speed_law",
    "solver.friction_family": "friction_family",
    "solver.method": "method",
    "solver.formulation": "formulation",
}
#: Sections of a config file, in the order of the documentation.
CONFIG_SECTIONS = ("", "ball", "gap", "rig", "contact", "release", "friction", "flight", "solver")
_CONFIG_ORDER = (
    "case",
    "spin_rate",
    "mu_s",
    "theta0",
    "torque_model",
    "spin_mode",
    "t_max",
    "ball.radius",
    "ball.hole_radius",
    "ball.density",
    "gap.width",
    "gap.viscosity",
    "rig.weight",
    "contact.patch_radius",
    "release.theta_dot",
    "release.phase",
    "friction.speed_law",
    "friction.speed_ratio",
    "friction.slip_speed",
    "flight.mach",
    "flight.p1",
    "flight.altitude",
    "flight.n_contacts",
    "flight.bore_radius",
    "solver.rtol",
    "solver.atol",
    "solver.fixed_step",
    "solver.friction_width",
    "solver.friction_family",
    "solver.method",
    "solver.formulation",
)


def config_schema() -> dict[str, dict[str, tuple[str, str | None]]]:
    """section -> key -> (field name, pint unit, or None for words and whole numbers)."""
    by_key: dict[str, tuple[str, str | None]] = {k: (v, None) for k, v in _WORD_KEYS.items()}
    by_key.update({p.config: (p.name, p.pint_unit) for p in PARAMS.values() if p.config})
    schema: dict[str, dict[str, tuple[str, str | None]]] = {s: {} for s in CONFIG_SECTIONS}
    for key in _CONFIG_ORDER:
        section, _, name = key.rpartition(".")
        schema[section][name] = by_key[key]
    return schema
