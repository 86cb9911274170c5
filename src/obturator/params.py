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
from dataclasses import dataclass

from .reference import TABLE1

__all__ = [
    "Range",
    "FitDefaults",
    "Param",
    "PARAMS",
    "SWEEP_PARAMS",
    "FIT_PARAMS",
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


@dataclass(frozen=True)
class FitDefaults:
    """How a calibration fits a parameter: start, bounds, and an internal scale that
    makes the optimiser's variable O(1)."""

    initial: float
    bounds: tuple[float, float]
    scale: float = 1.0


@dataclass(frozen=True)
class Param:
    """One physical parameter.

    Attributes
    ----------
    name : str
        Canonical field name (config files, Python keywords, ``--flag-name``).
    unit : str
        SI unit, CF style (``"1"``: a pure number).
    long_name : str
        Description with the thesis's symbol (NetCDF ``long_name``, help texts).
    config : str or None
        Key in a TOML config, ``"section.key"`` or a top-level ``"key"``.
    range : Range or None
        Allowed values of a swept or sampled input (the case factories check
        combined limits, such as theta_0 above the opening angle, themselves).
    sweep : bool
        May be swept or sampled by :mod:`obturator.sweeps`.
    flight_only : bool
        Applies to the flight case only.
    fit : FitDefaults or None
        Fittable by :func:`obturator.calibration.fit_exact`.
    """

    name: str
    unit: str
    long_name: str
    config: str | None = None
    range: Range | None = None
    sweep: bool = False
    flight_only: bool = False
    fit: FitDefaults | None = None

    @property
    def pint_unit(self) -> str:
        """The unit in pint syntax (``""`` for a pure number)."""
        return "" if self.unit == "1" else self.unit.replace(" ", "*")


_R_S = TABLE1["ball_radius"]
_POSITIVE = Range(0.0, math.inf, True, True)

#: Every physical parameter, by name.
PARAMS: dict[str, Param] = {
    p.name: p
    for p in (
        # 1 rad/s to the case factories' 1e6 rad/s: below ~1 rad/s the integrators' step
        # control, scaled by the spin period, degenerates (measured: 0.5 rad/s runs on
        # for minutes, 1e-6 rad/s divides by zero inside Radau IIA); the rig's slowest
        # run is 42 rad/s (Appendix B)
        Param(
            "spin_rate",
            "rad/s",
            "projectile spin rate omega_p",
            "spin_rate",
            Range(1.0, 1e6),
            True,
        ),
        Param(
            "mu_s",
            "1",
            "sliding friction coefficient mu_s",
            "mu_s",
            Range(0.0, 2.0),
            True,
            fit=FitDefaults(0.55, (0.02, 1.2)),
        ),
        Param(
            "theta0_deg",
            "deg",
            "initial nutation angle theta_0",
            "theta0",
            Range(0.0, 90.0, True, False),
            True,
            fit=FitDefaults(TABLE1["theta0_deg"], (70.0, 89.9), 10.0),
        ),
        Param("density", "kg/m^3", "ball density rho", "ball.density", _POSITIVE, True),
        Param(
            "hole_radius",
            "m",
            "ball hole radius r_s",
            "ball.hole_radius",
            Range(0.0, _R_S / math.sqrt(2.0), False, True),
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
        Param("ball_radius", "m", "ball radius R_s", "ball.radius"),
        Param("viscosity", "Pa s", "gap-fluid viscosity mu_f", "gap.viscosity"),
        Param("weight", "N", "normal load on the rig W", "rig.weight"),
        Param(
            "patch_radius",
            "m",
            "contact patch radius a",
            "contact.patch_radius",
            fit=FitDefaults(2.79e-4, (1e-5, 1e-3), 1e-4),
        ),
        Param("p1", "Pa", "free-stream pressure P_1", "flight.p1"),
        Param("bore_radius", "m", "bore radius r_p", "flight.bore_radius"),
        Param("pressure_force", "N", "pressure force on the ball F_p"),
        Param("t_max", "s", "integration horizon t_max", "t_max"),
        Param("rtol", "1", "relative tolerance", "solver.rtol"),
        Param("atol", "1", "absolute tolerance (rates in omega_p0)", "solver.atol"),
        Param(
            "friction_width",
            "1",
            "friction regularisation width / omega_p0",
            "solver.friction_width",
        ),
        Param(
            "shear_constant",
            "N m s",
            "viscous shear constant S (Eq. 42)",
            fit=FitDefaults(TABLE1["shear_constant"], (0.0, 2e-7), 1e-8),
        ),
        # mechanisms of the validation study (obturator.validation): release
        # transient theta_dot_0 (a plunger/jet kick of a few rad/s at most), slip-speed
        # law of mu (ratio r, speed v_s around the rig's slip speeds 0-1.6 m/s),
        # release phase psi_0, Coulomb contact patch radius (around the 0.28 mm Hertz value)
        Param(
            "theta_dot0",
            "rad/s",
            "release rate theta_dot_0 (spin rig)",
            "release.theta_dot",
            Range(-1e3, 1e3),
            True,
            fit=FitDefaults(0.0, (-3.0, 3.0)),
        ),
        Param(
            "speed_ratio",
            "1",
            "slip-speed law ratio r (spin rig, with speed_law)",
            "friction.speed_ratio",
            Range(0.0, 1.0, True, False),
            True,
            fit=FitDefaults(0.5, (0.05, 1.0)),
        ),
        Param(
            "slip_speed",
            "m/s",
            "slip-speed law reference speed v_s (spin rig, with speed_law)",
            "friction.slip_speed",
            Range(0.0, 100.0, True, False),
            True,
            fit=FitDefaults(0.05, (0.002, 2.0), 0.1),
        ),
        Param(
            "release_phase",
            "rad",
            "release phase psi_0 (spin rig)",
            "release.phase",
            Range(-2.0 * math.pi, 2.0 * math.pi),
            True,
            fit=FitDefaults(0.0, (0.0, 2.0 * math.pi)),
        ),
    )
}

#: Parameters a sweep or Monte Carlo study may vary (in this order).
SWEEP_PARAMS: dict[str, Param] = {k: p for k, p in PARAMS.items() if p.sweep}
#: Parameters a calibration may fit.
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
