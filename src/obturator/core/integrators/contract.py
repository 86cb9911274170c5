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
  underflow, non-finite state) or, DOP853 only, ``STIFF``.

These are NamedTuples, so numba compiles them as plain tuples (and caches
functions that take them); the Python side reads fields by name.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from ...status import Status

__all__ = ["Problem", "Controls", "RawSolution", "Status"]


class Problem(NamedTuple):
    """What to integrate.

    Attributes
    ----------
    y0 : ndarray, shape (8,)
        Initial state (layout per formulation, see :mod:`obturator.core.dynamics`).
    p : ndarray
        Packed parameters (:mod:`obturator.core.layout`).
    scale : ndarray, shape (8,)
        Component scales of the error weights (1 for angles and quaternion
        components, omega_p0 for rates).
    t0 : float
        Start time [s] of `y0` (0 at release; later when ``auto`` hands a run
        from DOP853 to Radau IIA in flight).
    """

    y0: np.ndarray
    p: np.ndarray
    scale: np.ndarray
    t0: float = 0.0


class Controls(NamedTuple):
    """How to integrate.

    Attributes
    ----------
    t_max : float
        End time [s].
    rtol, atol : float
        Tolerances (see the module docstring for the error weights).
    h0, h_max : float
        Initial and largest step [s].
    max_steps : int
        Accepted-step limit (status ``STEP_LIMIT`` when reached).
    t_eval : ndarray
        Output times [s], increasing; empty for none.
    record : bool
        Store every accepted step when `t_eval` is empty.
    terminal : bool
        Stop at the first theta = theta_cr crossing (downwards).
    event_tol : float
        Bracket width at which the event time is accepted [s].
    hand_back : bool
        Radau IIA only (set by ``auto``): stop with status ``NONSTIFF`` once the slip
        speed has stayed above the saturation of the regularised Coulomb law for
        half a revolution (:func:`.radau_control.sliding_resumed`), so that ``auto``
        continues with the cheaper explicit method.
    """

    t_max: float
    rtol: float
    atol: float
    h0: float
    h_max: float
    max_steps: int
    t_eval: np.ndarray
    record: bool
    terminal: bool
    event_tol: float
    hand_back: bool = False


class RawSolution(NamedTuple):
    """What an integrator returns (SI units, raw state rows).

    Attributes
    ----------
    status : Status
    t_event : float
        Opening time t_cr [s]; NaN if theta did not reach theta_cr.
    y_event : ndarray, shape (8,)
        State at the event (NaN if none).
    t : ndarray
        Output times [s] (see ``Controls.record`` and ``Controls.t_eval``).
    y : ndarray, shape (len(t), 8)
        Output states.
    nfev, njev : int
        Right-hand-side and Jacobian evaluations.
    n_steps, n_rejected : int
        Accepted and rejected steps.
    t_end : float
        Time reached [s] (the event time when it stopped there).
    y_end : ndarray, shape (8,)
        State at ``t_end``.
    """

    status: Status
    t_event: float
    y_event: np.ndarray
    t: np.ndarray
    y: np.ndarray
    nfev: int
    njev: int
    n_steps: int
    n_rejected: int
    t_end: float
    y_end: np.ndarray
