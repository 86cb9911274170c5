"""The regularisation widths each regularised path carries, refused outside them.

The regularised friction law turns stick into slip within a slip speed of
``friction_width * omega_p``; the narrower the width, the stiffer the stick phases.
The methods that integrate those phases with Radau IIA (``"regularised"``: DOP853, then
Radau IIA where stiff; ``"radau"``) do not carry every width of the allowed range:
below :data:`MIN_FRICTION_WIDTH` their t_cr jumps away from the width-free limit, far
above the trend of the width's own error, in every friction family and at every
tolerance measured (``python -m benchmarks.regularised_limits``, against the
set-valued solver at rtol 1e-12). There the width-free limit itself is the answer:
``method="set-valued"``. The default ``"auto"`` runs such cases set-valued.

Where options meet a case (:func:`check_width_resolved`, called by
:func:`~obturator.solve.integration_setup`): the explicitly chosen regularised methods
(:data:`WIDTH_BOUND_METHODS`) on a case with friction need ``friction_width >= rtol``
(both relative: the width to omega_p, rtol to the state): below it the integrator's
error control cannot resolve slip speeds of order the width, and t_cr leaves the
width-free limit by far more than the width's own error (measured basis: ``docs/benchmarks.md``,
History, "Width against tolerance"). ``"auto"`` is exempt (the cases it runs regularised
slide from release, where the width does not bind), and so are the reruns of a
convergence check of a case that ran ``"auto"`` or ``"set-valued"``
(:func:`width_rule_waived`).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any

from ..errors import InputError

__all__ = [
    "MIN_FRICTION_WIDTH",
    "WIDTH_BOUND_METHODS",
    "check_regularised_limits",
    "check_width_resolved",
    "width_rule_waived",
]

#: Smallest ``friction_width`` [1/omega_p] each method carries (methods not named: any
#: width of the allowed range).
MIN_FRICTION_WIDTH: dict[str, float] = {"regularised": 1e-10, "radau": 1e-10}


def check_regularised_limits(options: Any) -> None:
    """Raise InputError naming ``friction_width`` where `options`'s method cannot carry it.

    Parameters
    ----------
    options : SolverOptions
        Its ``method`` and ``friction_width`` (relative to the spin omega_p).
    """
    lo = MIN_FRICTION_WIDTH.get(options.method)
    if lo is not None and options.friction_width < lo:
        raise InputError(
            "friction_width",
            f"{options.friction_width:g} is outside the range method {options.method!r} "
            f"carries: [{lo:g}, 1] (relative to omega_p; its Radau IIA stick phases lose "
            "t_cr below it; method 'set-valued' is the width-free limit)",
        )


#: Methods that, chosen explicitly, need ``friction_width >= rtol`` on a case with
#: friction (:func:`check_width_resolved`).
WIDTH_BOUND_METHODS: frozenset[str] = frozenset({"regularised", "radau", "rosenbrock"})

#: True while :func:`width_rule_waived` is active in this thread or task.
_WAIVED: ContextVar[bool] = ContextVar("obturator_width_rule_waived", default=False)


@contextmanager
def width_rule_waived(waive: bool = True) -> Iterator[None]:
    """Within the block (where `waive`), :func:`check_width_resolved` passes every case.

    For the runs that a method the rule does not bind (``"auto"``, ``"set-valued"``) makes
    on the regularised path by itself: the reruns of its convergence check, the
    integrators' warm-up. Its own process only (a context variable).
    """
    token = _WAIVED.set(True) if waive else None
    try:
        yield
    finally:
        if token is not None:
            _WAIVED.reset(token)


def check_width_resolved(case: Any, options: Any) -> None:
    """Raise InputError naming ``friction_width`` where `options` run `case` with a width
    below ``rtol``.

    Parameters
    ----------
    case : Case
        Checked only if its torque has friction (``case.torque.is_regularised``): a
        frictionless case has no width to resolve.
    options : SolverOptions
        Checked only for the methods of :data:`WIDTH_BOUND_METHODS`;
        ``friction_width`` [1/omega_p] and ``rtol`` [-].
    """
    if options.method not in WIDTH_BOUND_METHODS or _WAIVED.get():
        return
    if not case.torque.is_regularised or options.friction_width >= options.rtol:
        return
    raise InputError(
        "friction_width",
        f"{options.friction_width:g} is below rtol {options.rtol:g} for method "
        f"{options.method!r}: the integrator cannot resolve slip speeds of order the width; "
        "use friction_width >= rtol, or method 'set-valued' (no width)",
    )
