"""The thesis's opening-time curves as :class:`xarray.Dataset` objects (no plotting).

=====================================  ======================================
function                               thesis figures
=====================================  ======================================
:func:`opening_time_vs_spin`           Figs. 38-42 (Eq. 92 or exact t_cr)
:func:`fig43_study`                    Fig. 43 (data, T2 line, exact t_cr)
:func:`opening_time_minimum`           the t_cr minimum over omega_p (ch. V)
=====================================  ======================================
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, Literal

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike
from scipy.optimize import minimize_scalar

from ..calibration import (
    PRINTED_SUMS_OMITTED_RUNS,
    THESIS_FIT_MIN_SPIN,
    SpinRigData,
    load_thesis_data,
    thesis_least_squares,
)
from ..errors import InputError, check_range
from ..model.case import Case
from ..model.cases import rig_case, table1_ball
from ..reference import TABLE1, THESIS_MU_S
from ..solve import SolverOptions, opening_time, opening_times
from .common import RIG_T_MAX, rig_approx, solver_attrs

__all__ = ["fig43_study", "opening_time_minimum", "opening_time_vs_spin"]


def _approx_point(case: Case, mu_s: float) -> tuple[float, float, float]:
    sol = rig_approx(case, mu_s)
    return sol.opening_time(), sol.approximation_parameter, sol.zeta


def opening_time_vs_spin(
    spin_rates: ArrayLike,
    *,
    mu_s_values: Sequence[float] = (0.1, 0.25, 0.35, 0.55),
    theta0_deg_values: Sequence[float] = (TABLE1["theta0_deg"],),
    method: Literal["approx", "exact"] = "approx",
    weight: float = TABLE1["rig_weight"],
    t_max: float = 5.0,
    options: SolverOptions | None = None,
) -> xr.Dataset:
    """Rig opening time over the spin rate, thesis Figs. 38-42.

    Parameters
    ----------
    spin_rates : array_like
        omega_p [rad/s].
    mu_s_values : sequence of float
        Sliding friction coefficients [-] (Figs. 39, 42: 0.1, 0.25, 0.35, 0.55).
    theta0_deg_values : sequence of float
        Initial nutation angles [deg] (Figs. 40-41: 75, 80, 85).
    method : {"approx", "exact"}
        ``approx``: Eq. (92), as the thesis plotted (Table 1 ball, W, S);
        ``exact``: integrate the equations of motion (NaN where the ball does
        not open within `t_max`).
    weight : float
        W [N] (Table 1: 0.07987).
    t_max : float
        Exact runs only: give up after this time [s].
    options : SolverOptions, optional

    Returns
    -------
    xarray.Dataset
        ``t_cr(mu_s, theta0_deg, spin_rate)`` [s]; for ``approx`` also
        ``approximation_parameter`` M/(C omega_p^2) [-] and ``zeta`` [-].
    """
    if method not in ("approx", "exact"):
        raise InputError("method", f"{method!r}; allowed: approx, exact")
    w = np.atleast_1d(np.asarray(spin_rates, dtype=float))
    mus = [float(m) for m in mu_s_values]
    th0s = [float(x) for x in theta0_deg_values]
    shape = (len(mus), len(th0s), w.size)
    tcr = np.full(shape, np.nan)
    eps = np.full(shape, np.nan)
    zeta = np.full(shape, np.nan)
    cases = [
        rig_case(wk, mu, theta0_deg=th0, weight=weight, t_max=t_max)
        for mu in mus
        for th0 in th0s
        for wk in w
    ]
    if method == "exact":
        tcr[...] = opening_times(cases, options, strict=True)[0].reshape(shape)
    else:
        for flat, case in enumerate(cases):
            i, j, k = np.unravel_index(flat, shape)
            tcr[i, j, k], eps[i, j, k], zeta[i, j, k] = _approx_point(case, mus[i])
    dims = ("mu_s", "theta0_deg", "spin_rate")
    data: dict[str, Any] = {
        "t_cr": (dims, tcr, {"units": "s", "long_name": f"opening time ({method})"}),
    }
    if method == "approx":
        data["approximation_parameter"] = (
            dims,
            eps,
            {"units": "1", "long_name": "M / (C omega_p^2)"},
        )
        data["zeta"] = (dims, zeta, {"units": "1", "long_name": "damping ratio (Eq. 89)"})
    attrs: dict[str, Any] = {
        "figures": "38-42",
        "title": "Opening time vs spin rate",
        "method": method,
        "weight": weight,
    }
    if method == "exact":
        attrs.update(t_max=t_max, **solver_attrs(options))
    return xr.Dataset(
        data,
        coords={
            "mu_s": ("mu_s", mus, {"units": "1"}),
            "theta0_deg": ("theta0_deg", th0s, {"units": "deg"}),
            "spin_rate": ("spin_rate", w, {"units": "rad/s"}),
        },
        attrs=attrs,
    )


# ---------------------------------------------------------------------------
# Fig. 43


def _data_vars(data: SpinRigData, used: np.ndarray) -> dict[str, Any]:
    return {
        "data_spin_rate": ("run", data.spin_rate, {"units": "rad/s"}),
        "data_t_cr": ("run", data.opening_time, {"units": "s", "long_name": "measured t_cr"}),
        "data_starred": ("run", data.starred, {"units": "1"}),
        "data_used_in_fit": ("run", used, {"units": "1"}),
    }


def fig43_study(
    data: SpinRigData | None = None,
    *,
    spin_rates: ArrayLike | None = None,
    subset: Literal["printed", "starred"] = "printed",
    theta0_deg: float = TABLE1["theta0_deg"],
    t_max: float = 5.0,
    options: SolverOptions | None = None,
) -> xr.Dataset:
    """Data, least-squares line t = T2 omega_p and exact t_cr at the fitted mu_s (Fig. 43).

    The fit is chapter IV's (Eq. 96, T2 = sum t^2 / sum t omega); mu_s follows
    from Eq. (95) and Eq. (78). The exact model is run at that mu_s.

    Parameters
    ----------
    data : SpinRigData, optional
        Default: thesis Appendix B.
    spin_rates : array_like, optional
        Model spin rates [rad/s]; default 125..700 (the thesis's range), 47 points.
    subset : {"printed", "starred"}
        ``printed``: the 24 runs (starred minus runs 40, 41, 45, 51, with the
        printed omega_p) that reproduce the thesis's printed sums;
        ``starred``: all starred runs with omega_p = f pi / 9. Only for the
        thesis data; user data always use their starred runs.
    theta0_deg : float
        theta_0 [deg].
    t_max : float
        Give up on an exact run after this time [s] (NaN if not opened).
    options : SolverOptions, optional

    Returns
    -------
    xarray.Dataset
        Data on dimension ``run``; ``t_linear`` = T2 omega_p, ``t_eq94`` =
        T1/omega_p^3 + T2 omega_p (Eq. 94 with T1 = 2.039e5-style coefficient
        from the fitted mu_bar) and ``t_exact`` on ``spin_rate`` [s].
    """
    thesis = data is None
    data = load_thesis_data() if data is None else data
    if thesis and subset == "printed":
        fit_data = (
            data.fit_subset().exclude_runs(PRINTED_SUMS_OMITTED_RUNS).with_printed_spin_rate()
        )
    elif subset in ("printed", "starred"):
        fit_data = data.fit_subset()
    else:
        raise InputError("subset", f"{subset!r}; allowed: printed, starred")
    used = np.isin(data.run, fit_data.run)
    ls = thesis_least_squares(fit_data, theta0=math.radians(theta0_deg))
    w = np.linspace(125.0, 700.0, 47) if spin_rates is None else np.asarray(spin_rates, float)
    # Eq. (93)-(94): T1 = ((lambda+1)/lambda) M / (A cos theta0) with M = mu_bar W R_s
    ball = table1_ball()
    lam, a = ball.inertia_ratio, ball.transverse_inertia
    th0 = math.radians(theta0_deg)
    t1 = (lam + 1.0) / lam * ls.mu_bar * TABLE1["rig_weight"] * ball.radius / (a * math.cos(th0))
    cases = [rig_case(x, ls.mu_s, theta0_deg=theta0_deg, t_max=t_max) for x in w]
    t_exact = opening_times(cases, options, strict=True)[0]
    ds = xr.Dataset(
        {
            **_data_vars(data, used),
            "t_linear": ("spin_rate", ls.t2 * w, {"units": "s", "long_name": "t = T2 omega_p"}),
            "t_eq94": ("spin_rate", t1 / w**3 + ls.t2 * w, {"units": "s", "long_name": "Eq. 94"}),
            "t_exact": (
                "spin_rate",
                t_exact,
                {"units": "s", "long_name": f"exact, mu_s = {ls.mu_s:.4f}"},
            ),
        },
        coords={
            "run": ("run", data.run),
            "spin_rate": ("spin_rate", w, {"units": "rad/s"}),
        },
        attrs={
            "figures": "43",
            "title": "Data, least-squares line and exact solution",
            "subset": subset if thesis else "starred",
            "n_fit": ls.n,
            "T2": ls.t2,
            "T1": t1,
            "mu_bar": ls.mu_bar,
            "mu_s": ls.mu_s,
            "theta0_deg": theta0_deg,
            "t_max": t_max,
            **solver_attrs(options),
        },
    )
    return ds


# ---------------------------------------------------------------------------
# t_cr minimum over the spin rate (chapter V: ~150 rad/s)


def _exact_tcr(
    w: float, mu_s: float, theta0_deg: float, weight: float, t_max: float, options
) -> float:
    return opening_time(
        rig_case(w, mu_s, theta0_deg=theta0_deg, weight=weight, t_max=t_max), options
    )


def opening_time_minimum(
    mu_s: float = THESIS_MU_S,
    *,
    theta0_deg: float = TABLE1["theta0_deg"],
    weight: float = TABLE1["rig_weight"],
    bounds: tuple[float, float] = (40.0, 1000.0),
    n_grid: int = 50,
    t_max: float = RIG_T_MAX,
    xatol: float = 1e-3,
    options: SolverOptions | None = None,
) -> xr.Dataset:
    """Spin rate of minimum rig opening time, approximate (Eq. 92) and exact.

    Approximate: :func:`scipy.optimize.minimize_scalar` (bounded) on Eq. (92).
    Exact: a grid scan finds the smallest grid t_cr and a bounded Brent search
    on the neighbouring grid interval refines it. The exact model opens at
    every spin (t_cr rises steeply at low spin, about linearly at high spin);
    if some grid runs do not open within `t_max`, ``exact_boundary`` (refined
    by bisection) marks the lowest spin that does and only the opening branch
    above it is searched. At mu_s = 0.35 (Table 1) the exact minimum lies at
    about 147 rad/s, where the thesis (chapter V) puts it ("near 150").

    Parameters
    ----------
    mu_s : float
        Sliding friction coefficient [-] (chapter IV: 0.5473).
    theta0_deg : float
        theta_0 [deg].
    weight : float
        W [N].
    bounds : (float, float)
        Search interval of omega_p [rad/s].
    n_grid : int
        Grid points of the exact scan (linear in omega_p).
    t_max : float
        An exact run that has not opened by `t_max` [s] counts as not opening.
    xatol : float
        Absolute tolerance on omega_p of the bounded searches [rad/s].
    options : SolverOptions, optional

    Returns
    -------
    xarray.Dataset
        ``spin_rate_min(model)`` [rad/s] and ``t_cr_min(model)`` [s] for model
        in (approx, exact); ``exact_boundary`` [rad/s] (NaN if the ball opens
        over the whole interval); the scan ``t_cr_approx(spin_rate)``,
        ``t_cr_exact(spin_rate)`` [s].
    """
    lo, hi = (float(b) for b in bounds)
    check_range("bounds[0]", lo, 0.0, hi, lo_open=True, hi_open=True, unit="rad/s")

    def approx_t(w: float) -> float:
        case = rig_case(w, mu_s, theta0_deg=theta0_deg, weight=weight)
        return _approx_point(case, mu_s)[0]

    res_a = minimize_scalar(approx_t, bounds=(lo, hi), method="bounded", options={"xatol": xatol})
    w_a, t_a = float(res_a.x), float(res_a.fun)

    grid = np.linspace(lo, hi, n_grid)
    grid_cases = [
        rig_case(w, mu_s, theta0_deg=theta0_deg, weight=weight, t_max=t_max) for w in grid
    ]
    t_grid = opening_times(grid_cases, options, strict=True)[0]
    opened = np.isfinite(t_grid)
    closed = np.flatnonzero(~opened)
    # Only the opening branch above the highest non-opening grid point counts.
    first = int(closed[-1]) + 1 if closed.size else 0
    boundary = w_e = t_e = math.nan
    if first < grid.size:
        left_edge = grid[0]
        if first > 0:
            a, b = grid[first - 1], grid[first]
            while b - a > xatol:  # bisection for the sticking boundary
                m = 0.5 * (a + b)
                if math.isfinite(_exact_tcr(m, mu_s, theta0_deg, weight, t_max, options)):
                    b = m
                else:
                    a = m
            boundary = left_edge = b
        k = first + int(np.argmin(t_grid[first:]))
        left = max(grid[max(k - 1, 0)], left_edge)
        right = grid[min(k + 1, grid.size - 1)]

        def exact_t(w: float) -> float:
            t = _exact_tcr(w, mu_s, theta0_deg, weight, t_max, options)
            return t if math.isfinite(t) else t_max

        res_e = minimize_scalar(
            exact_t, bounds=(left, right), method="bounded", options={"xatol": xatol}
        )
        w_e, t_e = float(res_e.x), float(res_e.fun)
        if t_grid[k] < t_e:  # Brent can settle on the cliff side; keep the better point
            w_e, t_e = float(grid[k]), float(t_grid[k])
    t_approx_grid = np.array([approx_t(w) for w in grid])
    return xr.Dataset(
        {
            "spin_rate_min": ("model", [w_a, w_e], {"units": "rad/s"}),
            "t_cr_min": ("model", [t_a, t_e], {"units": "s"}),
            "exact_boundary": (
                (),
                boundary,
                {"units": "rad/s", "long_name": "lowest spin that opens within t_max"},
            ),
            "t_cr_approx": ("spin_rate", t_approx_grid, {"units": "s", "long_name": "Eq. 92"}),
            "t_cr_exact": ("spin_rate", t_grid, {"units": "s", "long_name": "exact"}),
        },
        coords={
            "model": ("model", ["approx", "exact"]),
            "spin_rate": ("spin_rate", grid, {"units": "rad/s"}),
        },
        attrs={
            "title": "Spin rate of minimum opening time",
            "thesis_value": 150.0,
            "mu_s": mu_s,
            "theta0_deg": theta0_deg,
            "weight": weight,
            "t_max": t_max,
            "fit_min_spin": THESIS_FIT_MIN_SPIN,
            **solver_attrs(options),
        },
    )
