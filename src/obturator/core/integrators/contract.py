"""The contract every compiled integrator keeps: what goes in, what comes out.

An integrator is a module with ``integrate(problem, controls) -> RawSolution``,
compiled with numba (``nogil``, cached on disk). It integrates the equations
of motion of :mod:`obturator.core.dynamics` from t = t0 (0 at release) until the opening event
theta = theta_cr (``p[P_THETA_CR]``, a downward crossing) or ``t_max``:

* the event is tested at the end of every accepted step (Radau also at its
  collocation nodes) and located by re-stepping from the step start with a
  shorter step (Illinois false position, :mod:`.common`) to a bracket of
  ``event_tol``, so the event state is as accurate as an accepted step;
* with ``record`` and an empty ``t_eval`` every accepted step is stored (the
  start first, the event last); with ``t_eval`` the states at those times
  (method-specific dense output, never past the event when ``terminal``);
* ``terminal`` stops at the event; otherwise the run continues to ``t_max``
  with ``t_event`` kept;
* error weights are ``atol * scale[i] + rtol * max(|y_i|, |ynew_i|)`` (each
  method may transform (rtol, atol) internally, and says how);
* the status is a :class:`~obturator.status.Status`: ``OPENED``, ``T_MAX``,
  ``STEP_LIMIT`` (``max_steps`` accepted steps), ``FAILED`` (step size
  underflow, non-finite state); DOP853 and Radau IIA may instead stop with a hand-over
  signal (:class:`.switching.HandOff`, not an outcome).

These are NamedTuples, so numba compiles them as plain tuples (and caches
functions that take them); the Python side reads fields by name.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ..._docs import field_docs
from ...status import Status

__all__ = ["Problem", "Controls", "RawSolution", "Status"]


@field_docs
class Problem(NamedTuple):
    """What to integrate."""

    #: Initial state, shape (8,) (layout per formulation, see
    #: :mod:`obturator.core.dynamics`).
    y0: np.ndarray
    #: Packed parameters (:mod:`obturator.core.layout`).
    p: np.ndarray
    #: Component scales (shape (8,)) of the error weights (1 for angles and quaternion
    #: components, omega_p0 for rates).
    scale: np.ndarray
    #: Start time [s] of `y0` (0 at release; later when ``auto`` hands a run from DOP853 to Radau
    #: IIA in flight).
    t0: float = 0.0


@field_docs
class Controls(NamedTuple):
    """How to integrate."""

    #: End time [s].
    t_max: float
    #: Relative tolerance (see the module docstring for the error weights).
    rtol: float
    #: Absolute tolerance, scaled by `scale` per component (module docstring).
    atol: float
    #: Initial step [s].
    h0: float
    #: Largest step [s].
    h_max: float
    #: Accepted-step limit (status ``STEP_LIMIT`` when reached).
    max_steps: int
    #: Output times [s], increasing; empty for none.
    t_eval: np.ndarray
    #: Store every accepted step when `t_eval` is empty.
    record: bool
    #: Stop at the first theta = theta_cr crossing (downwards).
    terminal: bool
    #: Bracket width at which the event time is accepted [s].
    event_tol: float
    #: Radau IIA only (set by ``auto``): stop with the hand-over signal ``NONSTIFF`` once
    #: the slip speed has stayed above the saturation of the regularised Coulomb law for
    #: half a revolution (:func:`.switching.sliding_resumed`), so that ``auto`` continues
    #: with the cheaper explicit method. Every other integrator ignores it.
    stop_when_sliding: bool = False
    #: The set-valued solver only (:mod:`.stick_slip`, set by the front door's strategy
    #: ``slip_lanes``): stop with the hand-over signal ``NONSTIFF`` in the last slip (the
    #: ball no longer sticks), so that the slip continues in the DOP853 lanes
    #: (:mod:`.stick_slip_lanes`). Every other integrator ignores it.
    last_slip_to_lanes: bool = False


@field_docs
class RawSolution(NamedTuple):
    """What an integrator returns (SI units, raw state rows)."""

    #: How the integration ended: a :class:`obturator.status.Status`, or a hand-over signal
    #: (:class:`.switching.HandOff`) where DOP853 or Radau IIA stopped for the other method.
    status: int
    #: Opening time t_cr [s]; NaN if theta did not reach theta_cr.
    t_event: float
    #: State at the event, shape (8,) (NaN if none).
    y_event: np.ndarray
    #: Output times [s] (see ``Controls.record`` and ``Controls.t_eval``).
    t: np.ndarray
    #: Output states, shape (len(t), 8).
    y: np.ndarray
    #: Right-hand-side evaluations.
    nfev: int
    #: Jacobian evaluations.
    njev: int
    #: Accepted steps.
    n_steps: int
    #: Rejected steps.
    n_rejected: int
    #: Time reached [s] (the event time when it stopped there).
    t_end: float
    #: State at ``t_end``, shape (8,).
    y_end: np.ndarray
