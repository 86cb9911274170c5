"""t_start: from first light (t_cr, theta = beta_s) on to the started tube (theta_start).

The same equations of motion run past first light with the load that holds
until the bow shock is swallowed: the thesis's F_p = pi r_p^2 (P_2 - P_1)
(Eq. 43), kept constant (quasi-steady: the bore's acoustic time, about 0.1 ms,
is far below the milliseconds the passage takes to open). The spill through
the partly open bore changes the true load within the bracket of
:meth:`obturator.model.start.StartCondition.spill_load_factors`; the run is
repeated with each end of the bracket from first light on, so t_start comes
with the interval that this bound allows.

Contact geometry (Eq. 47): the ball seats on the ring where the bore meets
the socket. Past first light the upstream mouth covers part of that ring, but
at least half stays backed by material (:func:`obturator.model.passage.ring_contact_fraction`:
0.65 at theta = beta_s, 1/2 as theta -> 0), so the two diametral contacts of
Eq. 47 and Appendix A's arm are kept unchanged.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

from .._docs import field_docs
from ..json_values import finite_or_none
from ..model.case import Case
from ..model.start import StartCondition
from ..model.torques import CoulombContactFriction, ThesisFlightFriction
from .one import simulate
from .options import SolverOptions

__all__ = ["StartTimes", "start_times", "scaled_load"]


@field_docs
@dataclass(frozen=True)
class StartTimes:
    """Opening (first light) and start of one flight case."""

    #: First light, theta = beta_s [s]; NaN if not reached by t_max.
    t_cr: float
    #: Start, theta = theta_start, thesis load kept [s]; NaN if not reached or the tube cannot
    #: start.
    t_start: float
    #: t_start with the load from first light on, at the low end of the spill bracket [s]
    #: (the low load starts later).
    t_start_low_load: float
    #: t_start with the load from first light on, at the high end of the spill bracket [s].
    t_start_high_load: float
    #: theta_start and the flags.
    condition: StartCondition
    #: t_start of the early bound, theta_start_early (turned flow), thesis load [s]; NaN
    #: if not reached or the tube cannot start.
    t_start_early: float = math.nan
    #: t_start of the late bound, theta_start_late (friction, lowest C_d), thesis load [s];
    #: NaN if not reached by t_max or the late bound never starts
    #: (:attr:`StartCondition.late_startable`).
    t_start_late: float = math.nan

    @property
    def delay(self) -> float:
        """t_start - t_cr [s]."""
        return self.t_start - self.t_cr

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (NaN as None), the start condition included."""

        low, high = self.condition.spill_load_factors()
        return {
            "t_cr_s": finite_or_none(self.t_cr),
            "t_start_s": finite_or_none(self.t_start),
            "delay_s": finite_or_none(self.delay),
            "t_start_low_load_s": finite_or_none(self.t_start_low_load),
            "t_start_high_load_s": finite_or_none(self.t_start_high_load),
            "t_start_early_s": finite_or_none(self.t_start_early),
            "t_start_late_s": finite_or_none(self.t_start_late),
            "spill_load_factors": [low, high],
            **self.condition.to_dict(),
        }


def scaled_load(case: Case, factor: float) -> Case:
    """The flight case with its sliding-friction load F_p times `factor`."""
    fr = case.torque.friction
    if isinstance(fr, ThesisFlightFriction):
        fr = replace(fr, pressure_force=fr.pressure_force * factor)
    elif isinstance(fr, CoulombContactFriction):
        fr = replace(fr, normal_force=fr.normal_force * factor)
    else:
        raise TypeError("scaled_load needs a flight case (pressure-loaded friction)")
    return case.with_(torque=replace(case.torque, friction=fr))


def start_times(
    case: Case, condition: StartCondition, options: SolverOptions | None = None
) -> StartTimes:
    """t_cr, then t_start from the state at first light (the spill bracket, and the
    early and late bounds of theta_start with the thesis load).

    Parameters
    ----------
    case : Case
        A flight case (its opening angle is first light, beta_s).
    condition : StartCondition
        From :func:`obturator.model.start.start_condition` at the case's Mach.
    options : SolverOptions, optional

    Returns
    -------
    StartTimes
    """
    options = options or SolverOptions()
    first = simulate(case, options)
    nan = math.nan
    if not first.opened or not condition.startable:
        return StartTimes(first.opening_time if first.opened else nan, nan, nan, nan, condition)
    t_cr = first.opening_time
    y_cr = first.state[-1]
    rest = case.t_max - t_cr
    low, high = condition.spill_load_factors()
    runs = [(1.0, condition.theta_start), (low, condition.theta_start)]
    runs += [(high, condition.theta_start), (1.0, condition.theta_start_early)]
    runs.append((1.0, condition.theta_start_late))
    out = []
    for factor, theta in runs:
        if not math.isfinite(theta):
            out.append(nan)
            continue
        if theta >= case.opening_angle:  # a turned flow that starts before first light
            res = simulate(case.with_(theta_cr=theta), options, t_eval=None)
            out.append(res.opening_time if res.opened else nan)
            continue
        onward = scaled_load(case, factor).with_(theta_cr=theta, t_max=rest)
        res = simulate(onward, options, y0=y_cr, t_eval=None)
        out.append(t_cr + res.opening_time if res.opened else nan)
    return StartTimes(t_cr, out[0], out[1], out[2], condition, out[3], out[4])
