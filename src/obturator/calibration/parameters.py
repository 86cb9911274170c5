"""Named fit parameters (lmfit's ``Parameter``, frozen): value, unit, bounds, errors.

A fit result holds one :class:`FitParameter` per model parameter, fitted
(``vary``) or held fixed, instead of parallel dicts of values, units and
errors. Defaults (start value, bounds, the optimiser's internal scale) come
from the registry :data:`obturator.params.FIT_PARAMS`.

>>> p = FitParameter("mu_s", 0.5875, "1", stderr=0.0133, ci95=(0.56, 0.61))
>>> p.to_dict()["fitted"], p.to_dict()["ci95"]
(True, [0.56, 0.61])
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from ..errors import InputError
from ..params import FIT_PARAMS

__all__ = ["FitParameter", "check_fit_names", "fit_bounds"]


@dataclass(frozen=True)
class FitParameter:
    """One model parameter of a fit.

    Attributes
    ----------
    name : str
    value : float
        Best value (fitted) or the value held fixed, in `unit`.
    unit : str
    vary : bool
        True when fitted.
    bounds : (float, float)
        Bounds of a fitted parameter.
    stderr : float or None
        Standard error (fitted parameters only).
    ci95 : (float, float) or None
        95 % Student-t interval, value +- t_{0.975, dof} stderr (fitted only).
    """

    name: str
    value: float
    unit: str
    vary: bool = True
    bounds: tuple[float, float] = (-math.inf, math.inf)
    stderr: float | None = None
    ci95: tuple[float, float] | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: value, unit, stderr, ci95, fitted."""
        return {
            "value": self.value,
            "unit": self.unit,
            "stderr": self.stderr,
            "ci95": list(self.ci95) if self.ci95 is not None else None,
            "fitted": self.vary,
        }


def check_fit_names(fit: Sequence[str]) -> tuple[str, ...]:
    """The fitted names without repeats; each must be fittable and mu_s among them."""
    names = tuple(dict.fromkeys(fit))
    for k in names:
        if k not in FIT_PARAMS:
            raise InputError("fit", f"{k!r}; allowed: {', '.join(FIT_PARAMS)}")
    if "mu_s" not in names:
        raise InputError("fit", "mu_s must be among the fitted parameters")
    return names


def fit_bounds(
    names: Sequence[str], bounds: Mapping[str, tuple[float, float]] | None
) -> dict[str, tuple[float, float]]:
    """Bounds of the fitted parameters: the registry's, replaced by those given."""
    out = {k: FIT_PARAMS[k].fit.bounds for k in names}  # type: ignore[union-attr]
    out.update({k: v for k, v in (bounds or {}).items() if k in out})
    return out
