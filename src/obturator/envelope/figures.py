"""Figures of the envelope studies (matplotlib; never imported by the numerics).

Every function takes the labelled :class:`xarray.Dataset` that the study
returned, writes one PNG (or any format matplotlib infers from the suffix)
and returns the path.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ..files import figure_format
from ..status import Status

__all__ = ["plot_envelope", "plot_sobol", "plot_pareto", "plot_coupled"]


def _figure(ncols: int = 1, width: float = 6.0, height: float = 4.5) -> tuple[Any, Any]:
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, ncols, figsize=(width * ncols, height), constrained_layout=True)
    return fig, axes


def _save(fig: Any, path: str | Path) -> str:
    import matplotlib.pyplot as plt

    fig.savefig(path, dpi=120, format=figure_format(path))
    plt.close(fig)
    return str(path)


def plot_envelope(ds: Any, path: str | Path) -> str:
    """t_cr map (coupled load) with the requirement, and the coupled - constant difference.

    Left: filled contours of the trajectory-coupled t_cr over muzzle Mach x
    altitude; the requirement contour for the coupled (solid red) and the
    constant load (dashed black); hatched where the bore is choked at opening
    (Fanno, ``//``) or the inlet is not started (Kantrowitz, ``\\\\``); crosses
    where a t_cr is not converged. Right: relative difference in percent.
    """
    if "temperature_offset_k" in ds.dims:
        ds = ds.isel(temperature_offset_k=0)
    mach = ds["mach"].values
    alt_km = ds["altitude_m"].values / 1000.0
    req = float(ds.attrs["requirement_s"])
    fig, (ax, bx) = _figure(2)
    tc = ds["t_cr_coupled"].values.T
    t0 = ds["t_cr_constant"].values.T
    finite = tc[np.isfinite(tc)]
    if finite.size and mach.size > 1 and alt_km.size > 1:
        levels = np.geomspace(finite.min(), finite.max(), 12) if finite.max() > finite.min() else 8
        cf = ax.contourf(mach, alt_km, tc, levels=levels, cmap="viridis")
        fig.colorbar(cf, ax=ax, label="t_cr, trajectory-coupled [s]", format="%.3g")
        if np.nanmin(tc) < req < np.nanmax(tc):
            cs = ax.contour(mach, alt_km, tc, levels=[req], colors="red", linewidths=2.5)
            ax.clabel(cs, fmt=f"{req:g} s (coupled)")
        if np.nanmin(t0) < req < np.nanmax(t0):
            ax.contour(mach, alt_km, t0, levels=[req], colors="k", linestyles="--", linewidths=1.5)
        for name, hatch in (("choked_at_opening", "//"), ("started", "\\\\")):
            mask = ds[name].values.T.astype(float)
            if name == "started":
                mask = 1.0 - mask
            if mask.any():
                ax.contourf(mach, alt_km, mask, levels=[0.5, 1.5], colors="none", hatches=[hatch])
                ax.contour(mach, alt_km, mask, levels=[0.5], colors="0.3", linewidths=0.8)
        rd = 100.0 * ds["relative_difference"].values.T
        cf2 = bx.contourf(mach, alt_km, rd, levels=12, cmap="magma")
        fig.colorbar(cf2, ax=bx, label="t_cr coupled / constant - 1 [%]")
    else:  # a single row or column: line plots
        x, xlabel = (mach, "muzzle Mach M_0") if mach.size > 1 else (alt_km, "altitude [km]")
        ax.plot(x, np.ravel(tc), "o-", label="coupled")
        ax.plot(x, np.ravel(t0), "s--", label="constant load")
        ax.axhline(req, color="red")
        ax.set_ylabel("t_cr [s]")
        ax.legend()
        bx.plot(x, 100.0 * np.ravel(ds["relative_difference"].values.T), "o-")
        bx.set_ylabel("coupled / constant - 1 [%]")
        ax.set_xlabel(xlabel)
        bx.set_xlabel(xlabel)
    unconv = (ds["status_coupled"].values.T == Status.UNCONVERGED) | (
        ds["status_constant"].values.T == Status.UNCONVERGED
    )
    if unconv.any() and mach.size > 1 and alt_km.size > 1:
        mm, aa = np.meshgrid(mach, alt_km)
        ax.plot(mm[unconv], aa[unconv], "wx", label="not converged")
    if mach.size > 1 and alt_km.size > 1:
        for a in (ax, bx):
            a.set_xlabel("muzzle Mach M_0")
            a.set_ylabel("launch altitude [km]")
    ax.set_title(f"opening time; red: {req:g} s coupled, dashed: constant load")
    bx.set_title("trajectory-coupled vs constant load")
    return _save(fig, path)


def plot_sobol(ds: Any, path: str | Path) -> str:
    """Bar chart of first-order and total Sobol indices with their confidence intervals."""
    names = [str(x) for x in ds["input"].values]
    x = np.arange(len(names))
    fig, ax = _figure(1, width=1.0 + 1.1 * len(names))
    w = 0.38
    ax.bar(x - w / 2, ds["S1"], w, yerr=ds["S1_conf"], capsize=3, label="first order S1")
    ax.bar(x + w / 2, ds["ST"], w, yerr=ds["ST_conf"], capsize=3, label="total ST")
    ax.set_xticks(x, names, rotation=20)
    ax.set_ylabel("Sobol index of t_cr")
    ax.axhline(0.0, color="k", linewidth=0.6)
    ax.legend()
    ax.set_title(str(ds.attrs.get("title", "Sobol indices")))
    return _save(fig, path)


def plot_pareto(ds: Any, path: str | Path) -> str:
    """Pareto front: robust t_cr objective against ball mass."""
    fig, ax = _figure(1)
    m = 1000.0 * ds["mass"].values
    ax.plot(m, ds["objective"].values, "o-", label="optimised designs")
    if "baseline_mass" in ds.attrs:
        ax.plot(
            1000.0 * ds.attrs["baseline_mass"],
            ds.attrs["baseline_objective"],
            "r*",
            ms=12,
            label="Table 1",
        )
    ax.set_xlabel("ball mass [g]")
    ax.set_ylabel(f"{ds.attrs.get('objective', 'objective')} of t_cr [s]")
    ax.legend()
    return _save(fig, path)


def plot_coupled(hist: dict[str, np.ndarray], t_const: float, path: str | Path) -> str:
    """theta(t), F_p(t) and M(t) of one trajectory-coupled opening."""
    fig, (ax, bx) = _figure(2)
    t = hist["t"]
    ax.plot(t, np.degrees(hist["theta"]), label="theta, coupled")
    if np.isfinite(t_const):
        ax.axvline(t_const, color="k", linestyle="--", label="t_cr, constant load")
    ax.set_xlabel("t [s]")
    ax.set_ylabel("theta [deg]")
    ax.legend()
    for key, style, label in (
        ("force", "-", "F_p"),
        ("mach", ":", "Mach number"),
        ("spin", "--", "spin omega_p"),
    ):
        bx.plot(t, hist[key] / hist[key][0], linestyle=style, label=label)
    bx.set_xlabel("t [s]")
    bx.set_ylabel("ratio to the muzzle value")
    bx.legend()
    bx.set_title("piecewise-constant load and spin along the flight")
    return _save(fig, path)
