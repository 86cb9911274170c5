"""The fit engine: every optimiser call of the calibration and the validation.

* :func:`minimize_least_squares`: bounded nonlinear least squares in the
  optimiser variables of a :class:`~.parameters.ParameterSet`
  (:func:`scipy.optimize.least_squares`, trust-region reflective), settings in
  :class:`LeastSquaresSettings` (the calibration's and the validation's differ
  in their finite-difference steps, see there);
* :func:`central_jacobian`: the Jacobian at the optimum by central differences,
  steps kept inside the bounds (the covariance's input, :mod:`.intervals`);
* :func:`minimize_bounded_scalar`: Brent's bounded scalar minimisation (the
  bootstrap's one-parameter refits and the likelihood's sigma).

Both finite-difference Jacobians take an optional ``prefetch``: a function that
evaluates the model at all the Jacobian's points at once (one batched solve, whose
lanes fill with every column's runs) and caches them, so the residual calls that
follow are cache look-ups. The points and the arithmetic of the differences stay
scipy's and this module's own; only the model values can move, by the rounding of
the batched solver (:func:`obturator.solve.opening_times`: bit-equal on the DOP853
lanes, ~1e-8 relative where a fuller batch puts stiff runs into Radau IIA lanes).
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import Literal, NamedTuple

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import least_squares, minimize_scalar

from .._docs import field_docs

__all__ = [
    "LeastSquaresSettings",
    "Minimum",
    "central_jacobian",
    "minimize_bounded_scalar",
    "minimize_least_squares",
]

Residuals = Callable[[NDArray[np.float64]], NDArray[np.float64]]
#: Evaluates (and caches) the model at many optimiser points at once.
Prefetch = Callable[[Sequence[NDArray[np.float64]]], None]
#: scipy >= 1.16 maps its finite differences through ``workers`` (older: no prefetch,
#: the same Jacobian one point at a time).
_LSQ_MAPS = "workers" in inspect.signature(least_squares).parameters


@field_docs
@dataclass(frozen=True)
class LeastSquaresSettings:
    """How :func:`minimize_least_squares` steps and stops."""

    #: Finite differences of the optimiser's Jacobian: "2-point" (forward) or "3-point"
    #: (central).
    jac: Literal["2-point", "3-point"] = "3-point"
    #: Relative step of those finite differences. t_cr ripples slightly in the parameters (see
    #: :func:`obturator.calibration.fit_exact`, Notes): the step must be large against that
    #: ripple's scale and small against the parameters' uncertainties.
    diff_step: float = 1e-4
    #: Variable scaling of the trust region (a number, or "jac": from the Jacobian's columns).
    x_scale: float | Literal["jac"] = "jac"
    #: Stopping tolerance on the relative step of x.
    xtol: float = 1e-8
    #: Stopping tolerance on the relative change of the cost.
    ftol: float = 1e-8
    #: Relative step of :func:`central_jacobian` at the optimum.
    covariance_step: float = 1e-4
    #: Most residual evaluations (finite-difference ones not counted); None: scipy's default,
    #: 100 per variable.
    max_nfev: int | None = None


class Minimum(NamedTuple):
    """Where :func:`minimize_least_squares` stopped."""

    x: NDArray[np.float64]
    success: bool
    message: str
    nfev: int
    #: Half the sum of squared residuals at x.
    cost: float = float("nan")
    #: Stopped because it used up its evaluations (``max_nfev``), not converged.
    exhausted: bool = False


def minimize_least_squares(
    residuals: Residuals,
    x0: NDArray[np.float64],
    bounds: tuple[NDArray[np.float64], NDArray[np.float64]],
    settings: LeastSquaresSettings,
    *,
    xtol: float | None = None,
    prefetch: Prefetch | None = None,
) -> Minimum:
    """Minimise sum(residuals(x)^2) over x within `bounds` (optimiser variables).

    Parameters
    ----------
    residuals : callable
        x -> residual vector (scaled: unit weights, or divided by their SDs).
    x0 : ndarray
        Start, inside `bounds`.
    bounds : (ndarray, ndarray)
        Lower and upper bounds of x.
    settings : LeastSquaresSettings
    xtol : float, optional
        Overrides ``settings.xtol`` (later passes of an iterated fit).
    prefetch : callable, optional
        Evaluates the residuals' model at a list of points at once (module notes);
        the optimiser's Jacobian hands it all its points before it asks for them.

    Returns
    -------
    Minimum
        x clipped into the bounds, the optimiser's verdict and its evaluations.
    """
    lo, hi = bounds
    res = least_squares(
        residuals,
        x0,
        bounds=(lo, hi),
        method="trf",
        jac=settings.jac,
        diff_step=settings.diff_step,
        x_scale=settings.x_scale,
        xtol=settings.xtol if xtol is None else xtol,
        ftol=settings.ftol,
        max_nfev=settings.max_nfev,
        **({"workers": _prefetching_map(prefetch)} if prefetch and _LSQ_MAPS else {}),
    )
    x = np.clip(res.x, lo, hi)
    exhausted = res.status == 0  # scipy's status 0: the evaluation budget ran out
    return Minimum(x, bool(res.success), str(res.message), int(res.nfev), res.cost, exhausted)


def _prefetching_map(prefetch: Prefetch) -> Callable[..., list[NDArray[np.float64]]]:
    """A map for scipy's finite differences (its ``workers``) that hands every point
    to `prefetch` first, then evaluates them one by one (cache look-ups)."""

    def mapped(fun: Callable[[NDArray[np.float64]], NDArray], points: Iterable) -> list:
        points = list(points)
        prefetch(points)
        return [fun(x) for x in points]

    return mapped


def central_jacobian(
    residuals: Residuals,
    x: NDArray[np.float64],
    bounds: tuple[NDArray[np.float64], NDArray[np.float64]],
    step: float,
    *,
    prefetch: Prefetch | None = None,
) -> NDArray[np.float64]:
    """d residuals / d x at x by central differences (step `step` max(|x_j|, 1)).

    A step that would leave the bounds stops at the bound (one-sided there).
    `prefetch`, if given, receives all 2 x.size points first (module notes).
    """
    lo, hi = bounds
    pairs = []
    for j in range(x.size):
        h = step * max(abs(x[j]), 1.0)
        xp, xm = x.copy(), x.copy()
        xp[j] = min(x[j] + h, hi[j])
        xm[j] = max(x[j] - h, lo[j])
        pairs.append((xp, xm))
    if prefetch is not None and pairs:
        prefetch([pt for pair in pairs for pt in pair])
    cols = [(residuals(xp) - residuals(xm)) / (xp[j] - xm[j]) for j, (xp, xm) in enumerate(pairs)]
    return np.column_stack(cols) if cols else np.empty((0, 0))


def minimize_bounded_scalar(
    objective: Callable[[float], float], bounds: tuple[float, float], xatol: float
) -> tuple[float, float]:
    """Brent's bounded minimisation of a scalar function: (argmin, minimum)."""
    res = minimize_scalar(objective, bounds=bounds, method="bounded", options={"xatol": xatol})
    return float(res.x), float(res.fun)
