"""Bootstrap of the exact-model mu_s over resampled runs, on an interpolated t_cr table.

Refitting the exact model 200 times would cost 200 x ~15 x N integrations.
Instead a table of exact t_cr(mu_s, omega_i) is computed once on a small mu_s
grid at the data's own spin rates (so no interpolation in omega is needed) and
interpolated in mu_s by a cubic spline per run (:class:`OpeningTimeTable`).
Each bootstrap resample (runs drawn with replacement) refits mu_s alone,
theta_0 and S held at their best values, by a bounded scalar minimisation of
the resampled sum of squares (:func:`bootstrap_mu_s`, through the fit engine
:func:`obturator.fitting.minimize_bounded_scalar`). The interpolation error
is measured against fresh exact runs at the midpoints of the mu_s grid and
reported (``BootstrapResult.interpolation_error``). On the thesis data (28
starred runs, 88 mu_s rows) it is 2e-5 s, 1500 times below the 0.033 s rms
scatter of the data. The grid must be fine: t_cr(mu_s) ripples (see
:func:`obturator.calibration.fit_exact`, Notes), and 9 rows gave 6e-4 s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.interpolate import CubicSpline

from .._docs import field_docs
from ..errors import SolverError
from ..fitting import minimize_bounded_scalar
from .rig_model import model_opening_times_grid

__all__ = ["TableSettings", "OpeningTimeTable", "BootstrapResult", "bootstrap_mu_s"]


@field_docs
@dataclass(frozen=True)
class TableSettings:
    """How finely the bootstrap's t_cr table is computed."""

    #: Grid points per ripple period of t_cr(mu_s) (see ``fit_exact``, Notes).
    resolution: float = 6.0
    #: The table spans mu_s (1 +- halfwidth) around the best value, or +- 6 standard errors if that
    #: is wider.
    halfwidth: float = 0.05
    #: Cap on the table's mu_s rows (>= 4).
    max_points: int = 121
    #: Grid midpoints at which the table is checked against exact runs.
    verify: int = 12

    def mu_grid(
        self,
        mu_s: float,
        stderr: float,
        spin_rate: NDArray[np.float64],
        t_cr: NDArray[np.float64],
    ) -> NDArray[np.float64]:
        """The table's mu_s rows around a best fit.

        Parameters
        ----------
        mu_s, stderr : float
            Best mu_s and its standard error [-].
        spin_rate, t_cr : ndarray
            The runs' spins [rad/s] and best-fit model t_cr [s] (NaN: not opened),
            which set the ripple period pi mu_s / (omega_p t_cr) of t_cr(mu_s).
        """
        half = max(self.halfwidth * mu_s, 6.0 * stderr)
        ok = np.isfinite(t_cr)
        period = float(np.min(math.pi * mu_s / (spin_rate[ok] * t_cr[ok]))) if ok.any() else half
        n_rows = int(
            np.clip(math.ceil(2.0 * half * self.resolution / period) + 1, 4, self.max_points)
        )
        return np.linspace(max(mu_s - half, 1e-3), mu_s + half, n_rows)


