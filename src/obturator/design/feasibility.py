"""Whether the rig can run a setting, and how far it lies from the validated runs.

Holding moment
--------------
Before release the rig spins with the ball held at the set angle theta_0. Held rigidly
in the spinning seat, the ball needs the moment that keeps its hole axis from turning,
the gyroscopic moment of Euler's equations at omega_r = 0 (thesis Eqs. 5a-5c):

    M_hold = omega_p^2 |C - A| sin(theta_0) cos(theta_0)   [N m],

C and A the ball's axial and transverse inertias. Two things can supply it:

* the seat's friction, at most M_seat = mu_s W R_s (the moment scale of thesis Eq. 61;
  mu_s = 0.5473, the thesis's fit, chapter IV; W the ball's load: Table 1's measured
  0.07987 N on the as-built ball, rho V g on a new one);
* the holding jet, at most M_jet = F_jet R_s with F_jet = 0.04 N (air at about 100 m/s
  through a 2 mm nozzle, acting fully tangentially: the bound the fit registry states
  for theta_dot0, :data:`obturator.params.FIT_SPECS`).

M_hold / M_seat is the stick ratio kappa at release (:func:`obturator.solve.dispatch.
stick_ratio`). The Appendix B runs needed kappa 0.077-2.51, more than the seat and the
jet together at the highest spins: the rig demonstrably held them. The rig's bound is
therefore the larger of M_seat + M_jet and the largest M_hold the measured runs needed;
a setting that asks for more is *infeasible* and never planned.

Distance from the validated runs
--------------------------------
A feasible setting is *extrapolated* where it leaves what the measured runs cover: its
spin outside their range, its release angle more than the stated alignment tolerance
(1 deg, thesis chapter IV p. 97) from every measured run's, a ball none of them used
(hole radius or density), or a stick ratio outside theirs. Such runs are planned when
they discriminate best, but are marked in the plan, the report and the figure: the
candidates there are extrapolations, not interpolations, of what was validated.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._docs import field_docs
from ..calibration.data import SpinRigData
from ..model import validity
from ..model.case import Case
from ..model.cases import TABLE1, rig_case, table1_ball
from ..validation.candidates import THESIS_MU_S
from .settings import Setting

__all__ = [
    "JET_FORCE",
    "RELEASE_TOLERANCE_DEG",
    "Feasibility",
    "ValidatedRange",
    "check_setting",
    "holding_moment",
    "seat_friction_moment",
]

#: Largest force of the holding jet [N] (the fit registry's argument for theta_dot0).
JET_FORCE = validity.HOLDING_JET_FORCE
#: Stated alignment tolerance of the release angle [deg] (thesis chapter IV, p. 97).
RELEASE_TOLERANCE_DEG = 1.0
_HOLE = float(TABLE1["hole_radius"])
_RHO = float(TABLE1["density"])


def _is_table1_ball(hole_radius: float, density: float) -> bool:
    return math.isclose(hole_radius, _HOLE) and math.isclose(density, _RHO)


def _rig(
    hole_radius: float,
    density: float,
    spin_rate: float = 100.0,
    theta0_deg: float = 87.25,
    mu_s: float = THESIS_MU_S,
) -> Case:
    """The rig case of a setting, loaded as :func:`obturator.design.design_case` loads a
    ball: Table 1's measured W on the as-built ball, rho V g on any other."""
    ball = table1_ball(hole_radius=hole_radius, density=density)
    weight = float(TABLE1["rig_weight"]) if _is_table1_ball(hole_radius, density) else None
    return rig_case(spin_rate, mu_s, theta0_deg=theta0_deg, weight=weight, ball=ball)


def holding_moment(
    spin_rate: float, theta0_deg: float, hole_radius: float = _HOLE, density: float = _RHO
) -> float:
    """Moment that holds the ball at `theta0_deg` in the seat spinning at `spin_rate` [N m]:
    :func:`obturator.model.validity.holding_moment` of the setting's rig case.
    `spin_rate` [rad/s], `theta0_deg` [deg], `hole_radius` [m], `density` [kg/m^3] (the
    Table 1 ball by default)."""
    return validity.holding_moment(_rig(hole_radius, density, spin_rate, theta0_deg))


def seat_friction_moment(
    hole_radius: float = _HOLE, density: float = _RHO, mu_s: float = THESIS_MU_S
) -> float:
    """Largest friction moment of the seat on the ball, mu_s W R_s [N m] (thesis Eq. 61):
    :func:`obturator.model.validity.seat_friction_moment` of the setting's rig case."""
    return validity.seat_friction_moment(_rig(hole_radius, density, mu_s=mu_s))


def _jet_moment(hole_radius: float, density: float) -> float:
    return validity.holding_jet_moment(_rig(hole_radius, density))


