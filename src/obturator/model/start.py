"""When the tube starts: the Kantrowitz-Donaldson limit on the opening passage (thesis ch. I).

Before the bore opens, the blocked inlet carries a detached bow shock (Fig. 2b).
The flow starts -- the shock is swallowed and only attached oblique shocks
stand at the lip (Fig. 2c) -- once the throat can pass the captured flow behind
a normal shock at sonic speed (thesis Eq. 2, with M_2 from Eq. 3):

    A_c / A_t <= (A_c / A_t)_start(M) = A/A*(M_2)       (``swallow_area_ratio``)

The throat of the passage through the ball is the open area A(theta) of
:mod:`.passage` (the straight stream tube through the tilted hole), so the
tube starts at the nutation angle theta_start(M) where

    A(theta_start) = A_c / (A_c/A_t)_start(M).

A(theta) falls monotonically from the full bore at theta = 0 to nothing at
beta_s, so theta_start < beta_s: the start comes after first light. Two flags:

* **unstartable**: A_c / A(0) >= (A_c/A_t)_start(M); even the aligned ball
  leaves too small a throat (the Mach number is below
  ``start_mach(A_c / A(0))``, Eq. 2 inverted). Never for the Table 1
  constant-area bore (A_c = A(0)) in this frictionless, perfect-throat limit.
* **choked**: the started tube of length L_p and diameter 2 r_p chokes by wall
  friction (Fanno, chapter I.B.4.c) at or below the choking Mach, a normal
  shock stands in the bore and the flow unstarts again (the drag rise of
  the thesis's Refs. 7-8).

**Bracket.** Eq. 2 on the lens is an idealisation: no friction between lip and ball,
and a throat that passes sonic flow over its whole area. Neither end of it is a
conservative choice. :attr:`StartCondition.theta_start_early` takes the flow turned
through the tilted hole (:func:`.passage.turned_open_area`, the window of a mouth
onto the bore, larger than the lens): it starts sooner.
:attr:`StartCondition.theta_start_late` takes the lens with the Fanno friction of the
post-shock flow over the tube (the top of the friction-factor range at the post-shock
Reynolds number) and the lowest discharge coefficient of the lens orifice
(:mod:`obturator.flow.start_friction`): it starts later, or never (with f_D L/D
~0.12 the Table 1 bore cannot start below ~M 1.36 at all; at sea level, with the
friction range's top (f_D L/D 0.123-0.129), not below M 1.38, and with C_d = 0.84
as well not below M 2.05). theta_start (decreasing in time) is in
[theta_start_late, theta_start_early].
"""

from __future__ import annotations

import functools
import math
from dataclasses import asdict, dataclass
from typing import Any, NamedTuple

from .._docs import field_docs
from ..errors import InputError, check_range
from ..flow import (
    choking_mach_freestream,
    normal_shock_pressure_ratio,
    normal_shock_stagnation_pressure_ratio,
    start_mach,
    swallow_area_ratio,
)
from ..flow.start_friction import (
    DISCHARGE_COEFFICIENT_RANGE,
    post_shock_reynolds,
    start_area_ratio,
    start_friction_range,
)
from ..reference import TABLE1
from .geometry import BoredBall
from .passage import open_angle, open_area, turned_open_angle

__all__ = [
    "START_BOUNDS",
    "StartCondition",
    "full_bore_start_mach",
    "start_angle",
    "start_condition",
]


