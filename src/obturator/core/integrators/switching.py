"""One policy for moving between the explicit and the implicit method, for every driver.

The equations of motion are stiff only near stick (the friction Jacobian grows like
M / (A |omega_r|) as the slip speed omega_r shrinks), so each driver runs the explicit
DOP853 where the ball slips fast and Radau IIA near stick, and all of them decide the
switch with the thresholds of one record, :data:`SWITCH`, and the tests below:

* DOP853 -> Radau IIA (the signal :attr:`HandOff.STIFF`): Hairer's stiffness test
  (:func:`stiffness_count`, as ``dop853.f``) or the step budget
  (:func:`over_step_budget`); used by :mod:`.dop853` and the DOP853 lanes;
* Radau IIA -> DOP853 under ``auto`` (the signal :attr:`HandOff.NONSTIFF`): sliding resumed
  (:func:`sliding_resumed`); used by :mod:`.radau` and the Radau IIA lanes;
* the set-valued solver's slips (:mod:`.stick_slip`): DOP853 stretches above
  :data:`FAST_SLIP` (M / A) h_max, each at most :data:`CHUNK` of the time the slip
  takes to halve, ended by the same stiffness test.

Both signals are internal (:class:`HandOff`, apart from the outcomes of
:class:`~obturator.status.Status`): ``auto``, the lanes and the set-valued solver act on
them, and no result carries them.
"""

from __future__ import annotations

import math
from enum import IntEnum
from typing import NamedTuple

from numba import njit

from ..._docs import field_docs

__all__ = [
    "AUTO_HAND_BACKS",
    "CHUNK",
    "FAST_SLIP",
    "HandOff",
    "NONSTIFF_SIGNAL",
    "STIFF_SIGNAL",
    "SLIDING_REVOLUTIONS",
    "SLIDING_WIDTHS",
    "STEPS_PER_PERIOD",
    "STEP_ALLOWANCE",
    "STIFF_HLAMBDA",
    "STIFF_STEPS",
    "SWITCH",
    "SwitchSettings",
    "over_step_budget",
    "sliding_resumed",
    "stiffness_count",
]


class HandOff(IntEnum):
    """Why an integrator stopped to hand the run to the other method: not an outcome.

    An integrator's ``status`` field carries either an outcome
    (:class:`~obturator.status.Status`) or one of these; the values are disjoint from the
    outcomes', so one integer tells which.
    """

    #: DOP853 only: stiff here (Hairer's test or the step budget); Radau IIA continues.
    STIFF = 3
    #: Radau IIA under ``auto`` only: sliding has resumed; DOP853 continues.
    NONSTIFF = 6


#: The signals as plain integers, for the compiled code's status variables (an outcome
#: member and an integer unify to an integer; two enumerations do not unify).
STIFF_SIGNAL = int(HandOff.STIFF)
NONSTIFF_SIGNAL = int(HandOff.NONSTIFF)


@field_docs
class SwitchSettings(NamedTuple):
    """The thresholds of the explicit/implicit switch (defaults: :data:`SWITCH`)."""

    #: DOP853 -> Radau IIA: h |lambda| beyond DOP853's stability boundary (6.1, dop853.f).
    stiff_hlambda: float = 6.1
    #: ... on this many accepted steps in a row (dop853.f: a sticking phase within a few
    #: dozen steps, not a single stiff-looking step).
    stiff_steps: int = 15
    #: ... the count restarts after this many calm steps in a row (dop853.f).
    calm_steps: int = 6
    #: DOP853 -> Radau IIA backstop: more tried steps than this per spin period of
    #: simulated time (non-stiff runs need ~15-70) ...
    steps_per_period: float = 200.0
    #: ... plus this fixed allowance (the start-up steps).
    step_allowance: int = 1000
    #: Radau IIA -> DOP853 (``auto``): a slip speed above this many regularisation widths
    #: leaves the regularised law saturated (1 - 5e-9, algebraic family): not stiff ...
    sliding_widths: float = 1e4
    #: ... for this many revolutions without a return below it (sticking recurs twice a
    #: revolution in the stick-slip phase, so half a revolution without it ends it).
    sliding_revolutions: float = 0.5
    #: Hand-backs Radau IIA -> DOP853 in one ``auto`` run; then Radau IIA runs to the end
    #: (bounds the cost of a run that keeps switching).
    auto_hand_backs: int = 4
    #: Set-valued slips: DOP853 above this slip speed in units of (M / A) h_max, where the
    #: largest step resolves the slip direction's relaxation (rate ~ M / (A |omega_r|)).
    fast_slip: float = 4.0
    #: ... each stretch at most this fraction of |omega_r| / |omega_r'|, so the slip cannot
    #: fall below half the threshold inside it.
    chunk: float = 0.5


#: The switch thresholds every driver uses.
SWITCH = SwitchSettings()

# module constants for the compiled code (numba freezes plain globals)
STIFF_HLAMBDA = SWITCH.stiff_hlambda
STIFF_STEPS = SWITCH.stiff_steps
CALM_STEPS = SWITCH.calm_steps
STEPS_PER_PERIOD = SWITCH.steps_per_period
STEP_ALLOWANCE = SWITCH.step_allowance
SLIDING_WIDTHS = SWITCH.sliding_widths
SLIDING_REVOLUTIONS = SWITCH.sliding_revolutions
AUTO_HAND_BACKS = SWITCH.auto_hand_backs
FAST_SLIP = SWITCH.fast_slip
CHUNK = SWITCH.chunk


@njit(cache=True, inline="always")
def stiffness_count(hl, n_stiff, n_calm):
    """Hairer's stiffness test after an accepted DOP853 step with estimate h |lambda| = `hl`
    and the runs so far: (n_stiff, n_calm, stiff). Stiff once `hl` exceeded
    :data:`STIFF_HLAMBDA` on :data:`STIFF_STEPS` accepted steps without
    :data:`CALM_STEPS` calm ones in a row between them."""
    if hl > STIFF_HLAMBDA:
        n_stiff += 1
        return n_stiff, 0, n_stiff >= STIFF_STEPS
    n_calm += 1
    if n_calm >= CALM_STEPS:
        n_stiff = 0
    return n_stiff, n_calm, False


@njit(cache=True, inline="always")
def over_step_budget(n_tried, steps_per_time, t, t0) -> bool:
    """DOP853's backstop: `n_tried` (accepted + rejected) steps exceed `steps_per_time`
    (:data:`STEPS_PER_PERIOD` per spin period) [1/s] over (t0, t] plus :data:`STEP_ALLOWANCE`."""
    return n_tried > steps_per_time * (t - t0) + STEP_ALLOWANCE


@njit(cache=True, fastmath=False, inline="always")
def sliding_resumed(t, t_stick, slip, spin, width):
    """After an accepted Radau IIA step at time t: (hand back, t_stick).

    t_stick is the last time the slip speed `slip` [rad/s] was below
    :data:`SLIDING_WIDTHS` regularisation widths `width` [rad/s]; the run hands back
    when the time since then covers :data:`SLIDING_REVOLUTIONS` revolutions at the
    spin `spin` [rad/s]. Shared by :func:`.radau.integrate` and the Radau lanes.
    """
    if slip < SLIDING_WIDTHS * width:
        return False, t
    return (t - t_stick) * abs(spin) >= 2.0 * math.pi * SLIDING_REVOLUTIONS, t_stick
