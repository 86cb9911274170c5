"""One trajectory: :func:`simulate` (time history) and :func:`opening_time` (t_cr alone).

:func:`simulate` integrates one :class:`~obturator.model.case.Case` to the opening
event theta = theta_cr (thesis: theta_cr = beta_s) and returns a
:class:`~obturator.result.NutationResult`; :func:`opening_time` returns t_cr alone
(no time series stored). Many cases go through :func:`obturator.solve.opening_times`.

The default method ``"auto"`` chooses the integrator per case
(:mod:`obturator.solve.dispatch`): the set-valued solver (no width) at low spin where it
takes the case, the regularised law described below elsewhere, as the lanes do.

Numerics of the regularised law (``"regularised"``): at release the ball co-rotates,
omega_r = 0, and the sliding-friction direction is 0/0; near sticking the friction
torque is extremely stiff. Only
the magnitude of the friction torque is regularised (width delta [rad/s], one
of three families; see :func:`obturator.core.dynamics.applied_torque`); the thesis's
moment arm always uses the true slip direction. Integration is compiled: an
explicit Dormand-Prince 8(5,3) pair, which hands the run to a
fifth-order Radau IIA method when it detects stiffness (Radau's Newton
iterations cope with the strongly nonlinear stiffness of near-stick phases),
and back once the ball slides again; Radau alone or an L-stable Rosenbrock pair
can be chosen; the opening event is located by re-stepping to 1e-12 s.
"""

from __future__ import annotations

import numpy as np

from ..core.dynamics import observables
from ..core.integrators import RawSolution, integrate
from ..errors import SolverError
from ..model.case import Case
from ..result import NutationResult
from ..status import MESSAGES, Status
from .dispatch import core_method, dispatched_controls, dispatched_method
from .options import SolverOptions
from .setup import integration_setup

__all__ = ["opening_time", "simulate"]


def _run(
    case: Case,
    options: SolverOptions,
    y0: np.ndarray | None,
    record: bool,
    t_eval: np.ndarray | None,
    terminal: bool,
) -> tuple[np.ndarray, RawSolution]:
    """Pack the case, call the compiled integrator; return the parameters and its solution."""
    problem, controls = integration_setup(
        case, options, y0, record=record, t_eval=t_eval, terminal=terminal
    )
    method = dispatched_method(options.method, problem.p, problem.y0)
    controls = dispatched_controls(options.method, method, controls)
    return problem.p, integrate(core_method(method), problem, controls)


def simulate(
    case: Case,
    options: SolverOptions | None = None,
    *,
    y0: np.ndarray | None = None,
    t_eval: np.ndarray | None = None,
    terminal: bool = True,
) -> NutationResult:
    """Integrate one case and return its time history and opening time t_cr.

    Parameters
    ----------
    case : Case
    options : SolverOptions, optional
    y0 : ndarray, optional
        Initial state (see :func:`initial_state`); default: co-rotating release.
    t_eval : array_like, optional
        Output times [s] (dense output); default: every accepted step.
    terminal : bool
        Stop at the opening event (default) or continue to ``case.t_max``.

    Returns
    -------
    NutationResult
    """
    options = options or SolverOptions()
    p, out = _run(case, options, y0, True, t_eval, terminal)
    obs = observables(out.y, p) if len(out.t) else np.empty((0, 11))
    return NutationResult(
        t=out.t,
        theta=obs[:, 0],
        psi=np.unwrap(obs[:, 1]),
        phi=np.unwrap(obs[:, 2]),
        omega_r=obs[:, 3],
        torque=obs[:, 4],
        kinetic_energy=obs[:, 5],
        spin_rate=obs[:, 6],
        axial_momentum=obs[:, 7],
        power=obs[:, 8],
        opening_time=float(out.t_event),
        status=Status(out.status),
        message=MESSAGES[Status(out.status)],
        nfev=int(out.nfev),
        njev=int(out.njev),
        n_steps=int(out.n_steps),
        n_rejected=int(out.n_rejected),
        case=case,
        options=options,
        state=out.y,
    )


def opening_time(case: Case, options: SolverOptions | None = None) -> float:
    """Opening time t_cr [s] of a case (NaN if it does not open by ``case.t_max``).

    Stores no time series. Under the methods of the front door (``auto``, ``regularised``,
    ``set-valued``) this is :func:`~obturator.solve.opening_times` of a batch of one, so
    a case gives the same bits alone and in any study (:mod:`obturator.solve.plan`).

    Raises
    ------
    SolverError
        If the integrator fails or reaches its step limit (a RuntimeError).
    """
    options = options or SolverOptions()
    from .many import batchable, integrate_packed, pack_points

    if batchable(options):
        t_cr, codes, _ = integrate_packed(pack_points([case], options), options)
        status = Status(int(codes[0]))
        if status in (Status.FAILED, Status.STEP_LIMIT):
            raise SolverError(f"{case.name or 'case'}: {MESSAGES[status]}", status=status)
        return float(t_cr[0])
    _, out = _run(case, options, None, False, None, True)
    status = Status(out.status)
    if not status.success:
        raise SolverError(f"{case.name or 'case'}: {MESSAGES[status]}", status=status)
    return float(out.t_event)
