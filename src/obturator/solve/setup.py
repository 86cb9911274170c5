"""What the compiled integrators take for one case: parameter vector, error scales, controls.

Shared by the one-trajectory path (:mod:`obturator.solve.one`) and the lanes
(:mod:`obturator.solve.many`), so both start every run from the same numbers.
"""

from __future__ import annotations

import math

import numpy as np

from ..core.dynamics import observables
from ..core.integrators import Controls, Problem
from ..core.layout import (
    FAMILY_CODES,
    FORM_CODES,
    N_PARAM,
    N_STATE,
    P_A,
    P_C,
    P_FAMILY,
    P_FORM,
    P_IP,
    P_KE0,
    P_SPEED,
    P_SPIN_MODE,
    P_THETA_CR,
    P_VISC,
    P_WIDTH,
    SPIN_CODES,
)
from ..core.specialised import specialise
from ..errors import InputError
from ..model.case import Case
from .limits import check_width_resolved
from .options import SolverOptions, max_step_periods

__all__ = ["error_scale", "integration_controls", "integration_setup", "pack_parameters"]


def pack_parameters(case: Case, options: SolverOptions, y0: np.ndarray | None = None) -> np.ndarray:
    """Flat float parameter vector for the compiled right-hand side."""
    ball = case.ball
    a, c = ball.transverse_inertia, ball.axial_inertia
    if y0 is None:
        y0 = case.initial_state(options.formulation)
    p = np.zeros(N_PARAM)
    p[P_A], p[P_C], p[P_IP] = a, c, case.projectile_inertia
    p[P_SPIN_MODE] = SPIN_CODES[case.spin_mode]
    p[P_FORM] = FORM_CODES[options.formulation]
    p[P_WIDTH] = options.friction_width * case.spin_rate
    p[P_THETA_CR] = case.opening_angle
    p[P_VISC:P_FAMILY] = case.torque.pack()
    p[P_SPEED : P_SPEED + 3] = case.torque.speed_law.pack()
    p[P_FAMILY] = FAMILY_CODES[options.friction_family]
    # total kinetic energy, read by the thesis's energy form only (Appendix A, C(4));
    # elsewhere it stays 0, so that packing calls no compiled code (a process that has
    # not loaded numba can pack points, obturator.sweeps.ahead)
    if case.spin_mode == "thesis-energy":
        obs = observables(y0[None, :], p)
        p[P_KE0] = obs[0, 5] + 0.5 * case.projectile_inertia * case.spin_rate**2
    return specialise(p)


def error_scale(case: Case, formulation: str) -> np.ndarray:
    """Component scales of the error weights: 1 for angles, omega_p0 for rates."""
    w = case.spin_rate
    if formulation == "euler":
        return np.array([1.0, w, 1.0, w, 1.0, w, w, 1.0])
    return np.array([1.0, 1.0, 1.0, 1.0, w, w, w, w])


def integration_controls(
    options: SolverOptions,
    t_max: float,
    h0: float,
    h_max: float,
    *,
    t_eval: np.ndarray | None = None,
    record: bool = False,
    terminal: bool = True,
) -> Controls:
    """The :class:`Controls` of `options` for a run to `t_max` [s] with initial step `h0`
    and largest step `h_max` [s] (as :func:`integration_setup` derives them from a case;
    the batched lanes rebuild them from their packed arrays)."""
    return Controls(
        t_max=t_max,
        rtol=options.rtol,
        atol=options.atol,
        h0=h0,
        h_max=h_max,
        max_steps=int(options.max_steps),
        t_eval=np.empty(0) if t_eval is None else t_eval,
        record=record,
        terminal=terminal,
        event_tol=options.event_tol,
    )


def integration_setup(
    case: Case,
    options: SolverOptions,
    y0: np.ndarray | None = None,
    *,
    record: bool = False,
    t_eval: np.ndarray | None = None,
    terminal: bool = True,
) -> tuple[Problem, Controls]:
    """What the compiled integrators take for one case: the packed problem and controls.

    The initial step is 1e-4 spin periods (``options.fixed_step`` where given: the
    fixed step of ``"moreau-jean"``) and the largest ``options.max_step`` or
    :func:`max_step_periods` of a period. Shared by the one-trajectory path and the batched lanes
    (:mod:`obturator.solve.many`), so both start from the same numbers.

    Raises
    ------
    InputError
        `y0` not of shape (8,), or `t_eval` not non-negative and increasing; a width
        the method cannot resolve at its rtol
        (:func:`~obturator.solve.limits.check_width_resolved`).
    """
    check_width_resolved(case, options)
    if y0 is None:
        y0 = case.initial_state(options.formulation)
    y0 = np.asarray(y0, dtype=float)
    if y0.shape != (N_STATE,):
        raise InputError("y0", f"expected shape ({N_STATE},), got {y0.shape}")
    period = 2.0 * math.pi / case.spin_rate
    te = np.empty(0) if t_eval is None else np.asarray(t_eval, dtype=float)
    if te.size and (np.any(np.diff(te) < 0) or te[0] < 0):
        raise InputError("t_eval", "times must be non-negative and increasing")
    controls = integration_controls(
        options,
        float(case.t_max),
        options.fixed_step if options.fixed_step is not None else 1e-4 * period,
        options.max_step if options.max_step is not None else max_step_periods(case) * period,
        t_eval=te,
        record=record,
        terminal=terminal,
    )
    p = pack_parameters(case, options, y0)
    return Problem(y0, p, error_scale(case, options.formulation)), controls