def _setting_ratio(s: Setting) -> tuple[float, float]:
    m = holding_moment(s.spin_rate, s.theta0_deg, s.hole_radius, s.density)
    return m, m / seat_friction_moment(s.hole_radius, s.density)


@field_docs
@dataclass(frozen=True)
class ValidatedRange:
    """What the measured runs cover (the reference of :func:`check_setting`)."""

    #: Lowest and highest measured spin [rad/s].
    spin_rate: tuple[float, float]
    #: Distinct measured release angles [deg].
    theta0_deg: tuple[float, ...]
    #: Distinct measured balls, (hole radius [m], density [kg/m^3]).
    balls: tuple[tuple[float, float], ...]
    #: Lowest and highest stick ratio at release of the measured runs [-].
    stick_ratio: tuple[float, float]
    #: Largest holding moment a measured run needed [N m].
    holding_moment_max: float

    @classmethod
    def of(cls, data: SpinRigData) -> ValidatedRange:
        """From the measured runs (each run's own theta_0, hole and density if given)."""
        rows = [dict(r) for r in data.run_settings()]
        runs = [
            Setting(
                float(w),
                float(r.get("theta0_deg", TABLE1["theta0_deg"])),
                float(r.get("hole_radius", _HOLE)),
                float(r.get("density", _RHO)),
            )
            for w, r in zip(data.spin_rate, rows, strict=True)
        ]
        held = np.array([_setting_ratio(s) for s in runs])
        return cls(
            (float(data.spin_rate.min()), float(data.spin_rate.max())),
            tuple(sorted({s.theta0_deg for s in runs})),
            tuple(sorted({(s.hole_radius, s.density) for s in runs})),
            (float(held[:, 1].min()), float(held[:, 1].max())),
            float(held[:, 0].max()),
        )

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready, unit-suffixed keys."""
        return {
            "spin_rate_rad_s": list(self.spin_rate),
            "theta0_deg": list(self.theta0_deg),
            "balls": [{"hole_radius_m": h, "density_kg_m3": r} for h, r in self.balls],
            "stick_ratio": list(self.stick_ratio),
            "holding_moment_max_N_m": self.holding_moment_max,
        }


@field_docs
@dataclass(frozen=True)
class Feasibility:
    """Whether the rig can run one setting, and where it leaves the validated runs."""

    #: Moment that holds the ball at the set angle while it spins [N m].
    holding_moment: float
    #: The seat's largest friction moment mu_s W R_s [N m].
    seat_moment: float
    #: The holding jet's largest moment F_jet R_s [N m].
    jet_moment: float
    #: The rig's bound: max(seat + jet, the largest the measured runs needed) [N m].
    bound: float
    #: Stick ratio at release, holding moment over the seat's friction moment [-].
    stick_ratio: float
    #: Why the setting is an extrapolation of the measured runs (empty: it is not).
    extrapolated: tuple[str, ...]

    @property
    def feasible(self) -> bool:
        """The holding moment is within the rig's bound."""
        return self.holding_moment <= self.bound

    @property
    def as_built_ball(self) -> bool:
        """Runs on a ball the measured runs used (no new ball to make)."""
        return "new ball" not in self.extrapolated

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready, unit-suffixed keys."""
        return {
            "holding_moment_N_m": self.holding_moment,
            "seat_friction_moment_N_m": self.seat_moment,
            "jet_moment_N_m": self.jet_moment,
            "holding_bound_N_m": self.bound,
            "stick_ratio": self.stick_ratio,
            "feasible": self.feasible,
            "extrapolated": list(self.extrapolated),
        }


def check_setting(s: Setting, validated: ValidatedRange) -> Feasibility:
    """Holding moment, bound and distance from the validated runs of one setting."""
    m, kappa = _setting_ratio(s)
    seat = seat_friction_moment(s.hole_radius, s.density)
    jet = _jet_moment(s.hole_radius, s.density)
    bound = max(seat + jet, validated.holding_moment_max)
    why: list[str] = []
    lo, hi = validated.spin_rate
    if not lo <= s.spin_rate <= hi:
        why.append("spin")
    if min(abs(s.theta0_deg - t) for t in validated.theta0_deg) > RELEASE_TOLERANCE_DEG:
        why.append("release angle")
    if not any(
        math.isclose(s.hole_radius, h) and math.isclose(s.density, r) for h, r in validated.balls
    ):
        why.append("new ball")
    k_lo, k_hi = validated.stick_ratio
    if not k_lo <= kappa <= k_hi:
        why.append("stick ratio")
    return Feasibility(m, seat, jet, bound, kappa, tuple(why))


def check_settings(s: Sequence[Setting], validated: ValidatedRange) -> list[Feasibility]:
    """:func:`check_setting` of every setting."""
    return [check_setting(x, validated) for x in s]
