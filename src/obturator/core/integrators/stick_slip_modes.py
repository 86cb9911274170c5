"""The modes of the exact stick-slip law: slip speed, stick admissibility, breakaway.

The pieces of :mod:`obturator.core.integrators.stick_slip` that decide and change the
mode of a state (Leine & Nijmeijer's switch model with the exact admissible set F of
:mod:`obturator.core.friction_sets`): the relative rotation omega_r and its rate,
whether the required reaction G_req lies inside F (stick), the kick that starts a slip
where it leaves F, and the rigid passage through an exit window where a kicked slip
falls back.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ..._docs import field_docs
from ...errors import InputError
from ..friction_sets import (
    breakaway_angle,
    exit_slip_direction,
    moment_scale,
    relative_rate,
    required_reaction,
    stick_margin,
    turn_rigidly,
)
from ..jit_flags import NO_REFCOUNT
from ..layout import (
    FRIC_COULOMB,
    FRIC_THESIS_FLIGHT,
    FRIC_THESIS_RIG,
    P_A,
    P_FRIC,
    P_SPEED,
    SPEED_CONSTANT,
)

__all__ = [
    "EVENT_DRIVEN",
    "EventDrivenSettings",
    "MODES",
    "ModeSettings",
    "HOME_IN",
    "KICK",
    "RELEASE_KICK",
    "STICK_SLIP",
    "TAKE_OFF",
    "HAND_OFF_KAPPA",
    "HAND_OFF_SLIP",
    "HOLD_THROUGH",
    "REKICK",
    "SLIP_FLOOR",
    "break_away",
    "check_set_valued_law",
    "excess",
    "slip",
    "slip_floor",
    "slip_rate",
    "slip_speed_unit",
    "stick_admissible",
    "stick_ratio",
    "through_window",
]


@field_docs
class ModeSettings(NamedTuple):
    """The mode decisions' thresholds (defaults: :data:`MODES`)."""

    #: A kicked slip that falls back below the kick inside an exit window of F is held
    #: rigidly through this fraction of the window left, then kicked again (with the
    #: larger excess there) ...
    rekick: float = 0.5
    #: ... unless no more than this is left [rad]: then through the window (a grazing
    #: exit, whose creep is below the kick's scale).
    hold_through: float = 1e-4
    #: Relative margin (of M) that G_req must keep inside F to enter stick (rounding of
    #: G_req on the boundary must not decide the mode).
    margin: float = 1e-9
    #: A slip is handed to the DOP853 lanes (:mod:`.stick_slip_lanes`) once the stick
    #: ratio kappa = |G_req| / M is at least this: on the rig a ball past kappa ~0.55 no
    #: longer sticks (``docs/stick_slip.md`` section 10); at 0.8 a handed slip comes back
    #: to the mode loop only rarely (at 0.55 often: a wasted hand-off) ...
    hand_off_kappa: float = 0.8
    #: ... and its slip speed is at least this, in units of (M / A) h_max
    #: (:func:`slip_speed_unit`: the direction then relaxes within ~2 largest steps) ...
    hand_off_slip: float = 0.5
    #: ... and the lanes hand it back where an accepted step ends below this (same
    #: units): DOP853 then still has ~4 largest steps per relaxation time of the slip
    #: direction, which is singular at zero slip.
    slip_floor: float = 0.25


#: The thresholds the mode decisions use.
MODES = ModeSettings()

# module constants for the compiled code (numba freezes plain globals)
REKICK = MODES.rekick
HOLD_THROUGH = MODES.hold_through
_MARGIN = MODES.margin
HAND_OFF_KAPPA = MODES.hand_off_kappa
HAND_OFF_SLIP = MODES.hand_off_slip
SLIP_FLOOR = MODES.slip_floor


@field_docs
class EventDrivenSettings(NamedTuple):
    """The mode transitions' thresholds (defaults: :data:`EVENT_DRIVEN`)."""

    #: Slip speed, in units of |omega_p|, at which a decaying slip with G_req inside F
    #: becomes stick (projecting from it moves the attitude by O(r^2 / a), below the
    #: step error).
    stick_slip: float = 1e-6
    #: Slip speed, in units of |omega_p|, given at breakaway: at 1e-9 Radau IIA hovered
    #: at the kick's level in the wide windows near theta = 49 deg (40 rad/s) and
    #: rounding decided whether a window slipped; at 1e-8 it took off in every window.
    kick: float = 1e-8
    #: The kick at release (zero slip, G_req well outside F: flight, the rig at some
    #: azimuths), where the slip takes off at once: larger kicks moved the flight t_cr.
    release_kick: float = 1e-9
    #: Fraction of the predicted time to zero slip taken as the step when homing in
    #: (the slip changes ~1 / (1 - home_in) fold across it; near 1 Newton fails).
    home_in: float = 0.5
    #: First Radau IIA step after a breakaway, in units of the kicked slip's age (the
    #: time from the exit of F to the kick): longer first steps let Newton land on a
    #: decaying branch of the non-smooth law.
    take_off: float = 1.0


