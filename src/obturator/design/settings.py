"""What a rig campaign can set, and how a setting becomes a case of each candidate.

Controllable settings (thesis chapter III; chapter VI recommends varying the hole size
and the obturator material):

* spin rate omega_p [rad/s]: the rig's motor; Appendix B covers 78-446 rad/s;
* release angle theta_0 [deg] *as the release sets it*: the release holds the ball at a
  chosen tilt; a candidate that fits theta_0 (the "theta0" mechanism: a misalignment
  of the release) reads its fitted value as an *offset* from Table 1's 87.25 deg, so at a
  set angle theta_set its ball starts at theta_set + (theta0_fit - 87.25 deg); every
  other candidate starts at theta_set;
* hole radius r_s [m]: thesis Fig. 17 compares 3.75 and 5.58 mm (Table 1: 4.72 mm);
  r_s moves the opening angle beta_s = asin(r_s/R_s) and the inertia ratio C/A;
* ball density rho [kg/m^3] (material): thesis Fig. 16 compares 6000 and 10000 kg/m^3.
  On the rig the load is a new ball's own weight rho V g; the friction law of each
  candidate is kept (a real change of material also changes the friction against the
  PMMA seat: an assumption).

What is measured: the opening time t_cr (the rig's laser readout, thesis chapter III.B).
The time to an intermediate angle is not used: the rig gives only t_cr.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._docs import field_docs
from ..errors import InputError, check_range
from ..model.case import Case
from ..model.cases import TABLE1
from ..validation.candidates import Candidate

#: Suffix of a new ball's copy of a ball-specific parameter (:data:`.posterior.NEW_BALL`).
NEW_BALL = "@new_ball"

__all__ = [
    "NAIVE_SPINS",
    "NOMINAL_SETTING",
    "Setting",
    "SettingRanges",
    "design_case",
    "naive_plan",
    "setting_arrays",
    "settings_of",
]

_THETA0 = float(TABLE1["theta0_deg"])
_HOLE = float(TABLE1["hole_radius"])
_RHO = float(TABLE1["density"])
#: Largest hole radius the bored sphere allows: r_s <= R_s / sqrt(2) [m].
_HOLE_MAX = float(TABLE1["ball_radius"]) / math.sqrt(2.0)

#: (field of :class:`Setting`, its key in JSON with the unit).
_SETTING_KEYS = (
    ("spin_rate", "spin_rate_rad_s"),
    ("theta0_deg", "theta0_set_deg"),
    ("hole_radius", "hole_radius_m"),
    ("density", "density_kg_m3"),
)


@field_docs
@dataclass(frozen=True)
class Setting:
    """One run's controllable settings."""

    #: Spin rate omega_p [rad/s].
    spin_rate: float
    #: Release angle as set [deg].
    theta0_deg: float = _THETA0
    #: Hole radius r_s [m].
    hole_radius: float = _HOLE
    #: Ball density [kg/m^3].
    density: float = _RHO

    def to_dict(self) -> dict[str, float]:
        """JSON-ready, unit-suffixed keys."""
        return {key: getattr(self, name) for name, key in _SETTING_KEYS}

    @classmethod
    def from_dict(cls, d: Mapping[str, float]) -> Setting:
        """Inverse of :meth:`to_dict`."""
        return cls(**{name: float(d[key]) for name, key in _SETTING_KEYS})

    @property
    def n_changes(self) -> int:
        """How many of the release angle, hole radius and density differ from Table 1's
        rig (0-3; the spin is set in every campaign)."""
        return sum(
            (
                not math.isclose(self.theta0_deg, _THETA0),
                not math.isclose(self.hole_radius, _HOLE),
                not math.isclose(self.density, _RHO),
            )
        )

    @property
    def is_as_built_ball(self) -> bool:
        """The Table 1 ball (hole radius and density), whatever the spin and release."""
        return math.isclose(self.hole_radius, _HOLE) and math.isclose(self.density, _RHO)

    @property
    def is_nominal_rig(self) -> bool:
        """Table 1 ball at the Table 1 release angle (only the spin varies)."""
        return (self.theta0_deg, self.hole_radius, self.density) == (_THETA0, _HOLE, _RHO)


