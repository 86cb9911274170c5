"""The likelihood of measured opening times under a model (issue 9, item 3).

Noise model
-----------
Run i has measured opening time y_i at the recorded spin w_i. The model gives
m_i = t_cr(theta; w_i), or nothing if the ball has not opened by the horizon
T (``t_max``). The measurement is

    y_i = t_cr(theta; w_i + u_i) + e_i,

e_i ~ N(0, sigma^2) the run-to-run scatter (sigma fitted, one value for all
runs) and u_i the spin error. The regulator held the readout to +-5 Hz
(+-1.75 rad/s, thesis chapter III.B), taken as u_i uniform on that band:
SD sigma_w = 1.75/sqrt(3) = 1.01 rad/s (:data:`SPIN_SD`). Propagated to first
order (the effective-variance method of errors in variables):

    s_i^2 = sigma^2 + (g_i sigma_w)^2,  g_i = dt_cr/domega_p at w_i,

with g_i the secant slope of the model over the regulation band,
(t(w_i + 1.75) - t(w_i - 1.75)) / 3.5 rad/s, which is robust to the small
ripple of t_cr in omega_p (see :func:`obturator.calibration.fit_exact`).

Why errors in variables, not per-cluster offsets: an offset per replicate
cluster adds 23 parameters for 54 runs (and is not identifiable for the 9
single runs), whereas the regulation band is documented and adds none. It
also makes physical sense of the scatter at 78 rad/s, where t_cr changes
fastest with spin.

Log-likelihood
--------------
For an opened run (a density)::

    log L_i = -1/2 log(2 pi) - log s_i - (y_i - m_i)^2 / (2 s_i^2)

For a run the model has not opened by T (right-censored model value: all we
know is t_cr > T, i.e. the residual y_i - t_cr is below y_i - T; a
probability, as in a Tobit model)::

    log L_i = log P(e < y_i - T) = log Phi((y_i - T) / s_i) = log(1 - Phi((T - y_i) / s_i))

with s_i = sigma for censored runs (no slope). Every run contributes; none is
dropped. AIC = 2k - 2 log L and BIC = k ln n - 2 log L, with k the fitted
physical parameters plus sigma.

For the Gauss-Newton steps (:func:`scaled_residuals`) a censored run enters
as if it had opened at the horizon, residual (T - y_i)/s_i: the limit of the
opened residual as m_i -> T, so the objective is continuous where a run
crosses the horizon; the reported likelihood uses the survival term above.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import log_ndtr

from ..fitting import minimize_bounded_scalar
from .floor import SPIN_REGULATION

__all__ = [
    "LOG_2PI",
    "SPIN_SD",
    "aic",
    "bic",
    "effective_sd",
    "nll_terms",
    "profile_sigma",
    "scaled_residuals",
]

#: SD of the spin error [rad/s]: uniform on the +-1.75 rad/s regulation band.
SPIN_SD = SPIN_REGULATION / math.sqrt(3.0)
LOG_2PI = math.log(2.0 * math.pi)
_SIGMA_RANGE = (1e-5, 10.0)  # s


def effective_sd(sigma: float, slope: ArrayLike, spin_sd: float = SPIN_SD) -> NDArray[np.float64]:
    """s_i = sqrt(sigma^2 + (g_i sigma_w)^2) [s].

    Parameters
    ----------
    sigma : float
        Run-to-run scatter [s].
    slope : array_like
        g_i = dt_cr/domega_p [s^2] (NaN counts as 0).
    spin_sd : float
        sigma_w [rad/s].
    """
    g = np.nan_to_num(np.asarray(slope, dtype=float), nan=0.0)
    return np.sqrt(sigma * sigma + (g * spin_sd) ** 2)


def nll_terms(
    measured: ArrayLike, model: ArrayLike, sd: ArrayLike, t_max: float
) -> NDArray[np.float64]:
    """Per-run negative log-likelihood -log L_i (see the module notes).

    Parameters
    ----------
    measured : array_like
        y_i [s].
    model : array_like
        m_i [s]; NaN where the model did not open by `t_max` (censored).
    sd : array_like
        s_i [s].
    t_max : float
        Horizon T [s].
    """
    y = np.asarray(measured, dtype=float)
    m = np.asarray(model, dtype=float)
    s = np.broadcast_to(np.asarray(sd, dtype=float), y.shape)
    cens = ~np.isfinite(m)
    out = np.empty(y.shape)
    z = (y[~cens] - m[~cens]) / s[~cens]
    out[~cens] = 0.5 * LOG_2PI + np.log(s[~cens]) + 0.5 * z * z
    out[cens] = -log_ndtr((y[cens] - t_max) / s[cens])
    return out


def scaled_residuals(
    measured: ArrayLike, model: ArrayLike, sd: ArrayLike, t_max: float
) -> NDArray[np.float64]:
    """(m_i - y_i)/s_i, with m_i = T for censored runs (Gauss-Newton residuals)."""
    y = np.asarray(measured, dtype=float)
    m = np.asarray(model, dtype=float)
    return (np.where(np.isfinite(m), m, t_max) - y) / np.asarray(sd, dtype=float)


def profile_sigma(
    measured: ArrayLike,
    model: ArrayLike,
    slope: ArrayLike,
    t_max: float,
    spin_sd: float = SPIN_SD,
) -> tuple[float, float]:
    """Maximum-likelihood sigma [s] and the minimised total -log L.

    Without censored runs and without slopes this is the closed form
    sigma^2 = mean((y - m)^2); otherwise a bounded scalar minimisation in
    log sigma over 1e-5..10 s.
    """
    y = np.asarray(measured, dtype=float)
    m = np.asarray(model, dtype=float)
    g = np.nan_to_num(np.asarray(slope, dtype=float), nan=0.0)
    g = np.where(np.isfinite(m), g, 0.0)

    def total(log_sigma: float) -> float:
        s = effective_sd(math.exp(log_sigma), g, spin_sd)
        return float(np.sum(nll_terms(y, m, s, t_max)))

    if np.all(np.isfinite(m)) and (spin_sd == 0.0 or not np.any(g)):
        sigma = float(np.sqrt(np.mean((y - m) ** 2)))
        sigma = min(max(sigma, _SIGMA_RANGE[0]), _SIGMA_RANGE[1])
        return sigma, total(math.log(sigma))
    lo, hi = (math.log(x) for x in _SIGMA_RANGE)
    log_sigma, nll = minimize_bounded_scalar(total, (lo, hi), 1e-8)
    return math.exp(log_sigma), nll


def aic(nll: float, k: int) -> float:
    """Akaike information criterion 2k + 2 nll."""
    return 2.0 * k + 2.0 * nll


def bic(nll: float, k: int, n: int) -> float:
    """Bayesian information criterion k ln n + 2 nll."""
    return k * math.log(n) + 2.0 * nll
