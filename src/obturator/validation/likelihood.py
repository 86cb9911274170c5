"""The likelihood of measured opening times under a model (issue 9, item 3; issue 29, item 5).

Noise model
-----------
Run i has measured opening time y_i at the recorded spin w_i. The model gives
m_i = t_cr(theta; w_i), or nothing if the ball has not opened by the horizon
T (``t_max``). The measurement is

    y_i = t_cr(theta; w_i + u_i) + e_i,

e_i ~ N(0, sigma_b(i)^2) the run-to-run scatter and u_i the spin error. The
regulator held the readout to +-5 Hz (+-1.75 rad/s, thesis chapter III.B),
taken as u_i uniform on that band: SD sigma_w = 1.75/sqrt(3) = 1.01 rad/s
(:data:`SPIN_SD`). Propagated to first order (the effective-variance method of
errors in variables):

    s_i^2 = sigma_b(i)^2 + (g_i sigma_w)^2,  g_i = dt_cr/domega_p at w_i,

with g_i the secant slope of the model over the regulation band,
(t(w_i + 1.75) - t(w_i - 1.75)) / 3.5 rad/s, which is robust to the small
ripple of t_cr in omega_p (see :func:`obturator.calibration.fit_exact`).

Which sigma_b (``noise``):

* ``"band"`` (the default of ``obturator validate``): one sigma per spin band
  of :data:`~.floor.BANDS` (by cluster-mean spin), each fitted by maximum
  likelihood together with the model. The replicate scatter of the thesis runs
  differs tenfold between bands (pooled pure-error SD 0.104 s below 120 rad/s,
  0.012-0.013 s at 120-300 rad/s, 0.039 s above; :mod:`.floor`), so a single
  sigma lets the noisy slow runs pull the fit and hides misfit in the quiet
  middle bands. Why fitted and not the floor's band SDs plugged in: the floor's
  SD below 120 rad/s is the four runs at 78 rad/s, where t_cr changes fastest
  with spin, so it already contains most of the spin-error scatter that the
  (g_i sigma_w)^2 term models; fixed floor SDs beside that term would count it
  twice. Fitting sigma_b with the term gives it only the rest. It also uses
  every run of the band (singletons included; the floor uses only the
  replicates: 6 pure-error degrees of freedom below 120 rad/s) and gives a
  band without replicates a sigma. A band with fewer than
  :data:`MIN_GROUP_RUNS` runs shares the sigma of its neighbour
  (:func:`noise_groups`): an ML sigma of one or two residuals collapses
  towards 0. Goodness of fit is then judged against the independent replicate
  floor, band by band (:mod:`.goodness`), not against these fitted sigmas.
* ``"pooled"``: one sigma for all runs (issue 9's likelihood).

Each fitted sigma counts in k (AIC, BIC): the band model has k = p + 4 on the
thesis runs, the same for every candidate, so differences between candidates
are unchanged by the count.

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

with s_i = sigma_b(i) for censored runs (no slope). Every run contributes; none is
dropped. AIC = 2k - 2 log L and BIC = k ln n - 2 log L, with k the fitted
physical parameters plus the fitted sigmas.

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

from ..errors import InputError
from ..fitting import minimize_bounded_scalar
from ..vocab import NOISE_MODELS, check_choice
from .floor import SPIN_REGULATION, band_labels

__all__ = [
    "LOG_2PI",
    "MIN_GROUP_RUNS",
    "SPIN_SD",
    "aic",
    "bic",
    "effective_sd",
    "nll_terms",
    "noise_groups",
    "profile_noise",
    "profile_sigma",
    "scaled_residuals",
]

#: SD of the spin error [rad/s]: uniform on the +-1.75 rad/s regulation band.
SPIN_SD = SPIN_REGULATION / math.sqrt(3.0)
LOG_2PI = math.log(2.0 * math.pi)
_SIGMA_RANGE = (1e-5, 10.0)  # s
#: Fewest runs that get their own sigma under ``noise="band"``.
MIN_GROUP_RUNS = 3


def effective_sd(sigma: float, slope: ArrayLike, spin_sd: float = SPIN_SD) -> NDArray[np.float64]:
    """s_i = sqrt(sigma^2 + (g_i sigma_w)^2) [s].

    Parameters
    ----------
    sigma : float or array_like
        Run-to-run scatter [s] (one value, or one per run).
    slope : array_like
        g_i = dt_cr/domega_p [s^2] (NaN counts as 0).
    spin_sd : float
        sigma_w [rad/s].
    """
    g = np.nan_to_num(np.asarray(slope, dtype=float), nan=0.0)
    sig = np.asarray(sigma, dtype=float)
    return np.sqrt(sig * sig + (g * spin_sd) ** 2)


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


def noise_groups(band: ArrayLike, noise: str = "band") -> NDArray[np.str_]:
    """The sigma group of each run: its spin band, or ``"all"``.

    Under ``"band"`` a band with fewer than :data:`MIN_GROUP_RUNS` runs joins the
    next band down the spin range that has runs (the next one up for the lowest);
    if all runs together are fewer, they share one sigma.

    Parameters
    ----------
    band : array_like of str
        Band label of each run (:func:`~.floor.band_of`, by cluster-mean spin).
    noise : {"band", "pooled"}
    """
    check_choice("noise", noise, NOISE_MODELS)
    labels = np.asarray(band).astype(str).reshape(-1)
    if noise == "pooled" or labels.size < MIN_GROUP_RUNS:
        return np.full(labels.size, "all")
    order = [b for b in band_labels() if np.any(labels == b)]
    order += sorted(set(labels.tolist()) - set(order))  # labels from elsewhere, if any
    counts = {b: int(np.sum(labels == b)) for b in order}
    target = {b: b for b in order}
    while True:
        small = [b for b in order if counts[b] < MIN_GROUP_RUNS]
        if not small or len(order) == 1:
            break
        b = small[0]
        i = order.index(b)
        into = order[i - 1] if i > 0 else order[i + 1]
        counts[into] += counts.pop(b)
        order.remove(b)
        for k, v in target.items():
            if v == b:
                target[k] = into
    return np.array([target[b] for b in labels.tolist()], dtype=str)


def profile_noise(
    measured: ArrayLike,
    model: ArrayLike,
    slope: ArrayLike,
    t_max: float,
    groups: ArrayLike,
    spin_sd: float = SPIN_SD,
) -> tuple[NDArray[np.float64], dict[str, float], float]:
    """Maximum-likelihood sigma of each group [s] and the minimised total -log L.

    The runs of one group share a sigma and the terms of -log L separate by
    group, so each group's sigma is :func:`profile_sigma` of its own runs.

    Returns
    -------
    sigma_per_run : ndarray
        sigma_b(i) of each run [s].
    sigma_by_group : dict of str to float
        Each group's sigma [s].
    nll : float
        Total -log L.
    """
    y = np.asarray(measured, dtype=float).reshape(-1)
    m = np.asarray(model, dtype=float).reshape(-1)
    g = np.asarray(slope, dtype=float).reshape(-1)
    lab = np.asarray(groups).astype(str).reshape(-1)
    if not (y.size == m.size == g.size == lab.size):
        raise InputError("groups", f"has {lab.size} entries, expected {y.size} (one per run)")
    per_run = np.empty(y.size)
    by_group: dict[str, float] = {}
    total = 0.0
    for name in dict.fromkeys(lab.tolist()):
        sel = lab == name
        sigma, nll = profile_sigma(y[sel], m[sel], g[sel], t_max, spin_sd)
        per_run[sel] = sigma
        by_group[name] = sigma
        total += nll
    return per_run, by_group, total
