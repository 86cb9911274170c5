"""The thesis's figure studies as labelled :class:`xarray.Dataset` objects (no plotting).

One function per figure family of Bloomer (1980):

=====================================  ======================================
function                               thesis figures
=====================================  ======================================
:func:`couette_study`                  Figs. 9-10 (viscous-only, Couette S)
:func:`flight_and_rig_study`           Figs. 13-14 (Table 1 flight and rig)
:func:`exact_vs_approximate`           Fig. 15 (Eq. 65 against the exact run)
:func:`density_study`                  Fig. 16 (6000 vs 10000 kg/m^3)
:func:`hole_radius_study`              Fig. 17 (r_s = 3.75 vs 5.58 mm)
:func:`rig_spin_study`                 Figs. 32-37 (rig, 40..1000 rad/s)
:func:`opening_time_vs_spin`           Figs. 38-42 (Eq. 92 or exact t_cr)
:func:`fig43_study`                    Fig. 43 (data, T2 line, exact t_cr)
:func:`opening_time_minimum`           the t_cr minimum over omega_p (ch. V)
=====================================  ======================================

Conventions: time ``t`` in s, nutation ``theta`` in **degrees** (as the
thesis plots it), spin rates in rad/s; every variable and coordinate carries a
``units`` attribute, and every Dataset records the solver settings it used.
Histories of different lengths share a ``sample`` dimension with a 2-D time
coordinate ``t(case, sample)``.

Every rig run opens: the single bottom contact of the rig (Eq. 61) cannot hold
a torque about the gravity axis X, so friction cannot keep the ball
co-rotating. At low spin the ball spends long near-stick phases and opens late
(about 17.7 s at 40 rad/s for mu_s = 0.35, 42.7 s for mu_s = 0.5473), so the
studies integrate until the bore opens with a generous horizon; a run that
still has not opened by it keeps t_cr = NaN and its history ends there.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from typing import Any, Literal

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike
from scipy.optimize import minimize_scalar

from ..approx import ApproximationWarning, rig_approximation
from ..calibration.data import (
    PRINTED_SUMS_OMITTED_RUNS,
    THESIS_FIT_MIN_SPIN,
    SpinRigData,
    load_thesis_data,
    thesis_least_squares,
)
from ..errors import InputError, SolverError, check_range
from ..model.cases import TABLE1, couette_case, flight_case, rig_case, table1_ball
from ..solve import Case, SolverOptions, opening_time, simulate

__all__ = [
    "CAPTION_SHEAR_CONSTANT",
    "THESIS_MU_S",
    "couette_shear_constant",
    "couette_study",
    "density_study",
    "exact_vs_approximate",
    "fig43_study",
    "flight_and_rig_study",
    "hole_radius_study",
    "opening_time_minimum",
    "opening_time_vs_spin",
    "rig_spin_study",
    "solver_attrs",
]

#: S printed in the caption of Fig. 9 [N m s]. Eq. (34) with the inputs listed
#: on the same page gives 2.13e-8 N m s, 56 times smaller.
CAPTION_SHEAR_CONSTANT = 1.2e-6
#: The sliding friction coefficient calibrated in chapter IV [-].
THESIS_MU_S = 0.5473
#: End time of histories that have not opened within their horizon [s].
STICK_T_END = 1.0
#: Horizon of rig opening-time searches [s]: the slowest thesis rig case
#: (40 rad/s, mu_s = 0.5473) opens at 42.7 s.
RIG_T_MAX = 300.0


def solver_attrs(options: SolverOptions | None = None) -> dict[str, Any]:
    """Solver settings as flat Dataset attributes (netCDF-safe scalars).

    Parameters
    ----------
    options : SolverOptions, optional
        Default :class:`~obturator.solve.SolverOptions`.
    """
    from .. import __version__

    o = options or SolverOptions()
    return {
        "solver_method": o.method,
        "solver_rtol": o.rtol,
        "solver_atol": o.atol,
        "solver_friction_width": o.friction_width,
        "solver_formulation": o.formulation,
        "obturator_version": __version__,
    }


def _history(
    case: Case, t_end: float, n_points: int, options: SolverOptions | None
) -> tuple[np.ndarray, np.ndarray, float]:
    """theta(t) [deg] on an even grid to `t_end` [s] (continuing past opening), and t_cr [s]."""
    t = np.linspace(0.0, t_end, n_points)
    res = simulate(case.with_(t_max=t_end), options, t_eval=t, terminal=False)
    if not res.success:
        raise SolverError(f"{case.name}: {res.message}")
    theta = np.full(n_points, np.nan)
    theta[: res.t.size] = np.degrees(res.theta)
    return t, theta, res.opening_time


def _end_time(t_cr: float, fallback: float, factor: float = 1.3) -> float:
    return factor * t_cr if math.isfinite(t_cr) else fallback


def _histories_dataset(
    dim: str,
    labels: Sequence[Any],
    label_attrs: dict[str, str],
    runs: list[tuple[np.ndarray, np.ndarray, float]],
    extra: dict[str, tuple[Sequence[Any], dict[str, str]]] | None = None,
) -> xr.Dataset:
    """Stack histories of equal sample count with a 2-D time coordinate."""
    t = np.stack([r[0] for r in runs])
    theta = np.stack([r[1] for r in runs])
    tcr = np.array([r[2] for r in runs])
    data: dict[str, Any] = {
        "theta": ((dim, "sample"), theta, {"units": "deg", "long_name": "nutation angle"}),
        "t_cr": (dim, tcr, {"units": "s", "long_name": "opening time (NaN: not opened)"}),
    }
    for name, (values, attrs) in (extra or {}).items():
        data[name] = (dim, np.asarray(values), attrs)
    coords = {
        dim: (dim, np.asarray(labels), label_attrs),
        "t": ((dim, "sample"), t, {"units": "s", "long_name": "time"}),
    }
    return xr.Dataset(data, coords=coords)


# ---------------------------------------------------------------------------
# Figs. 9-10


def couette_shear_constant() -> float:
    """Eq. (34) S = (8/3) pi R_s^4 mu_f / h for the Fig. 9 inputs [N m s] (2.13e-8)."""
    return couette_case(1.0).torque.viscous.coefficient


def couette_study(
    scales: Sequence[float] = (1.0, 10.0, 100.0, 1000.0),
    *,
    base: Literal["eq34", "caption"] = "eq34",
    t_end: float = 0.1,
    n_points: int = 1001,
    options: SolverOptions | None = None,
) -> xr.Dataset:
    """Viscous-only flight runs, Couette torque, thesis Figs. 9-10.

    Parameters
    ----------
    scales : sequence of float
        Multipliers of the base shear constant (Fig. 10: x1, x10, x100, x1000).
    base : {"eq34", "caption"}
        Base S: Eq. (34) with the inputs of p. 52 (R_s = 7.62 mm, h = 0.0254 mm,
        mu = 1.92e-5 Pa s: S = 2.13e-8 N m s), or the 1.2e-6 N m s printed in
        the caption of Fig. 9 (which Eq. 34 does not give for those inputs; the
        Fig. 10 labels ~1e-6 .. 1e-3 follow the caption).
    t_end : float
        End of the histories [s]; the thesis's criterion is opening within 0.1 s.
    n_points : int
        Samples per history.
    options : SolverOptions, optional

    Returns
    -------
    xarray.Dataset
        ``theta(scale, t)`` [deg], ``t_cr(scale)`` [s] (NaN: not opened by
        `t_end`), ``shear_constant(scale)`` [N m s], ``theta_end(scale)`` [deg].
    """
    if base not in ("eq34", "caption"):
        raise InputError("base", f"{base!r}; allowed: eq34, caption")
    s34 = couette_shear_constant()
    factor = 1.0 if base == "eq34" else CAPTION_SHEAR_CONSTANT / s34
    scales = [check_range("scale", s, 0.0, math.inf, lo_open=True) for s in scales]
    runs = [_history(couette_case(factor * s), t_end, n_points, options) for s in scales]
    ds = xr.Dataset(
        {
            "theta": (
                ("scale", "t"),
                np.stack([r[1] for r in runs]),
                {"units": "deg", "long_name": "nutation angle"},
            ),
            "t_cr": ("scale", [r[2] for r in runs], {"units": "s"}),
            "shear_constant": (
                "scale",
                [factor * s * s34 for s in scales],
                {"units": "N m s", "long_name": "Couette shear constant S (Eq. 34)"},
            ),
            "theta_end": ("scale", [r[1][-1] for r in runs], {"units": "deg"}),
        },
        coords={
            "scale": ("scale", np.asarray(scales), {"units": "1", "long_name": "S multiplier"}),
            "t": ("t", runs[0][0], {"units": "s"}),
        },
        attrs={
            "figures": "9, 10",
            "title": "Viscous-only (Couette) flight runs",
            "base": base,
            "shear_constant_eq34": s34,
            "shear_constant_caption": CAPTION_SHEAR_CONSTANT,
            "caption_over_eq34": CAPTION_SHEAR_CONSTANT / s34,
            "spin_rate": 12042.77,
            "theta_cr_deg": math.degrees(couette_case(1.0).opening_angle),
            **solver_attrs(options),
        },
    )
    return ds


# ---------------------------------------------------------------------------
# Figs. 13-14


def flight_and_rig_study(
    *,
    mu_s: float = TABLE1["mu_s"],
    n_points: int = 2001,
    options: SolverOptions | None = None,
) -> xr.Dataset:
    """Table 1 flight (Fig. 13) and spin-rig (Fig. 14) histories.

    Parameters
    ----------
    mu_s : float
        Sliding friction coefficient (Table 1: 0.35) [-].
    n_points : int
        Samples per history (each runs to 1.3 t_cr).
    options : SolverOptions, optional

    Returns
    -------
    xarray.Dataset
        ``theta(case, sample)`` [deg] with time coordinate ``t(case, sample)``
        [s], ``t_cr(case)`` [s], ``spin_rate(case)`` [rad/s]; case is
        ``flight`` (M_1 = 3, P_1 = 0.099 MPa, 12042 rad/s) or ``rig`` (200 rad/s).
    """
    cases = {"flight": flight_case(mu_s=mu_s), "rig": rig_case(TABLE1["rig_spin_rate"], mu_s)}
    runs = []
    for c in cases.values():
        tcr = opening_time(c, options)
        runs.append(_history(c, _end_time(tcr, c.t_max), n_points, options))
    ds = _histories_dataset(
        "case",
        list(cases),
        {"long_name": "Table 1 column"},
        runs,
        {"spin_rate": ([c.spin_rate for c in cases.values()], {"units": "rad/s"})},
    )
    ds.attrs.update(
        figures="13, 14",
        title="Table 1 flight (aerodynamic) and rig (gravitational) models",
        mu_s=mu_s,
        theta_cr_deg=math.degrees(cases["rig"].opening_angle),
        **solver_attrs(options),
    )
    return ds


# ---------------------------------------------------------------------------
# Fig. 15


def exact_vs_approximate(
    spin_rate: float = TABLE1["rig_spin_rate"],
    mu_s: float = TABLE1["mu_s"],
    *,
    theta0_deg: float = TABLE1["theta0_deg"],
    t_end: float | None = None,
    n_points: int = 2001,
    options: SolverOptions | None = None,
) -> xr.Dataset:
    """Exact and linearised (Eq. 65) rig histories, thesis Fig. 15.

    Parameters
    ----------
    spin_rate : float
        omega_p [rad/s] (Fig. 15: 200, the Table 1 rig).
    mu_s : float
        Sliding friction coefficient [-] (Table 1: 0.35).
    theta0_deg : float
        theta_0 [deg].
    t_end : float, optional
        End time [s]; default 1.3 times the exact t_cr.
    n_points : int
    options : SolverOptions, optional

    Returns
    -------
    xarray.Dataset
        ``theta_exact(t)``, ``theta_approx(t)`` [deg]; attributes ``t_cr_exact``,
        ``t_cr_eq92`` (Eq. 92), ``t_cr_eq65`` (first crossing of Eq. 65) [s],
        ``zeta`` and ``approximation_parameter`` M/(C omega_p^2).
    """
    case = rig_case(spin_rate, mu_s, theta0_deg=theta0_deg)
    tcr = opening_time(case, options)
    t, theta, _ = _history(case, t_end or _end_time(tcr, 1.0), n_points, options)
    approx = _rig_approx(case, mu_s)
    ds = xr.Dataset(
        {
            "theta_exact": ("t", theta, {"units": "deg", "long_name": "exact (Eq. 17)"}),
            "theta_approx": (
                "t",
                np.degrees(approx.nutation_angle(t)),
                {"units": "deg", "long_name": "approximate (Eq. 65)"},
            ),
        },
        coords={"t": ("t", t, {"units": "s"})},
        attrs={
            "figures": "15",
            "title": "Exact and approximate solutions, spin rig",
            "spin_rate": spin_rate,
            "mu_s": mu_s,
            "theta0_deg": theta0_deg,
            "theta_cr_deg": math.degrees(case.opening_angle),
            "t_cr_exact": tcr,
            "t_cr_eq92": approx.opening_time(),
            "t_cr_eq65": approx.crossing_time(),
            "zeta": approx.zeta,
            "approximation_parameter": approx.approximation_parameter,
            **solver_attrs(options),
        },
    )
    return ds


def _rig_approx(case: Case, mu_s: float):
    """Linearised solution matching a rig case (same ball, W, S, theta_0, theta_cr)."""
    fr = case.torque.friction
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ApproximationWarning)
        return rig_approximation(
            case.ball,
            mu_s=mu_s,
            spin_rate=case.spin_rate,
            theta0=case.theta0,
            viscous_coefficient=case.torque.viscous.coefficient,
            weight=fr.weight,
            theta_cr=case.opening_angle,
            check=False,
        )


# ---------------------------------------------------------------------------
# Figs. 16-17


def _geometry_study(
    dim: str,
    values: Sequence[float],
    unit: str,
    make_case,
    n_points: int,
    options: SolverOptions | None,
) -> xr.Dataset:
    cases = [make_case(v) for v in values]
    tcr = [opening_time(c, options) for c in cases]
    finite = [x for x in tcr if math.isfinite(x)]
    t_end = 1.3 * max(finite) if finite else STICK_T_END
    runs = [_history(c, t_end, n_points, options) for c in cases]
    return xr.Dataset(
        {
            "theta": (
                (dim, "t"),
                np.stack([r[1] for r in runs]),
                {"units": "deg", "long_name": "nutation angle"},
            ),
            "t_cr": (dim, tcr, {"units": "s"}),
            "weight": (dim, [c.torque.friction.weight for c in cases], {"units": "N"}),
            "axial_inertia": (dim, [c.ball.axial_inertia for c in cases], {"units": "kg m^2"}),
            "transverse_inertia": (
                dim,
                [c.ball.transverse_inertia for c in cases],
                {"units": "kg m^2"},
            ),
            "inertia_ratio": (dim, [c.ball.inertia_ratio for c in cases], {"units": "1"}),
            "theta_cr": (dim, [math.degrees(c.opening_angle) for c in cases], {"units": "deg"}),
        },
        coords={dim: (dim, np.asarray(values, dtype=float), {"units": unit}), "t": runs[0][0]},
    )


def density_study(
    densities: Sequence[float] = (6000.0, 10000.0),
    *,
    spin_rate: float = TABLE1["rig_spin_rate"],
    mu_s: float = TABLE1["mu_s"],
    n_points: int = 1501,
    options: SolverOptions | None = None,
) -> xr.Dataset:
    """Rig histories for several ball densities, thesis Fig. 16.

    C, A and the weight W (Eq. 61 load) all follow the density; every other
    input is Table 1's.

    Parameters
    ----------
    densities : sequence of float
        rho [kg/m^3] (Fig. 16: 6000 and 10000).
    spin_rate : float
        omega_p [rad/s].
    mu_s : float
        Sliding friction coefficient [-].
    n_points : int
    options : SolverOptions, optional

    Returns
    -------
    xarray.Dataset
        ``theta(density, t)`` [deg], ``t_cr(density)`` [s] and the mass
        properties per density.
    """
    ds = _geometry_study(
        "density",
        densities,
        "kg/m^3",
        lambda rho: rig_case(spin_rate, mu_s, ball=table1_ball(density=rho), weight=None),
        n_points,
        options,
    )
    ds["t"].attrs["units"] = "s"
    ds.attrs.update(
        figures="16",
        title="Effect of ball density",
        spin_rate=spin_rate,
        mu_s=mu_s,
        **solver_attrs(options),
    )
    return ds


def hole_radius_study(
    hole_radii: Sequence[float] = (3.75e-3, 5.58e-3),
    *,
    spin_rate: float = TABLE1["rig_spin_rate"],
    mu_s: float = TABLE1["mu_s"],
    n_points: int = 1501,
    options: SolverOptions | None = None,
) -> xr.Dataset:
    """Rig histories for several hole radii, thesis Fig. 17.

    The weight follows the geometry (``weight=None``) and so does the opening
    angle theta_cr = beta_s = asin(r_s / R_s).

    Parameters
    ----------
    hole_radii : sequence of float
        r_s [m] (Fig. 17: 3.75 and 5.58 mm), below R_s / sqrt(2).
    spin_rate : float
        omega_p [rad/s].
    mu_s : float
        Sliding friction coefficient [-].
    n_points : int
    options : SolverOptions, optional

    Returns
    -------
    xarray.Dataset
        ``theta(hole_radius, t)`` [deg], ``t_cr(hole_radius)`` [s], mass
        properties and ``theta_cr(hole_radius)`` [deg].
    """
    ds = _geometry_study(
        "hole_radius",
        hole_radii,
        "m",
        lambda r: rig_case(spin_rate, mu_s, ball=table1_ball(hole_radius=r), weight=None),
        n_points,
        options,
    )
    ds["t"].attrs["units"] = "s"
    ds.attrs.update(
        figures="17",
        title="Effect of hole radius",
        spin_rate=spin_rate,
        mu_s=mu_s,
        **solver_attrs(options),
    )
    return ds


# ---------------------------------------------------------------------------
# Figs. 32-37


def rig_spin_study(
    spin_rates: Sequence[float] = (40.0, 100.0, 200.0, 500.0, 700.0, 1000.0),
    *,
    mu_s: float = TABLE1["mu_s"],
    stick_t_end: float = STICK_T_END,
    t_max: float = RIG_T_MAX,
    n_points: int = 1501,
    options: SolverOptions | None = None,
) -> xr.Dataset:
    """Rig histories over the spin rate, thesis Figs. 32-37.

    Each run is integrated to 1.3 t_cr (40 rad/s at mu_s = 0.35: t_cr = 17.7 s);
    a run that has not opened within `t_max` is integrated to `stick_t_end`.

    Parameters
    ----------
    spin_rates : sequence of float
        omega_p [rad/s] (Figs. 32-37: 40, 100, 200, 500, 700, 1000).
    mu_s : float
        Sliding friction coefficient [-] (Table 1: 0.35).
    stick_t_end : float
        End time of histories that do not open [s].
    t_max : float
        Horizon of the opening-time search [s].
    n_points : int
    options : SolverOptions, optional

    Returns
    -------
    xarray.Dataset
        ``theta(spin_rate, sample)`` [deg] with ``t(spin_rate, sample)`` [s],
        ``t_cr(spin_rate)`` [s] (NaN: not opened within `t_max`).
    """
    runs = []
    for w in spin_rates:
        case = rig_case(w, mu_s, t_max=t_max)
        tcr = opening_time(case, options)
        runs.append(_history(case, _end_time(tcr, stick_t_end), n_points, options))
    ds = _histories_dataset("spin_rate", [float(w) for w in spin_rates], {"units": "rad/s"}, runs)
    ds.attrs.update(
        figures="32-37",
        title="Spin rig, gravity model",
        mu_s=mu_s,
        t_max=t_max,
        theta_cr_deg=math.degrees(table1_ball().opening_angle),
        **solver_attrs(options),
    )
    return ds


# ---------------------------------------------------------------------------
# Figs. 38-42


def _approx_point(case: Case, mu_s: float) -> tuple[float, float, float]:
    sol = _rig_approx(case, mu_s)
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
    for i, mu in enumerate(mus):
        for j, th0 in enumerate(th0s):
            for k, wk in enumerate(w):
                case = rig_case(wk, mu, theta0_deg=th0, weight=weight, t_max=t_max)
                if method == "exact":
                    tcr[i, j, k] = opening_time(case, options)
                else:
                    tcr[i, j, k], eps[i, j, k], zeta[i, j, k] = _approx_point(case, mu)
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
    t_exact = np.array(
        [opening_time(rig_case(x, ls.mu_s, theta0_deg=theta0_deg, t_max=t_max), options) for x in w]
    )
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
    t_grid = np.array([_exact_tcr(w, mu_s, theta0_deg, weight, t_max, options) for w in grid])
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
