"""The thesis's time-history studies as labelled :class:`xarray.Dataset` objects (no plotting).

=====================================  ======================================
function                               thesis figures
=====================================  ======================================
:func:`couette_study`                  Figs. 9-10 (viscous-only, Couette S)
:func:`flight_and_rig_study`           Figs. 13-14 (Table 1 flight and rig)
:func:`exact_vs_approximate`           Fig. 15 (Eq. 65 against the exact run)
:func:`density_study`                  Fig. 16 (6000 vs 10000 kg/m^3)
:func:`hole_radius_study`              Fig. 17 (r_s = 3.75 vs 5.58 mm)
:func:`rig_spin_study`                 Figs. 32-37 (rig, 40..1000 rad/s)
=====================================  ======================================

Conventions: time ``t`` in s, nutation ``theta`` in **degrees** (as the
thesis plots it), spin rates in rad/s; every variable and coordinate carries a
``units`` attribute, and every Dataset records the solver settings it used.
Histories of different lengths share a ``sample`` dimension with a 2-D time
coordinate ``t(case, sample)``. The t_cr curves of Figs. 38-43 are in
:mod:`.opening_times`.

Every rig run opens: the single bottom contact of the rig (Eq. 61) cannot hold
a torque about the gravity axis X, so friction cannot keep the ball
co-rotating. At low spin the ball spends long near-stick phases and opens late
(about 17.7 s at 40 rad/s for mu_s = 0.35, 42.7 s for mu_s = 0.5473), so the
studies integrate until the bore opens with a generous horizon; a run that
still has not opened by it keeps t_cr = NaN and its history ends there.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, Literal

import numpy as np
import xarray as xr

from .._docs import fill_doc
from ..errors import InputError, SolverError, check_range
from ..model.case import Case
from ..model.cases import couette_case, flight_case, rig_case, table1_ball
from ..reference import CAPTION_SHEAR_CONSTANT, TABLE1
from ..solve import SolverOptions, opening_time, opening_times, simulate
from .common import RIG_T_MAX, STICK_T_END, rig_approx, solver_attrs

__all__ = [
    "couette_shear_constant",
    "couette_study",
    "density_study",
    "exact_vs_approximate",
    "flight_and_rig_study",
    "hole_radius_study",
    "rig_spin_study",
]


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
    approx = rig_approx(case, mu_s)
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


# ---------------------------------------------------------------------------
# Figs. 16-17


#: The rig inputs of the Figs. 16-17 studies besides the varied ball property.
_RIG_INPUTS = """\
spin_rate : float
    omega_p [rad/s].
mu_s : float
    Sliding friction coefficient [-].
n_points : int
options : SolverOptions, optional"""


def _geometry_study(
    dim: Literal["density", "hole_radius"],
    values: Sequence[float],
    unit: str,
    figure: str,
    title: str,
    spin_rate: float,
    mu_s: float,
    n_points: int,
    options: SolverOptions | None,
) -> xr.Dataset:
    """Rig histories over the ball property `dim` (a :func:`table1_ball` keyword).

    The weight follows the ball (``weight=None``); every other input is Table 1's.
    """
    cases = [rig_case(spin_rate, mu_s, ball=table1_ball(**{dim: v}), weight=None) for v in values]
    tcr = opening_times(cases, options, strict=True)[0].tolist()
    finite = [x for x in tcr if math.isfinite(x)]
    t_end = 1.3 * max(finite) if finite else STICK_T_END
    runs = [_history(c, t_end, n_points, options) for c in cases]
    ds = xr.Dataset(
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
    ds["t"].attrs["units"] = "s"
    attrs = {"figures": figure, "title": title, "spin_rate": spin_rate, "mu_s": mu_s}
    ds.attrs.update(attrs, **solver_attrs(options))
    return ds


@fill_doc(rig_inputs=_RIG_INPUTS)
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
    {rig_inputs}

    Returns
    -------
    xarray.Dataset
        ``theta(density, t)`` [deg], ``t_cr(density)`` [s] and the mass
        properties per density.
    """
    return _geometry_study(
        "density",
        densities,
        "kg/m^3",
        "16",
        "Effect of ball density",
        spin_rate,
        mu_s,
        n_points,
        options,
    )


@fill_doc(rig_inputs=_RIG_INPUTS)
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
    {rig_inputs}

    Returns
    -------
    xarray.Dataset
        ``theta(hole_radius, t)`` [deg], ``t_cr(hole_radius)`` [s], mass
        properties and ``theta_cr(hole_radius)`` [deg].
    """
    return _geometry_study(
        "hole_radius",
        hole_radii,
        "m",
        "17",
        "Effect of hole radius",
        spin_rate,
        mu_s,
        n_points,
        options,
    )


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