#: Table 1's rig at 200 rad/s.
NOMINAL_SETTING = Setting(200.0)


def _axis(lo: float, hi: float, n: int, nominal: float, geometric: bool = False) -> list[float]:
    """n values from lo to hi (geometric or linear), with the nominal added if inside."""
    if n == 1 or lo == hi:
        vals = [nominal if lo <= nominal <= hi else lo]
    else:
        vals = list(np.geomspace(lo, hi, n) if geometric else np.linspace(lo, hi, n))
        if lo <= nominal <= hi:
            vals.append(nominal)
    return sorted({round(float(v), 12) for v in vals})


@field_docs
@dataclass(frozen=True)
class SettingRanges:
    """Ranges of the controllable settings and the candidate grid over them."""

    #: (low, high) spin rate omega_p [rad/s]; default 90-450 (Appendix B: 78-446; below
    #: 90 rad/s the runs scatter most and every solve is stiff, about 15 times the cost).
    spin_rate: tuple[float, float] = (90.0, 450.0)
    #: (low, high) release angle as set [deg]; default 70-89 (Table 1: 87.25; 90 is the
    #: equilibrium the ball never leaves).
    theta0_deg: tuple[float, float] = (70.0, 89.0)
    #: (low, high) hole radius r_s [m]; default 3.75-5.58 mm (thesis Fig. 17), at most
    #: R_s/sqrt(2).
    hole_radius: tuple[float, float] = (3.75e-3, 5.58e-3)
    #: (low, high) ball density [kg/m^3]; default 6000-10000 (thesis Fig. 16).
    density: tuple[float, float] = (6000.0, 10000.0)
    #: Grid points of the spin-rate axis, geometrically spaced (the Table 1 value,
    #: 200 rad/s, is added when inside the range).
    n_spin: int = 8
    #: Grid points of the release-angle axis, linearly spaced (the Table 1 value is added
    #: when inside the range).
    n_theta0: int = 3
    #: Grid points of the hole-radius axis, linearly spaced (the Table 1 value is added when
    #: inside the range).
    n_hole: int = 2
    #: Grid points of the density axis, linearly spaced (the Table 1 value is added when
    #: inside the range).
    n_density: int = 2

    def __post_init__(self) -> None:
        limits = {
            "spin_rate": (20.0, 2000.0, "rad/s"),
            "theta0_deg": (45.0, 89.5, "deg"),
            "hole_radius": (1e-3, _HOLE_MAX, "m"),
            "density": (1000.0, 20000.0, "kg/m^3"),
        }
        for name, (lo, hi, unit) in limits.items():
            a, b = getattr(self, name)
            check_range(f"{name} (low end)", a, lo, hi, unit=unit)
            check_range(f"{name} (high end)", b, lo, hi, unit=unit)
            if a > b:
                raise InputError(name, f"low end {a:g} {unit} is above the high end {b:g} {unit}")
        for name in ("n_spin", "n_theta0", "n_hole", "n_density"):
            check_range(name, getattr(self, name), 1, 50)

    def grid(self) -> list[Setting]:
        """Every combination of the axes (spins geometric, the rest linear)."""
        spins = _axis(*self.spin_rate, self.n_spin, 200.0, geometric=True)
        th = _axis(*self.theta0_deg, self.n_theta0, _THETA0)
        holes = _axis(*self.hole_radius, self.n_hole, _HOLE)
        rhos = _axis(*self.density, self.n_density, _RHO)
        return [Setting(w, t, h, r) for w in spins for t in th for h in holes for r in rhos]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready."""
        return {
            "spin_rate_rad_s": list(self.spin_rate),
            "theta0_set_deg": list(self.theta0_deg),
            "hole_radius_m": list(self.hole_radius),
            "density_kg_m3": list(self.density),
            "points": [self.n_spin, self.n_theta0, self.n_hole, self.n_density],
        }


def design_case(
    candidate: Candidate, setting: Setting, values: Mapping[str, float], t_max: float
) -> Case:
    """The rig case of `candidate` with fitted `values` at `setting` (module notes).

    The setting is laid over the candidate as one measured run's own settings are
    (:func:`obturator.calibration.rig_model.apply_run_settings`, the same path as a
    user's runs with those columns in ``validate``): the release angle as set plus the
    candidate's theta_0 offset, a new ball (weight rho V g) where the hole or the
    density differs from Table 1's; on a new ball a ball-specific parameter takes the new
    ball's value (``"<name>@new_ball"`` in `values`, :mod:`.posterior`) where given.

    Parameters
    ----------
    candidate : Candidate
    setting : Setting
    values : mapping
        Values of ``candidate.params`` (physical units).
    t_max : float
        Horizon [s].
    """
    v = {k: float(values[k]) for k in candidate.params}
    new_ball = not setting.is_as_built_ball
    # a ball-specific parameter (the theta_0 offset of the polished spot) is the new ball's
    # own where the values carry one (:class:`.posterior.Posterior`), else the fitted one
    for k in candidate.params:
        if new_ball and f"{k}{NEW_BALL}" in values:
            v[k] = float(values[f"{k}{NEW_BALL}"])
    offset = v["theta0_deg"] - _THETA0 if "theta0_deg" in candidate.params else 0.0
    conditions: dict[str, float] = {"theta0_deg": min(setting.theta0_deg, 90.0 - offset)}
    if new_ball:
        conditions.update(hole_radius=setting.hole_radius, density=setting.density)
    run = replace(candidate, conditions=tuple(conditions.items()))
    return run.build(setting.spin_rate, v, t_max)


#: Distinct spins of the naive plan: larger naive campaigns repeat them (replicates).
NAIVE_SPINS = 20


def naive_plan(n_runs: int, spin_rate: Sequence[float]) -> list[Setting]:
    """The naive campaign of `n_runs`: spins spread as the measured runs (Appendix B), the
    Table 1 ball and release angle.

    The base is :data:`NAIVE_SPINS` spins spread as the m measured runs (the run at rank
    floor((j + 1/2) m / 20) in spin order, j = 0..19); a plan of n <= 20 runs takes the
    base spins at ranks floor((i + 1/2) 20 / n), a larger one repeats the base in order.
    """
    check_range("n_runs", n_runs, 1, 100_000)
    w = np.sort(np.asarray(spin_rate, dtype=float))
    m = w.size
    if m == 0:
        raise InputError("spin_rate", "no measured runs to spread the naive plan over")
    k = min(NAIVE_SPINS, m)
    base = [w[int((j + 0.5) * m / k)] for j in range(k)]
    if n_runs <= k:
        picks = [base[int((i + 0.5) * k / n_runs)] for i in range(n_runs)]
    else:
        picks = [base[i % k] for i in range(n_runs)]
    return [Setting(float(x)) for x in picks]


def settings_of(rows: Sequence[Mapping[str, float]]) -> list[Setting]:
    """Settings from their JSON form."""
    return [Setting.from_dict(r) for r in rows]


def setting_arrays(settings: Sequence[Setting]) -> dict[str, NDArray[np.float64]]:
    """Columns of a list of settings: spin [rad/s], theta0 set [deg], r_s [m], rho [kg/m^3]."""
    return {
        "spin_rate": np.array([s.spin_rate for s in settings]),
        "theta0_set_deg": np.array([s.theta0_deg for s in settings]),
        "hole_radius": np.array([s.hole_radius for s in settings]),
        "density": np.array([s.density for s in settings]),
    }
