"""Named fit parameters (lmfit's ``Parameter``, frozen): value, bounds, transform, errors.

One class, :class:`FitParameter`, serves both as the registry's description of a
fittable parameter (:data:`FIT_PARAMETERS`, read from
:data:`obturator.params.FIT_SPECS`: start, bounds, physical range, transform and
the reason for them) and as a fitted result (value, standard error, 95 %
interval and how it was computed). :class:`ParameterSet` is the ordered set a
fit varies (lmfit's ``Parameters``): vectors of optimiser variables to values
and back, bounds, and the delta-method derivatives.

>>> p = FitParameter("mu_s", 0.5875, "1", stderr=0.0133, ci95=(0.56, 0.61))
>>> p.to_dict()["fitted"], p.to_dict()["ci95"]
(True, [0.56, 0.61])
>>> FIT_PARAMETERS["slip_speed"].to_internal(0.1)
-1.0
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._docs import field_docs
from ..errors import InputError
from ..params import FIT_PARAMS, Transform

__all__ = ["FIT_PARAMETERS", "FitParameter", "ParameterSet", "registered"]

_LN10 = math.log(10.0)


@field_docs
@dataclass(frozen=True)
class FitParameter:
    """One model parameter of a fit: its description and, after a fit, its estimate."""

    #: Parameter name (for a registered one its key in :data:`obturator.params.FIT_PARAMS`,
    #: e.g. ``"mu_s"``).
    name: str
    #: Best value (fitted), the value held fixed, or (registry) the default start, in `unit`.
    value: float
    #: Unit of `value`, `bounds`, `stderr`, `ci95` and `plausible` ("1": dimensionless).
    unit: str = "1"
    #: True when fitted.
    vary: bool = True
    #: Hard bounds (low, high) of the fit.
    bounds: tuple[float, float] = (-math.inf, math.inf)
    #: Standard error (fitted parameters only).
    stderr: float | None = None
    #: 95 % interval (fitted parameters only), computed by `ci_method`.
    ci95: tuple[float, float] | None = None
    #: How `ci95` is computed: "wald" (value +- t_{0.975, dof} stderr on the optimiser's scale,
    #: clipped to the bounds) or "profile" (profile likelihood).
    ci_method: str = "wald"
    #: The optimiser's variable: "linear" (value / `scale`) or "log10" (log10(value)).
    transform: Transform = "linear"
    #: Typical size of the value, for the linear transform (in `unit`).
    scale: float = 1.0
    #: The physically argued range (see `reason`).
    plausible: tuple[float, float] = (-math.inf, math.inf)
    #: Why the bounds and the range (from :data:`obturator.params.FIT_SPECS`).
    reason: str = ""

    @property
    def start(self) -> float:
        """The registry's default start (the value itself for an unregistered one)."""
        spec = FIT_PARAMS[self.name].fit if self.name in FIT_PARAMS else None
        return spec.start if spec is not None else self.value

    @property
    def log(self) -> bool:
        """Fitted in log10."""
        return self.transform == "log10"

    @property
    def justification(self) -> str:
        """The reason for the bounds (the validation registry's old name)."""
        return self.reason

    def to_internal(self, value: float) -> float:
        """Value -> optimiser variable (log10 or value / scale)."""
        return math.log10(value) if self.log else value / self.scale

    def from_internal(self, x: float) -> float:
        """Optimiser variable -> value."""
        return 10.0**x if self.log else x * self.scale

    def derivative(self, x: float) -> float:
        """d value / d x at the optimiser variable x (the delta method's factor)."""
        return self.from_internal(x) * _LN10 if self.log else self.scale

    def internal_bounds(self) -> tuple[float, float]:
        """Bounds in optimiser variables."""
        lo, hi = self.bounds
        return (self.to_internal(lo), self.to_internal(hi))

    def is_plausible(self, value: float | None = None) -> bool:
        """Whether `value` (default: this value) lies in the plausible range (inclusive)."""
        v = self.value if value is None else value
        lo, hi = self.plausible
        return lo <= v <= hi

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: value, unit, stderr, ci95, fitted."""
        return {
            "value": self.value,
            "unit": self.unit,
            "stderr": self.stderr,
            "ci95": list(self.ci95) if self.ci95 is not None else None,
            "fitted": self.vary,
        }


def registered(name: str, value: float | None = None, **changes: Any) -> FitParameter:
    """The registry's parameter `name` (value: the default start unless given).

    Raises
    ------
    InputError
        `name` is not fittable (the message lists the fittable ones).
    """
    p = FIT_PARAMS.get(name)
    if p is None or p.fit is None:
        raise InputError("fit", f"{name!r}; allowed: {', '.join(FIT_PARAMS)}")
    s = p.fit
    par = FitParameter(
        name,
        s.start if value is None else float(value),
        p.unit,
        bounds=s.bounds,
        transform=s.transform,
        scale=s.scale,
        plausible=s.plausible,
        reason=s.reason,
    )
    return replace(par, **changes) if changes else par


#: Every fittable parameter as the registry describes it (value: the default start).
FIT_PARAMETERS: dict[str, FitParameter] = {k: registered(k) for k in FIT_PARAMS}


@dataclass(frozen=True)
class ParameterSet:
    """The parameters a fit varies, in order (lmfit's ``Parameters``).

    Parameters
    ----------
    params : tuple of FitParameter
        Their bounds and transforms define the optimiser's variables x.
    """

    params: tuple[FitParameter, ...]

    @classmethod
    def of(
        cls, names: Sequence[str], bounds: Mapping[str, tuple[float, float]] | None = None
    ) -> ParameterSet:
        """The registry's parameters `names`, bounds replaced by those given."""
        b = bounds or {}
        return cls(
            tuple(registered(k, bounds=tuple(b[k])) if k in b else registered(k) for k in names)
        )

    def __len__(self) -> int:
        return len(self.params)

    def __iter__(self) -> Iterator[FitParameter]:
        return iter(self.params)

    @property
    def names(self) -> tuple[str, ...]:
        """Names in order."""
        return tuple(p.name for p in self.params)

    def to_internal(self, values: Sequence[float]) -> NDArray[np.float64]:
        """Values -> optimiser variables."""
        return np.array([p.to_internal(v) for p, v in zip(self.params, values, strict=True)])

    def from_internal(self, x: NDArray[np.float64]) -> list[float]:
        """Optimiser variables -> values."""
        return [p.from_internal(float(v)) for p, v in zip(self.params, x, strict=True)]

    def values(self, x: NDArray[np.float64]) -> dict[str, float]:
        """Name -> value at the optimiser variables x."""
        return dict(zip(self.names, self.from_internal(x), strict=True))

    def internal_bounds(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Lower and upper bounds of the optimiser variables."""
        b = [p.internal_bounds() for p in self.params]
        return np.array([lo for lo, _ in b]), np.array([hi for _, hi in b])

    def start(self, values: Sequence[float]) -> NDArray[np.float64]:
        """Optimiser variables of `values`, clipped into the bounds."""
        lo, hi = self.internal_bounds()
        return np.clip(self.to_internal(values), lo, hi) if self.params else np.empty(0)

    def derivatives(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """d value / d x per parameter at x (the delta method's factors)."""
        return np.array([p.derivative(float(v)) for p, v in zip(self.params, x, strict=True)])