@field_docs
@dataclass(frozen=True)
class StartCondition:
    """The start of the internal flow at one flight Mach number."""

    #: Flight Mach number M_1 [-].
    mach: float
    #: Nutation angle at which the bow shock is swallowed [rad]; NaN when unstartable.
    theta_start: float
    #: (A_c/A_t)_start at this Mach (Eq. 2) [-].
    swallow_ratio: float
    #: Throat area needed, A_c / (A_c/A_t)_start [m^2].
    throat_area: float
    #: A_c [m^2].
    capture_area: float
    #: Open area of the aligned ball, A(0) [m^2].
    full_area: float
    #: First-light angle asin(r_s/R_s) [rad].
    beta_s: float
    #: The full bore swallows the shock at this Mach.
    startable: bool
    #: Fanno choking Mach of the started bore [-].
    choke_mach: float
    #: ``mach <= choke_mach``: the started tube chokes by friction and unstarts.
    choked: bool
    #: r_p [m].
    bore_radius: float
    #: Ratio of specific heats [-].
    gamma: float
    #: Early bound: Eq. 2 on the window of the flow turned through the hole [rad]; NaN
    #: when unstartable.
    theta_start_early: float = math.nan
    #: Late bound: the lens with wall friction and the lowest discharge coefficient [rad];
    #: NaN where the late bound never starts.
    theta_start_late: float = math.nan
    #: The lens with wall friction alone (C_d = 1) [rad]; NaN where it never starts.
    theta_start_friction: float = math.nan
    #: (A_c/A_t)_start of the late bound, C_d A/A*(M_3) (0: choked before the ball) [-].
    late_swallow_ratio: float = math.nan
    #: Reynolds number of the post-shock flow in the bore [-].
    reynolds_post_shock: float = math.nan
    #: Darcy friction factors of the post-shock flow, low and high [-].
    friction_factors: tuple[float, float] = (math.nan, math.nan)
    #: f_D L/D of the late bound (the high friction factor) [-].
    friction_fld: float = math.nan
    #: Discharge coefficients of the lens, low (late bound) and high [-].
    discharge_coefficients: tuple[float, float] = DISCHARGE_COEFFICIENT_RANGE

    @property
    def verdict(self) -> str:
        """``"starts"``, ``"unstartable"`` (Eq. 2) or ``"choked"`` (Fanno)."""
        if not self.startable:
            return "unstartable"
        return "choked" if self.choked else "starts"

    @property
    def late_startable(self) -> bool:
        """Whether the late bound starts at all."""
        return math.isfinite(self.theta_start_late)

    @property
    def late_verdict(self) -> str:
        """``"starts"`` or why the late bound never starts."""
        if self.late_startable:
            return "starts"
        if self.late_swallow_ratio <= 0.0:
            return f"never starts: f_D L/D {self.friction_fld:.3g} chokes the tube before the ball"
        return (
            f"never starts: C_d A/A*(M_3) = {self.late_swallow_ratio:.4g} < "
            f"A_c/A(0) = {self.capture_area / self.full_area:.4g}"
        )

    def spill_load_factors(self) -> tuple[float, float]:
        """Bounds on the ball's load between first light and start, over the thesis's F_p [-].

        Quasi-steady (the passage opens over milliseconds, the bore's acoustic
        time L_p / a is about 0.1 ms): with the throat A(theta) choked, the bore
        ahead of the ball holds subsonic flow at total pressure p_02 behind the
        normal bow shock, its Mach number M_b set by pi r_p^2 / A(theta) =
        A/A*(M_b); M_b rises from 0 at first light to M_2 at the start, where
        Eq. 2 holds. So the pressure on the upstream face stays in [P_2, p_02],
        the loaded area in [pi r_p^2 - A_t, pi r_p^2], and the downstream face,
        behind the sonic throat, sees at most the throat pressure
        p* = p_02 (2/(gamma+1))^(gamma/(gamma-1)) and at least P_1. Hence

            F_high = pi r_p^2 (p_02 - P_1),
            F_low  = (pi r_p^2 - A_t) (P_2 - p*),

        against the thesis's F_p = pi r_p^2 (P_2 - P_1) (Eq. 43), which the
        dynamics keep past first light.

        Returns
        -------
        (float, float)
            F_low / F_p and F_high / F_p.
        """
        g, m = self.gamma, self.mach
        p2 = float(normal_shock_pressure_ratio(m, g))
        p02 = float(normal_shock_stagnation_pressure_ratio(m, g)) * (
            1.0 + 0.5 * (g - 1.0) * m * m
        ) ** (g / (g - 1.0))
        p_star = p02 * (2.0 / (g + 1.0)) ** (g / (g - 1.0))
        bore = math.pi * self.bore_radius**2
        low = (1.0 - min(self.throat_area, bore) / bore) * (p2 - p_star) / (p2 - 1.0)
        return low, (p02 - 1.0) / (p2 - 1.0)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready fields (angles also in degrees; NaN as None)."""
        out: dict[str, Any] = {}
        for k, v in asdict(self).items():
            out[k] = None if isinstance(v, float) and not math.isfinite(v) else v
        for key in (
            "theta_start",
            "theta_start_early",
            "theta_start_late",
            "theta_start_friction",
        ):
            deg = math.degrees(getattr(self, key))
            out[f"{key}_deg"] = deg if math.isfinite(deg) else None
        out["friction_factors"] = list(self.friction_factors)
        out["discharge_coefficients"] = list(self.discharge_coefficients)
        out["late_startable"] = self.late_startable
        out["late_verdict"] = self.late_verdict
        out["beta_s_deg"] = math.degrees(self.beta_s)
        out["verdict"] = self.verdict
        return out


def _capture(bore_radius: float, capture_area: float | None) -> float:
    if capture_area is None:
        return math.pi * bore_radius * bore_radius
    return check_range("capture_area", capture_area, 0.0, math.inf, lo_open=True, unit="m^2")


def full_bore_start_mach(
    ball: BoredBall,
    bore_radius: float = TABLE1["bore_radius"],
    *,
    capture_area: float | None = None,
    gamma: float = TABLE1["gamma"],
) -> float:
    """Lowest flight Mach at which the aligned ball (theta = 0) swallows the shock [-].

    ``start_mach(A_c / A(0))`` (Eq. 2 inverted); 1 for A_c = A(0), the Table 1 bore.
    Raises :class:`~obturator.errors.InputError` when A_c / A(0) is at or above
    the Eq. 2 limit (1.6661 for gamma = 1.4): such a tube never starts.
    """
    full = open_area(0.0, ball.radius, ball.hole_radius, bore_radius)
    return float(start_mach(max(1.0, _capture(bore_radius, capture_area) / full), gamma))


@functools.lru_cache(maxsize=256)
def _choking_mach(l_over_d: float, diameter: float, altitude_m: float, gamma: float) -> float:
    """:func:`obturator.flow.choking_mach_freestream`, memoised: it depends on the bore and
    the altitude, not on the flight Mach, so every Mach number of a flight (each
    :func:`start_condition`) asks for the same fixed point of the Fanno relations."""
    return choking_mach_freestream(l_over_d, diameter, altitude_m=altitude_m, gamma=gamma)


def start_condition(
    mach: float,
    ball: BoredBall,
    bore_radius: float = TABLE1["bore_radius"],
    *,
    capture_area: float | None = None,
    gamma: float = TABLE1["gamma"],
    tube_length: float = TABLE1["projectile_length"],
    altitude_m: float = 0.0,
    discharge_coefficients: tuple[float, float] = DISCHARGE_COEFFICIENT_RANGE,
    relative_roughness: float = 0.0,
) -> StartCondition:
    """theta_start(M) and the unstartable / choked flags at flight Mach `mach`.

    Parameters
    ----------
    mach : float
        Flight Mach number M_1, in (1, 10].
    ball : BoredBall
        R_s, r_s.
    bore_radius : float
        Projectile bore r_p [m].
    capture_area : float, optional
        A_c [m^2]; default pi r_p^2 (the constant-area bore's inlet).
    gamma : float
        Ratio of specific heats [-].
    tube_length : float
        Bore length L_p [m] for the Fanno choking Mach (Table 1: 76.2 mm).
    altitude_m : float
        Altitude [m] of the free-stream Reynolds number of the friction factor
        (:func:`obturator.flow.choking_mach_freestream`) and of the post-shock one
        (:func:`obturator.flow.start_friction.post_shock_reynolds`).
    discharge_coefficients : (float, float)
        Range of C_d of the lens orifice, each in (0, 1] [-]; the low end makes the late
        bound (default :data:`~obturator.flow.start_friction.DISCHARGE_COEFFICIENT_RANGE`).
    relative_roughness : float
        eps/D of the bore wall for the high friction factor, in [0, 0.05].

    Returns
    -------
    StartCondition
    """
    inlet = _Inlet.of(mach, ball, bore_radius, capture_area, gamma, tube_length)
    cd_lo, cd_hi = _discharge(discharge_coefficients)
    lens = inlet.lens()
    choke = _choking_mach(inlet.l_over_d, 2.0 * bore_radius, altitude_m, gamma)
    early = inlet.early(lens)
    late = inlet.late(altitude_m, relative_roughness, cd_lo)
    return StartCondition(
        mach=inlet.mach,
        theta_start=lens.theta,
        swallow_ratio=lens.ratio,
        throat_area=lens.needed,
        capture_area=inlet.capture,
        full_area=inlet.full,
        beta_s=ball.opening_angle,
        startable=lens.startable,
        choke_mach=choke,
        choked=inlet.mach <= choke,
        bore_radius=bore_radius,
        gamma=gamma,
        theta_start_early=early,
        theta_start_late=late.theta,
        theta_start_friction=inlet.lens_angle(
            start_area_ratio(inlet.mach, late.friction_fld, 1.0, gamma)
        ),
        late_swallow_ratio=late.ratio,
        reynolds_post_shock=late.reynolds,
        friction_factors=late.friction_factors,
        friction_fld=late.friction_fld,
        discharge_coefficients=(cd_lo, cd_hi),
    )


#: The bounds of theta_start (:func:`start_angle`): Eq. 2 on the frictionless lens, the
#: late bound (wall friction, lowest discharge coefficient), the flow turned through the
#: hole (early).
START_BOUNDS: tuple[str, ...] = ("nominal", "late", "early")


def start_angle(
    mach: float,
    ball: BoredBall,
    bore_radius: float = TABLE1["bore_radius"],
    bound: str = "nominal",
    *,
    capture_area: float | None = None,
    gamma: float = TABLE1["gamma"],
    tube_length: float = TABLE1["projectile_length"],
    altitude_m: float = 0.0,
    discharge_coefficients: tuple[float, float] = DISCHARGE_COEFFICIENT_RANGE,
    relative_roughness: float = 0.0,
) -> float:
    """One bound of theta_start(M) [rad] (NaN where the tube cannot start): the field
    ``theta_start``, ``theta_start_late`` or ``theta_start_early`` of
    :func:`start_condition` with the same arguments, to the bit, computing only what that
    bound needs (the flight studies ask for it at every segment of a trajectory).

    Parameters
    ----------
    mach, ball, bore_radius, capture_area, gamma, tube_length, altitude_m,
    discharge_coefficients, relative_roughness
        As for :func:`start_condition`.
    bound : {"nominal", "late", "early"}
        Which bound (:data:`START_BOUNDS`).

    Returns
    -------
    float
        theta_start [rad], or NaN.
    """
    if bound not in START_BOUNDS:
        raise InputError("bound", f"{bound!r}; allowed: {', '.join(START_BOUNDS)}")
    inlet = _Inlet.of(mach, ball, bore_radius, capture_area, gamma, tube_length)
    cd_lo, _ = _discharge(discharge_coefficients)
    if bound == "late":
        return inlet.late(altitude_m, relative_roughness, cd_lo).theta
    lens = inlet.lens()
    return lens.theta if bound == "nominal" else inlet.early(lens)


def _discharge(coefficients: tuple[float, float]) -> tuple[float, float]:
    """(low, high) of a checked range of discharge coefficients."""
    lo, hi = (check_range("discharge_coefficient", c, 0.0, 1.0, lo_open=True) for c in coefficients)
    return (hi, lo) if lo > hi else (lo, hi)


class _Lens(NamedTuple):
    """Eq. 2 on the frictionless lens at one Mach number."""

    ratio: float  #: (A_c/A_t)_start
    needed: float  #: A_c / ratio [m^2]
    startable: bool
    theta: float  #: theta_start [rad] (NaN where not startable)


class _Late(NamedTuple):
    """The late bound: Fanno friction of the post-shock flow, lowest C_d."""

    reynolds: float
    friction_factors: tuple[float, float]
    friction_fld: float
    ratio: float
    theta: float


@dataclass(frozen=True)
class _Inlet:
    """The checked inputs that every bound of theta_start shares."""

    mach: float
    ball: BoredBall
    bore_radius: float
    capture: float
    full: float
    gamma: float
    l_over_d: float

    @classmethod
    def of(
        cls,
        mach: float,
        ball: BoredBall,
        bore_radius: float,
        capture_area: float | None,
        gamma: float,
        tube_length: float,
    ) -> _Inlet:
        m = check_range("mach", mach, 1.0, 10.0, lo_open=True)
        a_c = _capture(bore_radius, capture_area)
        full = open_area(0.0, ball.radius, ball.hole_radius, bore_radius)
        length = check_range("tube_length", tube_length, 0.0, 10.0, lo_open=True, unit="m")
        return cls(m, ball, bore_radius, a_c, full, gamma, length / (2.0 * bore_radius))

    def lens(self) -> _Lens:
        ratio = float(swallow_area_ratio(self.mach, self.gamma))
        needed = self.capture / ratio
        startable = needed <= self.full * (1.0 + 1e-12)
        theta = self._angle(min(needed, self.full))
        return _Lens(ratio, needed, startable, theta if startable else math.nan)

    def early(self, lens: _Lens) -> float:
        if not lens.startable:
            return math.nan
        b = self.ball
        return turned_open_angle(
            min(lens.needed, self.full), b.radius, b.hole_radius, self.bore_radius
        )

    def late(self, altitude_m: float, relative_roughness: float, cd_lo: float) -> _Late:
        re2 = post_shock_reynolds(self.mach, 2.0 * self.bore_radius, altitude_m, self.gamma)
        f_lo, f_hi = start_friction_range(re2, self.l_over_d, relative_roughness)
        fld = f_hi * self.l_over_d
        ratio = start_area_ratio(self.mach, fld, cd_lo, self.gamma)
        return _Late(re2, (f_lo, f_hi), fld, ratio, self.lens_angle(ratio))

    def lens_angle(self, ratio: float) -> float:
        """theta where the lens passes A_c / `ratio` (NaN where even A(0) is too small)."""
        if ratio <= 0.0 or self.capture / ratio > self.full * (1.0 + 1e-12):
            return math.nan
        return self._angle(min(self.capture / ratio, self.full))

    def _angle(self, area: float) -> float:
        b = self.ball
        return open_angle(area, b.radius, b.hole_radius, self.bore_radius)