@field_docs
@dataclass(frozen=True)
class OpeningTimeTable:
    """Exact t_cr on a mu_s grid at fixed spin rates, cubic-spline interpolated in mu_s."""

    #: Grid of mu_s [-] (increasing).
    mu_s: NDArray[np.float64]
    #: Spin rates [rad/s] (the data's own).
    spin_rate: NDArray[np.float64]
    #: Exact opening times [s], shape (n_mu, n_spin): one row per `mu_s`, one column per
    #: `spin_rate`.
    t_cr: NDArray[np.float64]
    #: Largest |spline - exact| [s] at the grid midpoints (NaN if unchecked).
    interpolation_error: float = math.nan
    #: The same relative to t_cr [-].
    interpolation_rel_error: float = math.nan
    #: Cubic spline of `t_cr` in `mu_s`, built at construction (private).
    _spline: CubicSpline = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "_spline", CubicSpline(self.mu_s, self.t_cr, axis=0))

    def __call__(self, mu_s: float) -> NDArray[np.float64]:
        """Interpolated t_cr [s] at every tabulated spin rate."""
        return self._spline(mu_s)

    @classmethod
    def build(
        cls,
        spin_rates: NDArray[np.float64],
        mu_grid: NDArray[np.float64],
        *,
        verify: int = 12,
        **model: Any,
    ) -> OpeningTimeTable:
        """Compute the table (and, with `verify`, its midpoint interpolation error).

        Parameters
        ----------
        spin_rates : ndarray
            Spin rates [rad/s].
        mu_grid : ndarray
            Increasing mu_s values [-]; rows with a non-opening run are dropped
            from the ends until the block around the grid centre opens everywhere.
        verify : int
            Number of grid midpoints (spread evenly) at which the exact model
            is run to measure the interpolation error; 0 skips the check.
        **model
            Keyword arguments of :func:`model_opening_times` other than mu_s.
        """
        mu_grid = np.asarray(mu_grid, dtype=float)
        rows = model_opening_times_grid(spin_rates, mu_grid, **model)
        ok = np.isfinite(rows).all(axis=1)
        centre = len(mu_grid) // 2
        if not ok[centre]:
            raise SolverError("exact model does not open at the centre of the mu_s grid")
        lo = centre
        while lo > 0 and ok[lo - 1]:
            lo -= 1
        hi = centre
        while hi + 1 < len(mu_grid) and ok[hi + 1]:
            hi += 1
        if hi - lo < 3:
            raise SolverError("fewer than 4 mu_s grid rows open at every spin rate")
        table = cls(mu_grid[lo : hi + 1], np.asarray(spin_rates, float), rows[lo : hi + 1])
        if not verify:
            return table
        mids = 0.5 * (table.mu_s[1:] + table.mu_s[:-1])
        pick = np.unique(np.linspace(0, mids.size - 1, min(int(verify), mids.size)).round())
        mids = mids[pick.astype(int)]
        exact = model_opening_times_grid(spin_rates, mids, **model)
        err = np.abs(np.array([table(m) for m in mids]) - exact)
        return cls(
            table.mu_s,
            table.spin_rate,
            table.t_cr,
            float(np.max(err)),
            float(np.max(err / exact)),
        )


@field_docs
@dataclass(frozen=True)
class BootstrapResult:
    """Bootstrap of the exact-model mu_s over resampled runs."""

    #: Refitted mu_s per resample [-].
    samples: NDArray[np.float64]
    #: Percentile interval (low, high) of mu_s [-] at `confidence`.
    interval: tuple[float, float]
    #: Two-sided level of the percentile interval [-] (e.g. 0.95).
    confidence: float
    #: Standard deviation of the samples [-].
    std: float
    #: Number of resamples of the runs (with replacement).
    n_resamples: int
    #: Seed of :func:`numpy.random.default_rng` that drew the resamples.
    seed: int
    #: Resamples whose optimum hit the table's mu_s range (interval unreliable if > 0).
    at_grid_edge: int
    #: The interpolated t_cr table on which each resample's mu_s was refitted.
    table: OpeningTimeTable = field(repr=False)

    @property
    def interpolation_error(self) -> float:
        """Largest midpoint interpolation error of the t_cr table [s]."""
        return self.table.interpolation_error


def bootstrap_mu_s(
    measured: NDArray[np.float64],
    table: OpeningTimeTable,
    *,
    n_resamples: int = 200,
    seed: int = 0,
    confidence: float = 0.95,
) -> BootstrapResult:
    """Percentile bootstrap of mu_s: resample runs, refit mu_s on the interpolated table.

    Parameters
    ----------
    measured : ndarray
        Measured t_cr [s], one per column of `table`.
    table : OpeningTimeTable
    n_resamples : int
    seed : int
        Seed of :func:`numpy.random.default_rng`.
    confidence : float
        Two-sided level of the percentile interval.
    """
    rng = np.random.default_rng(seed)
    n = measured.size
    lo, hi = float(table.mu_s[0]), float(table.mu_s[-1])
    tol = 1e-3 * (hi - lo)
    samples = np.empty(n_resamples)
    edge = 0
    for b in range(n_resamples):
        idx = rng.integers(0, n, n)
        t_b = measured[idx]

        def ss(mu: float, idx: NDArray[np.int64] = idx, t_b: NDArray[np.float64] = t_b) -> float:
            return float(np.sum((table(mu)[idx] - t_b) ** 2))

        mu_b, _ = minimize_bounded_scalar(ss, (lo, hi), 1e-6)
        samples[b] = mu_b
        edge += int(mu_b - lo < tol or hi - mu_b < tol)
    alpha = 0.5 * (1.0 - confidence)
    q = np.quantile(samples, [alpha, 1.0 - alpha])
    return BootstrapResult(
        samples=samples,
        interval=(float(q[0]), float(q[1])),
        confidence=confidence,
        std=float(np.std(samples, ddof=1)),
        n_resamples=n_resamples,
        seed=seed,
        at_grid_edge=edge,
        table=table,
    )
