"""Exceptions raised for non-physical or malformed input.

Every check names the offending field and the allowed range, so that the
command line can print it as one readable line.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, TypeVar

__all__ = [
    "InputError",
    "SolverError",
    "check_range",
    "replace_fields",
    "EXIT_INPUT",
    "EXIT_SOLVER",
    "EXIT_INTERNAL",
    "ClusterError",
    "EXIT_CLUSTER",
]

#: Process exit codes of the command line.
EXIT_INPUT = 2  # bad input: one line naming the field
EXIT_SOLVER = 3  # the integrator failed on valid input
EXIT_INTERNAL = 1  # anything else (a bug): one line, traceback with OBTURATOR_DEBUG=1
EXIT_CLUSTER = 4  # the Dask scheduler or a worker was lost; finished work is kept


class InputError(ValueError):
    """A parameter, config entry or data file is outside its allowed domain.

    Parameters
    ----------
    field : str
        Name of the offending field (as the user spelled it, e.g. ``hole_radius``).
    message : str
        What is wrong, including the allowed range.
    """

    def __init__(self, field: str, message: str) -> None:
        self.field = field
        self.message = message
        super().__init__(f"{field}: {message}")

    def __reduce__(self) -> tuple[type, tuple[str, str]]:
        # picklable with both arguments: a worker process's error reaches the parent
        return (type(self), (self.field, self.message))


class SolverError(RuntimeError):
    """The integrator failed (step-size underflow, step limit) on valid input.

    Not bad input: the command line reports it with its own exit code
    (:data:`EXIT_SOLVER`).

    Parameters
    ----------
    message : str
    status : obturator.status.Status, optional
        The integrator's status (``FAILED`` or ``STEP_LIMIT``), when known.
    """

    def __init__(self, message: str, *, status: object = None) -> None:
        super().__init__(message)
        self.status = status


class ClusterError(RuntimeError):
    """The Dask scheduler or a worker went away during a study.

    Finished points are already in the study's resume store; running the same
    command again (locally or with another ``--scheduler``) resumes it.
    """


def _fmt_interval(lo: float, hi: float, lo_open: bool, hi_open: bool) -> str:
    # infinite bounds are never attained: only finite values pass check_range
    left = "(" if lo_open or math.isinf(lo) else "["
    right = ")" if hi_open or math.isinf(hi) else "]"
    return f"{left}{lo:g}, {hi:g}{right}"


_D = TypeVar("_D")


def replace_fields(obj: _D, field: str, changes: dict[str, Any]) -> _D:
    """``dataclasses.replace(obj, **changes)`` after checking that each name is a field.

    Parameters
    ----------
    obj : dataclass instance
        The value to copy (its ``__post_init__`` checks the new values).
    field : str
        Field named by the error.
    changes : dict
        New values by field name.

    Raises
    ------
    InputError
        Naming the first unknown field and the allowed ones.
    """
    names = [f.name for f in dataclasses.fields(obj)]  # type: ignore[arg-type]
    for k in changes:
        if k not in names:
            raise InputError(field, f"unknown field {k!r}; allowed: {', '.join(names)}")
    return dataclasses.replace(obj, **changes)  # type: ignore[type-var]


def check_range(
    field: str,
    value: float,
    lo: float = -math.inf,
    hi: float = math.inf,
    *,
    lo_open: bool = False,
    hi_open: bool = False,
    unit: str = "",
) -> float:
    """Return ``float(value)`` if it lies in the interval, else raise :class:`InputError`.

    Parameters
    ----------
    field : str
        Field name used in the message.
    value : float
        Value to check; NaN and non-numbers are always rejected.
    lo, hi : float
        Interval bounds (in the same unit as `value`).
    lo_open, hi_open : bool
        Whether the bound itself is excluded.
    unit : str
        Unit shown in the message, e.g. ``"m"``.
    """
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(field, f"expected a number, got {value!r}") from None
    ok = math.isfinite(x) and (x > lo if lo_open else x >= lo) and (x < hi if hi_open else x <= hi)
    if not ok:  # the message is built only when needed (sweeps check ~20 fields a point)
        interval = _fmt_interval(lo, hi, lo_open, hi_open)
        suffix = f" {unit}" if unit else ""
        raise InputError(field, f"{x:g}{suffix} is outside the allowed range {interval}{suffix}")
    return x
