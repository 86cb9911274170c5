"""Figures of the thesis reproduction, drawn from the :mod:`obturator.thesis` Datasets.

Every function returns a :class:`matplotlib.figure.Figure` built without
pyplot (an Agg canvas is attached), so nothing here touches global matplotlib
state and it works headless. Axes carry units; measured data are drawn as
points (starred runs filled, the others open). The numeric modules never
import this one.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from .files import figure_format

if TYPE_CHECKING:  # pragma: no cover
    import xarray as xr
    from matplotlib.axes import Axes

    from .calibration.data import SpinRigData
    from .calibration.exact import ExactFit

__all__ = [
    "calibration_residuals",
    "figure_suffixes",
    "fig09_couette",
    "fig10_couette_scaled",
    "fig13_flight",
    "fig14_rig",
    "fig15_exact_vs_approximate",
    "fig16_density",
    "fig17_hole_radius",
    "fig32_37_rig_spin",
    "fig38_eq92_data",
    "fig39_mu_sensitivity",
    "fig40_theta0_sensitivity",
    "fig41_theta0_data",
    "fig42_mu_data",
    "fig43_least_squares",
    "opening_time_minimum_figure",
    "save",
]

_T = "time t [s]"
_TH = r"nutation angle $\theta$ [deg]"
_W = r"projectile spin $\omega_p$ [rad/s]"
_TCR = r"opening time $t_{cr}$ [s]"


def _figure(nrows: int = 1, ncols: int = 1, size: tuple[float, float] = (6.4, 4.4)) -> Any:
    fig = Figure(figsize=size, layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(nrows, ncols, squeeze=False)
    return fig, axes


def figure_suffixes() -> tuple[str, ...]:
    """File suffixes :func:`save` can write (png, pdf, svg, ...)."""
    return tuple(FigureCanvasAgg(Figure()).get_supported_filetypes())


def save(fig: Figure, path: str | Path, dpi: int = 110) -> Path:
    """Write `fig` as PNG (or any format matplotlib infers from the suffix); return the path."""
    p = Path(path)
    fig.savefig(p, dpi=dpi, format=figure_format(p))  # a device: written in place
    return p


def _theta_cr_line(ax: Axes, theta_cr_deg: float | None, label: bool = True) -> None:
    if theta_cr_deg is not None and math.isfinite(theta_cr_deg):
        ax.axhline(
            theta_cr_deg,
            color="0.4",
            ls=":",
            lw=1,
            label=rf"$\theta_{{cr}} = \beta_s$ = {theta_cr_deg:.2f}°" if label else None,
        )


def _tcr_label(t_cr: float) -> str:
    return f"t_cr = {t_cr:.4g} s" if math.isfinite(t_cr) else "does not open"


def _data_points(ax: Axes, data: SpinRigData | None, max_spin: float | None = None) -> None:
    if data is None:
        return
    w, t, s = data.spin_rate, data.opening_time, data.starred
    keep = np.ones(w.size, bool) if max_spin is None else w <= max_spin
    ax.plot(w[keep & s], t[keep & s], "ko", ms=4, label="data (starred, fitted)")
    ax.plot(w[keep & ~s], t[keep & ~s], "ko", mfc="none", ms=4, label="data (not starred)")


# ---------------------------------------------------------------------------
# Figs. 9-10


def _envelope(t: np.ndarray, y: np.ndarray, n_bins: int = 300) -> tuple[np.ndarray, ...]:
    """Bin centres and per-bin min/max of y(t): the envelope of a fast oscillation."""
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    edges = np.linspace(t[0], t[-1], n_bins + 1)
    k = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, n_bins - 1)
    lo = np.full(n_bins, np.nan)
    hi = np.full(n_bins, np.nan)
    np.fmin.at(lo, k, y)
    np.fmax.at(hi, k, y)
    keep = np.isfinite(lo)
    return 0.5 * (edges[:-1] + edges[1:])[keep], lo[keep], hi[keep]


def fig09_couette(ds: xr.Dataset) -> Figure:
    """Fig. 9: theta(t) with the Couette viscous torque alone (first scale of the study).

    theta oscillates at about the spin frequency (~2 kHz) with a slowly drifting
    mean, which plotted sample by sample is a solid block: the figure shows the
    envelope (min/max per bin) over 0-0.1 s and the oscillation itself in an inset.
    """
    fig, ax = _figure()
    a = ax[0, 0]
    sel = ds.isel(scale=0)
    s = float(sel["shear_constant"])
    t = np.asarray(ds["t"], float)
    th = np.asarray(sel["theta"], float)
    ok = np.isfinite(th)
    tc, lo, hi = _envelope(t[ok], th[ok], n_bins=40)  # ~5 spin periods per bin
    a.fill_between(tc, lo, hi, color="C0", alpha=0.35, lw=0, label="envelope of theta(t)")
    a.plot(
        tc,
        0.5 * (lo + hi),
        "C0-",
        lw=1,
        label=f"mid-line; S = {s:.3g} N m s ({_tcr_label(float(sel['t_cr']))})",
    )
    a.axvline(0.1, color="C3", ls="--", lw=1, label="0.1 s (time of flight)")
    a.set(xlabel=_T, ylabel=_TH, title="Fig. 9: viscous torque only (Couette, Eq. 34)")
    a.legend(fontsize=8, loc="lower left")
    zoom = t[ok] <= t[ok][0] + 0.003
    if zoom.sum() > 10:
        ins = a.inset_axes((0.55, 0.55, 0.42, 0.38))
        ins.plot(t[ok][zoom] * 1e3, th[ok][zoom], "C0-", lw=0.8)
        ins.set_xlabel("t [ms]", fontsize=7)
        ins.set_ylabel("theta [deg]", fontsize=7)
        ins.tick_params(labelsize=6)
        ins.set_title("first 3 ms", fontsize=7)
    return fig


def theta_history_figure(res: Any) -> Figure:
    """theta(t) of one :class:`~obturator.result.NutationResult` with theta_cr and t_cr."""
    fig, ax = _figure(size=(6.4, 4.0))
    a = ax[0, 0]
    a.plot(res.t, np.degrees(res.theta), lw=1.0, label=r"$\theta(t)$")
    a.axhline(
        math.degrees(res.case.opening_angle),
        color="k",
        ls="--",
        lw=0.8,
        label=r"$\theta_{cr}=\beta_s$",
    )
    if res.opened:
        a.axvline(
            res.opening_time,
            color="C3",
            ls=":",
            lw=0.8,
            label=f"$t_{{cr}}$ = {res.opening_time:.4g} s",
        )
    a.set(xlabel=_T, ylabel=_TH, title=f"{res.case.name}, omega_p = {res.case.spin_rate:g} rad/s")
    a.legend()
    return fig


def fig10_couette_scaled(ds: xr.Dataset) -> Figure:
    """Fig. 10: theta(t) for increasing orders of magnitude of the Couette constant S."""
    fig, ax = _figure()
    a = ax[0, 0]
    for k in range(ds.sizes["scale"]):
        sel = ds.isel(scale=k)
        a.plot(
            ds["t"],
            sel["theta"],
            label=f"S = {float(sel['shear_constant']):.3g} N m s "
            f"({_tcr_label(float(sel['t_cr']))})",
        )
    _theta_cr_line(a, ds.attrs.get("theta_cr_deg"))
    a.set(xlabel=_T, ylabel=_TH, title="Fig. 10: Couette S x 1, 10, 100, 1000")
    a.legend(fontsize=8)
    return fig


# ---------------------------------------------------------------------------
# Figs. 13-17


def _history(ds: xr.Dataset, dim: str, label: Any, title: str) -> Figure:
    fig, ax = _figure()
    a = ax[0, 0]
    sel = ds.sel({dim: label})
    a.plot(sel["t"], sel["theta"], label=_tcr_label(float(sel["t_cr"])))
    _theta_cr_line(a, ds.attrs.get("theta_cr_deg"))
    a.set(xlabel=_T, ylabel=_TH, title=title)
    a.legend(fontsize=8)
    return fig


def fig13_flight(ds: xr.Dataset) -> Figure:
    """Fig. 13: Table 1 flight case (aerodynamic load, 12042 rad/s)."""
    return _history(ds, "case", "flight", f"Fig. 13: flight, mu_s = {ds.attrs['mu_s']:g}")


def fig14_rig(ds: xr.Dataset) -> Figure:
    """Fig. 14: Table 1 spin-rig case (gravity load, 200 rad/s)."""
    return _history(ds, "case", "rig", f"Fig. 14: spin rig, mu_s = {ds.attrs['mu_s']:g}")


def fig15_exact_vs_approximate(ds: xr.Dataset) -> Figure:
    """Fig. 15: exact and linearised (Eq. 65) histories on the rig."""
    fig, ax = _figure()
    a = ax[0, 0]
    a.plot(ds["t"], ds["theta_exact"], label=f"(a) exact, t_cr = {ds.attrs['t_cr_exact']:.4g} s")
    a.plot(
        ds["t"],
        ds["theta_approx"],
        "--",
        label=f"(b) approximate Eq. 65, Eq. 92: t_cr = {ds.attrs['t_cr_eq92']:.4g} s",
    )
    _theta_cr_line(a, ds.attrs["theta_cr_deg"])
    a.set(
        xlabel=_T,
        ylabel=_TH,
        title=f"Fig. 15: exact vs approximate, {ds.attrs['spin_rate']:g} rad/s, "
        f"mu_s = {ds.attrs['mu_s']:g}",
    )
    a.legend(fontsize=8)
    return fig


def _family(ds: xr.Dataset, dim: str, fmt, title: str) -> Figure:
    fig, ax = _figure()
    a = ax[0, 0]
    for k in range(ds.sizes[dim]):
        sel = ds.isel({dim: k})
        (line,) = a.plot(
            ds["t"], sel["theta"], label=f"{fmt(float(sel[dim]))}, {_tcr_label(float(sel['t_cr']))}"
        )
        a.axhline(float(sel["theta_cr"]), color=line.get_color(), ls=":", lw=1)
    a.set(xlabel=_T, ylabel=_TH, title=title)
    a.legend(fontsize=8)
    return fig


def fig16_density(ds: xr.Dataset) -> Figure:
    """Fig. 16: densities 6000 and 10000 kg/m^3 (weight follows the density).

    The two curves overlap: A, C and the rig's friction moment mu_s W R_s all
    scale with rho, so Euler's equations divided by A do not depend on it; only
    the small viscous term (rho-independent) differs, by ~0.1 % in t_cr.
    """
    fig = _family(ds, "density", lambda v: f"rho = {v:g} kg/m^3", "Fig. 16: effect of ball density")
    fig.axes[0].text(
        0.02,
        0.04,
        "curves overlap: inertia and friction moment both scale with rho;\n"
        "only the small viscous torque does not",
        transform=fig.axes[0].transAxes,
        fontsize=7,
    )
    return fig


def fig17_hole_radius(ds: xr.Dataset) -> Figure:
    """Fig. 17: hole radii 3.75 and 5.58 mm (dotted: each ball's theta_cr)."""
    return _family(
        ds, "hole_radius", lambda v: f"r_s = {1e3 * v:g} mm", "Fig. 17: effect of hole radius"
    )


def fig32_37_rig_spin(ds: xr.Dataset, spin_rate: float) -> Figure:
    """Figs. 32-37: one rig history at `spin_rate` [rad/s] from :func:`rig_spin_study`."""
    number = {40.0: 32, 100.0: 33, 200.0: 34, 500.0: 35, 700.0: 36, 1000.0: 37}.get(
        float(spin_rate)
    )
    name = f"Fig. {number}" if number else "Rig"
    return _history(
        ds,
        "spin_rate",
        float(spin_rate),
        f"{name}: gravity model, omega_p = {spin_rate:g} rad/s, mu_s = {ds.attrs['mu_s']:g}",
    )


# ---------------------------------------------------------------------------
# Figs. 38-42


def _tcr_curves(
    a: Axes,
    ds: xr.Dataset,
    dim: str,
    fmt,
    style: str = "-",
    fixed: dict[str, Any] | None = None,
    suffix: str = "",
) -> None:
    sub = ds.sel(fixed) if fixed else ds
    for k in range(sub.sizes[dim]):
        sel = sub.isel({dim: k})
        a.plot(sel["spin_rate"], sel["t_cr"], style, label=fmt(float(sel[dim])) + suffix)


def _tcr_axes(a: Axes, title: str, ymax: float | None = None) -> None:
    a.set(xlabel=_W, ylabel=_TCR, title=title)
    a.set_ylim(0.0, ymax)
    a.legend(fontsize=8)


def fig38_eq92_data(ds: xr.Dataset, data: SpinRigData | None = None) -> Figure:
    """Fig. 38: Eq. (92) at the first mu_s of `ds` (0.35) with the data."""
    fig, ax = _figure()
    a = ax[0, 0]
    sel = ds.isel(mu_s=0, theta0_deg=0)
    a.plot(sel["spin_rate"], sel["t_cr"], label=f"Eq. 92, mu_s = {float(sel['mu_s']):g}")
    _data_points(a, data)
    _tcr_axes(a, "Fig. 38: data and Eq. 92", ymax=1.2 * float(np.nanmax(sel["t_cr"])))
    return fig


def _mu_curves(a: Any, ds: xr.Dataset, exact: xr.Dataset | None) -> None:
    """Eq. (92) for each mu_s of `ds` at its theta_0, and dashed the exact model's."""
    th0 = {"theta0_deg": float(ds["theta0_deg"][0])}
    _tcr_curves(a, ds, "mu_s", lambda v: f"mu_s = {v:g}", fixed=th0, suffix=" (Eq. 92)")
    if exact is not None:
        a.set_prop_cycle(None)
        _tcr_curves(a, exact, "mu_s", lambda v: f"mu_s = {v:g}", "--", th0, " (exact)")


def fig39_mu_sensitivity(ds: xr.Dataset, exact: xr.Dataset | None = None) -> Figure:
    """Fig. 39: Eq. (92) for several mu_s (dashed: exact model, if given)."""
    fig, ax = _figure()
    a = ax[0, 0]
    _mu_curves(a, ds, exact)
    _tcr_axes(a, "Fig. 39: sensitivity to mu_s", ymax=float(np.nanmax(ds["t_cr"])) * 1.05)
    return fig


def fig40_theta0_sensitivity(ds: xr.Dataset) -> Figure:
    """Fig. 40: Eq. (92) for several theta_0."""
    fig, ax = _figure()
    a = ax[0, 0]
    mu = {"mu_s": float(ds["mu_s"][0])}
    _tcr_curves(a, ds, "theta0_deg", lambda v: f"theta_0 = {v:g}°", fixed=mu)
    _tcr_axes(a, f"Fig. 40: sensitivity to theta_0 (Eq. 92, mu_s = {mu['mu_s']:g})")
    return fig


def fig41_theta0_data(ds: xr.Dataset, data: SpinRigData | None = None) -> Figure:
    """Fig. 41: Eq. (92) for several theta_0 with the data."""
    fig, ax = _figure()
    a = ax[0, 0]
    mu = {"mu_s": float(ds["mu_s"][0])}
    _tcr_curves(a, ds, "theta0_deg", lambda v: f"theta_0 = {v:g}° (Eq. 92)", fixed=mu)
    _data_points(a, data)
    _tcr_axes(a, f"Fig. 41: data and Eq. 92 for several theta_0 (mu_s = {mu['mu_s']:g})")
    return fig


def fig42_mu_data(
    ds: xr.Dataset, data: SpinRigData | None = None, exact: xr.Dataset | None = None
) -> Figure:
    """Fig. 42: Eq. (92) for several mu_s with the data (dashed: exact model, if given)."""
    fig, ax = _figure()
    a = ax[0, 0]
    _mu_curves(a, ds, exact)
    _data_points(a, data)
    _tcr_axes(a, "Fig. 42: data and Eq. 92 for several mu_s", ymax=1.0)
    return fig


# ---------------------------------------------------------------------------
# Fig. 43, the minimum, the calibration


def fig43_least_squares(ds: xr.Dataset) -> Figure:
    """Fig. 43: data, least-squares line t = T2 omega_p and exact t_cr at the fitted mu_s."""
    fig, ax = _figure()
    a = ax[0, 0]
    w = ds["data_spin_rate"].values
    t = ds["data_t_cr"].values
    used = ds["data_used_in_fit"].values.astype(bool)
    a.plot(w[used], t[used], "ko", ms=4, label=f"data used in the fit ({used.sum()})")
    a.plot(w[~used], t[~used], "ko", mfc="none", ms=4, label="other data")
    a.plot(
        ds["spin_rate"],
        ds["t_linear"],
        "C0-",
        label=f"t = T2 omega_p, T2 = {ds.attrs['T2']:.4e} s^2",
    )
    a.plot(ds["spin_rate"], ds["t_eq94"], "C0:", label="Eq. 94 (with T1 term)")
    a.plot(
        ds["spin_rate"],
        ds["t_exact"],
        "C3s-",
        ms=3,
        label=f"exact, mu_s = {ds.attrs['mu_s']:.4f}",
    )
    a.set_xlim(0.0, 1.02 * float(ds["spin_rate"].max()))
    _tcr_axes(a, "Fig. 43: data, least-squares line and exact solution", ymax=0.8)
    return fig


def opening_time_minimum_figure(ds: xr.Dataset, data: SpinRigData | None = None) -> Figure:
    """t_cr(omega_p), Eq. (92) and exact, with their minima (and, if some grid runs did
    not open within the horizon, the lowest spin that did)."""
    fig, ax = _figure()
    a = ax[0, 0]
    a.plot(ds["spin_rate"], ds["t_cr_approx"], "C0-", label="Eq. 92")
    a.plot(ds["spin_rate"], ds["t_cr_exact"], "C3.-", label="exact")
    for k, c in (("approx", "C0"), ("exact", "C3")):
        w = float(ds["spin_rate_min"].sel(model=k))
        if math.isfinite(w):
            t = float(ds["t_cr_min"].sel(model=k))
            a.plot([w], [t], "*", color=c, ms=12, label=f"minimum {k}: {w:.1f} rad/s")
    wb = float(ds["exact_boundary"])
    if math.isfinite(wb):
        a.axvline(wb, color="C3", ls=":", lw=1, label=f"exact opens above {wb:.1f} rad/s")
    a.axvline(ds.attrs["thesis_value"], color="0.5", ls="--", lw=1, label="thesis: 150 rad/s")
    _data_points(a, data, max_spin=float(ds["spin_rate"].max()))
    _tcr_axes(a, f"Minimum of t_cr, mu_s = {ds.attrs['mu_s']:g}", ymax=1.0)
    return fig


def calibration_residuals(fit: ExactFit) -> Figure:
    """Exact-model calibration: data and fitted model (top), residuals (bottom)."""
    fig, ax = _figure(2, 1, size=(6.4, 6.4))
    a, b = ax[0, 0], ax[1, 0]
    order = np.argsort(fit.spin_rate)
    w = fit.spin_rate[order]
    a.plot(w, fit.measured[order], "ko", ms=4, label="measured")
    a.plot(w, fit.model[order], "C3s-", ms=3, label=f"exact model, mu_s = {fit.mu_s:.4f}")
    a.set(xlabel=_W, ylabel=_TCR, title="Exact-model calibration")
    a.legend(fontsize=8)
    b.axhline(0.0, color="0.5", lw=1)
    b.plot(w, fit.residuals[order], "ko", ms=4)
    b.set(xlabel=_W, ylabel="residual model - measured [s]")
    b.set_title(f"rms = {fit.rms:.3g} s, reduced chi-square = {fit.redchi:.3g}", fontsize=9)
    return fig


def spin_rates_for_figures(ds: xr.Dataset) -> Sequence[float]:
    """The spin rates of a :func:`rig_spin_study` Dataset [rad/s]."""
    return [float(w) for w in ds["spin_rate"].values]
