"""One fit engine and one fit-parameter registry for the calibration and the validation.

* :mod:`.parameters` - :class:`FitParameter` (a parameter's registry entry and,
  after a fit, its estimate), :class:`ParameterSet` (the fitted set and its
  optimiser variables), :data:`FIT_PARAMETERS` (every fittable parameter, read
  from the bounds table :data:`obturator.params.FIT_SPECS`);
* :mod:`.engine` - the optimiser calls: bounded least squares, the Jacobian at
  the optimum, bounded scalar minimisation;
* :mod:`.intervals` - covariance, standard errors, Wald and profile-likelihood
  intervals.

The studies keep only their objective: the calibration's residuals of t_cr
(:func:`obturator.calibration.fit_exact`), the validation's censored likelihood
with errors in variables (:func:`obturator.validation.fit_candidate`).
"""

from .engine import (
    LeastSquaresSettings,
    Minimum,
    central_jacobian,
    minimize_bounded_scalar,
    minimize_least_squares,
)
from .intervals import CHI2_95, Estimate, covariance_internal, profile_limit, wald
from .parameters import FIT_PARAMETERS, FitParameter, ParameterSet, registered

__all__ = [
    "CHI2_95",
    "FIT_PARAMETERS",
    "Estimate",
    "FitParameter",
    "LeastSquaresSettings",
    "Minimum",
    "ParameterSet",
    "central_jacobian",
    "covariance_internal",
    "minimize_bounded_scalar",
    "minimize_least_squares",
    "profile_limit",
    "registered",
    "wald",
]