#: The thresholds the mode loop uses.
EVENT_DRIVEN = EventDrivenSettings()

# module constants for the compiled code (numba freezes plain globals)
STICK_SLIP = EVENT_DRIVEN.stick_slip
KICK = EVENT_DRIVEN.kick
RELEASE_KICK = EVENT_DRIVEN.release_kick
HOME_IN = EVENT_DRIVEN.home_in
TAKE_OFF = EVENT_DRIVEN.take_off


def check_set_valued_law(p: np.ndarray, solver: str) -> None:
    """Refuse a friction law without a set-valued form here (InputError naming it).

    Taken: the thesis law (rig, flight) and the Coulomb patch law with a patch
    (a > 0), each with constant mu_s. A Coulomb point contact (a = 0) has a flat
    disc for its set (:mod:`obturator.core.friction_sets`): no limit to integrate.
    """
    code = p[P_FRIC]
    if code not in (FRIC_THESIS_RIG, FRIC_THESIS_FLIGHT, FRIC_COULOMB):
        raise InputError("torque_model", f"{solver} takes the thesis or the Coulomb patch law")
    if p[P_SPEED] != SPEED_CONSTANT:
        raise InputError("speed_law", f"{solver} takes a constant mu_s only")
    if code == FRIC_COULOMB and not p[P_FRIC + 5] > 0.0:
        raise InputError(
            "patch_radius",
            f"0 m: {solver} needs a contact patch (> 0 m); a point contact's set at "
            "zero slip is a flat disc and its t_cr has no limit as the width shrinks",
        )


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def slip(y: np.ndarray) -> tuple[float, float, float, float]:
    """omega_r (inertial) and |omega_r| [rad/s] of a state."""
    wx, wy, wz = relative_rate(y, y[7])
    return wx, wy, wz, math.sqrt(wx * wx + wy * wy + wz * wz)


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def stick_admissible(y: np.ndarray, p: np.ndarray) -> bool:
    """G_req of `y` inside F with the relative margin _MARGIN."""
    gx, gy, gz = required_reaction(y, p, y[7])
    return stick_margin(gx, gy, gz, p) > _MARGIN * moment_scale(p)


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def stick_ratio(y: np.ndarray, p: np.ndarray) -> float:
    """kappa = |G_req| / M [-] at `y` (inf for a law with no moment scale)."""
    gx, gy, gz = required_reaction(y, p, y[7])
    scale = moment_scale(p)
    return math.sqrt(gx * gx + gy * gy + gz * gz) / scale if scale > 0.0 else math.inf


