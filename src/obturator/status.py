"""One status enumeration for every outcome: integrators, results, sweeps, the CLI.

The compiled integrators return the first five; studies add the two that only a
study can know (a point that is not a valid case, an opening that did not pass
the convergence check). Each value has one readable message
(:data:`MESSAGES`) and one flag name (:data:`FLAGS`, the CF ``flag_meanings``
of the ``status`` variable in sweep and Monte Carlo files).

>>> Status(2).name, Status.UNCONVERGED.value
('STEP_LIMIT', 4)
>>> MESSAGES[Status.OPENED]
'The bore opened: theta reached theta_cr.'
"""

from __future__ import annotations

from enum import IntEnum

__all__ = ["Status", "MESSAGES", "FLAGS"]


class Status(IntEnum):
    """Outcome of one integration or one study point.

    Integrator values: ``OPENED`` (1), ``T_MAX`` (0), ``STEP_LIMIT`` (2),
    ``FAILED`` (-1). The hand-over signals between the explicit and the implicit method
    are not outcomes and live apart
    (:class:`obturator.core.integrators.switching.HandOff`, values 3 and 6, which no
    status takes).
    Study values:
    ``INVALID_INPUT`` (-2, the point is not a valid case and was not
    integrated), ``UNCONVERGED`` (4, opened but t_cr moved by more than the
    threshold in the convergence check) and, for trajectory-coupled flights
    (:mod:`obturator.envelope`), ``SUBSONIC`` (5, the projectile fell below Mach 1
    before the bore opened, where the normal-shock load model ends).
    """

    INVALID_INPUT = -2
    FAILED = -1
    T_MAX = 0
    OPENED = 1
    STEP_LIMIT = 2
    UNCONVERGED = 4
    SUBSONIC = 5

    @property
    def message(self) -> str:
        """The readable message of this status."""
        return MESSAGES[self]

    @property
    def success(self) -> bool:
        """True when the integration ended normally (opened or reached t_max)."""
        return self in (Status.OPENED, Status.T_MAX, Status.UNCONVERGED)


#: Readable message of each status.
MESSAGES: dict[Status, str] = {
    Status.INVALID_INPUT: "Not a valid case: the point was not integrated.",
    Status.FAILED: "Integration failed: step size underflow or non-finite state.",
    Status.T_MAX: "Reached t_max before the bore opened.",
    Status.OPENED: "The bore opened: theta reached theta_cr.",
    Status.STEP_LIMIT: "Step limit reached before the bore opened or t_max.",
    Status.UNCONVERGED: "The bore opened, but t_cr is not converged (convergence check).",
    Status.SUBSONIC: "The flight went subsonic before the bore opened (no normal-shock load).",
}

#: Flag name of each status (CF ``flag_meanings`` in sweep and Monte Carlo files).
FLAGS: dict[Status, str] = {
    Status.INVALID_INPUT: "invalid_input",
    Status.FAILED: "solver_failed",
    Status.T_MAX: "not_opened_by_t_max",
    Status.OPENED: "opened",
    Status.STEP_LIMIT: "step_limit",
    Status.UNCONVERGED: "opened_not_converged",
    Status.SUBSONIC: "subsonic_before_opening",
}