def slip_floor(p: np.ndarray, h_max: float) -> float:
    """The slip speed [rad/s] below which the DOP853 lanes give a handed slip back to the
    mode loop: :data:`SLIP_FLOOR` (M / A) h_max."""
    return SLIP_FLOOR * slip_speed_unit(p, h_max)


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def slip_speed_unit(p: np.ndarray, h_max: float) -> float:
    """(M / A) h_max [rad/s]: the slip speed whose direction relaxes in about one largest
    step `h_max` [s] (relaxation rate ~ M / (A |omega_r|)); the unit of
    :data:`~.stick_slip.FAST_SLIP`."""
    return moment_scale(p) / p[P_A] * h_max


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def slip_rate(y: np.ndarray, f: np.ndarray) -> float:
    """d|omega_r|/dt [rad/s^2] at `y` with derivative `f` (omega_r' = R w' - omega_p' Z)."""
    wx, wy, wz, r = slip(y)
    if r == 0.0:
        return 0.0
    q0, q1, q2, q3 = y[0], y[1], y[2], y[3]
    s = 2.0 / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    a1, a2, a3 = f[4], f[5], f[6]
    ax = (1.0 - s * (q2 * q2 + q3 * q3)) * a1 + s * (q1 * q2 - q0 * q3) * a2
    ax += s * (q1 * q3 + q0 * q2) * a3
    ay = s * (q1 * q2 + q0 * q3) * a1 + (1.0 - s * (q1 * q1 + q3 * q3)) * a2
    ay += s * (q2 * q3 - q0 * q1) * a3
    az = s * (q1 * q3 - q0 * q2) * a1 + s * (q2 * q3 + q0 * q1) * a2
    az += (1.0 - s * (q1 * q1 + q2 * q2)) * a3 - f[7]
    return (wx * ax + wy * ay + wz * az) / r


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def excess(y: np.ndarray, p: np.ndarray) -> float:
    """-stick_margin of G_req at `y` [N m]: how far G_req is outside F."""
    gx, gy, gz = required_reaction(y, p, y[7])
    return -stick_margin(gx, gy, gz, p)


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def break_away(y: np.ndarray, p: np.ndarray, kick: float, work: np.ndarray) -> float:
    """Start a slip from zero slip at `y` (in place); returns the time it takes [s].

    Leaving F, the ball slips along the direction in which the friction gives way
    (:func:`~obturator.core.friction_sets.exit_slip_direction`: u = -G_req / |G_req|
    for the thesis law, perpendicular to the hole axis, so the inertia along u is A;
    the Coulomb patch law's ray is taken with the same inertia A for its timing) with
    |omega_r|(tau) = a tau + j tau^2 / 2, a = e / A and j = de/dt / A, e the excess
    of |G_req| over the radius of F.
    The slip starts at |omega_r| = `kick`, i.e. at the tau where that series reaches
    it, from the rigid motion turned on by omega_p tau (the slip's own turn there,
    ~ kick tau / 3, is dropped).
    """
    wp = y[7]
    a_inv = 1.0 / p[P_A]
    dphi = 1e-6
    e0 = excess(y, p)
    turn_rigidly(y, dphi if wp >= 0.0 else -dphi, work)
    rate = a_inv * max(e0, 0.0)
    jerk = a_inv * (excess(work, p) - e0) * abs(wp) / dphi
    tau = 0.0
    if jerk > 0.0:
        tau = (math.sqrt(rate * rate + 2.0 * jerk * kick) - rate) / jerk
    elif rate > 0.0:
        tau = kick / rate
    turn_rigidly(y, wp * tau, work)
    for i in range(4):
        y[i] = work[i]
    gx, gy, gz = required_reaction(y, p, wp)
    ux, uy, uz = exit_slip_direction(y, gx, gy, gz, p)
    if ux == 0.0 and uy == 0.0 and uz == 0.0:
        return tau
    ux, uy, uz = kick * ux, kick * uy, kick * uz
    q0, q1, q2, q3 = y[0], y[1], y[2], y[3]
    s = 2.0 / (q0 * q0 + q1 * q1 + q2 * q2 + q3 * q3)
    # body rates += R^T u
    y[4] += (1.0 - s * (q2 * q2 + q3 * q3)) * ux + s * (q1 * q2 + q0 * q3) * uy
    y[4] += s * (q1 * q3 - q0 * q2) * uz
    y[5] += s * (q1 * q2 - q0 * q3) * ux + (1.0 - s * (q1 * q1 + q3 * q3)) * uy
    y[5] += s * (q2 * q3 + q0 * q1) * uz
    y[6] += s * (q1 * q3 + q0 * q2) * ux + s * (q2 * q3 - q0 * q1) * uy
    y[6] += (1.0 - s * (q1 * q1 + q2 * q2)) * uz
    return tau


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def through_window(y, p, t, t_max, r_kick, ytry, ts, ys, n_out, t_eval, i_eval):
    """Hold the ball rigidly through part of an exit window of F (in place on `y`).

    For a slip that did not take off: |omega_r| has fallen below the kick with G_req
    outside F and Radau IIA's steps have collapsed. Where G_req only grazes the boundary
    of F its creep is below the kick's scale, and the ball turns rigidly to the end of the
    window; otherwise (more than :data:`HOLD_THROUGH` rad of window left) it turns
    through :data:`REKICK` of what is left and the mode loop kicks it again, with the
    larger excess there. Returns (t_end, i_eval, n_out), t_end < 0 where this does not
    apply (the run failed).
    """
    wp = y[7]
    window = -breakaway_angle(y, p, wp)
    if not (slip(y)[3] < r_kick and window > 0.0 and wp != 0.0):
        return -1.0, i_eval, n_out
    if window > HOLD_THROUGH:
        window *= REKICK
    t_new = min(t + (window + 1e-12) / abs(wp), t_max)
    while i_eval < t_eval.shape[0] and t_eval[i_eval] <= t_new:
        turn_rigidly(y, wp * (t_eval[i_eval] - t), ytry)
        ts[n_out] = t_eval[i_eval]
        for i in range(y.shape[0]):
            ys[n_out, i] = ytry[i]
        n_out += 1
        i_eval += 1
    turn_rigidly(y, wp * (t_new - t), ytry)
    for i in range(y.shape[0]):
        y[i] = ytry[i]
    return t_new, i_eval, n_out
