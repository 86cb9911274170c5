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

__all__ = ["plot_envelope", "plot_sobol", "plot_pareto", "pareto_collapse", "plot_coupled"]


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


def _round_log_ticks(lo: float, hi: float) -> list[float]:
    """1-2-5 values in [lo, hi] (any unit): colorbar ticks of log-spaced levels that read
    as round numbers, not as the levels' own digits."""
    from matplotlib.ticker import LogLocator

    ticks = LogLocator(subs=(1.0, 2.0, 5.0)).tick_values(lo, hi)
    inside = [float(t) for t in ticks if lo <= t <= hi]
    return inside if len(inside) >= 2 else [lo, hi]


def plot_envelope(ds: Any, path: str | Path) -> str:
    """t_cr map (coupled load) with the requirement, and the coupled - constant difference.

    Left: filled contours of the trajectory-coupled t_cr over muzzle Mach x
    altitude; the requirement contour for the coupled (solid red) and the
    constant load (dashed black), named in the legend (no inline label cuts them);
    hatched where the bore is choked at opening (Fanno, ``//``) or the inlet is not
    started (Kantrowitz, ``\\\\``); crosses where a t_cr is not converged.
    Right: relative difference in percent.
    """
    if "temperature_offset_k" in ds.dims:
        ds = ds.isel(temperature_offset_k=0)
    mach = ds["mach"].values
    alt_km = ds["altitude_m"].values / 1000.0
    req = float(ds.attrs["requirement_s"])
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    fig, (ax, bx) = _figure(2)
    tc = ds["t_cr_coupled"].values.T
    t0 = ds["t_cr_constant"].values.T
    finite = tc[np.isfinite(tc)]
    if finite.size and mach.size > 1 and alt_km.size > 1:
        levels = np.geomspace(finite.min(), finite.max(), 12) if finite.max() > finite.min() else 8
        cf = ax.contourf(mach, alt_km, tc, levels=levels, cmap="viridis")
        cb = fig.colorbar(cf, ax=ax, label="t_cr, trajectory-coupled [s]", format="%g")
        cb.set_ticks(_round_log_ticks(finite.min(), finite.max()))
        # the requirement contours are named in the legend, not by inline labels: an
        # inline label cuts its line where it sits, and on a short contour hides it
        lines = []
        if np.nanmin(tc) < req < np.nanmax(tc):
            ax.contour(mach, alt_km, tc, levels=[req], colors="red", linewidths=2.5)
            lines.append(Line2D([], [], color="red", lw=2.5, label=f"{req:g} s, coupled"))
        if np.nanmin(t0) < req < np.nanmax(t0):
            ax.contour(mach, alt_km, t0, levels=[req], colors="k", linestyles="--", linewidths=1.5)
            lines.append(
                Line2D([], [], color="k", ls="--", lw=1.5, label=f"{req:g} s, constant load")
            )
        hatched = []
        for name, hatch, what in (
            ("choked_at_opening", "//", "bore choked at opening (Fanno)"),
            ("started", "\\\\", "inlet not started (Kantrowitz)"),
        ):
            mask = ds[name].values.T.astype(float)
            if name == "started":
                mask = 1.0 - mask
            if mask.any():
                ax.contourf(mach, alt_km, mask, levels=[0.5, 1.5], colors="none", hatches=[hatch])
                ax.contour(mach, alt_km, mask, levels=[0.5], colors="0.3", linewidths=0.8)
                hatched.append(Patch(facecolor="white", edgecolor="0.3", hatch=hatch, label=what))
        if hatched or lines:
            ax.legend(
                handles=[*lines, *hatched], loc="lower right", fontsize="small", framealpha=0.9
            )
        rd = 100.0 * ds["relative_difference"].values.T
        cf2 = bx.contourf(mach, alt_km, rd, levels=12, cmap="magma")
        fig.colorbar(cf2, ax=bx, label="t_cr coupled / constant - 1 [%]")
    else:  # a single row or column: line plots
        x, xlabel = (mach, "muzzle Mach $M_0$") if mach.size > 1 else (alt_km, "altitude [km]")
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
            a.set_xlabel("muzzle Mach $M_0$")
            a.set_ylabel("launch altitude [km]")
    ax.set_title(f"opening time; red: {req:g} s coupled, dashed: constant load")
    bx.set_title("trajectory-coupled vs constant load")
    return _save(fig, path)


def plot_sobol(ds: Any, path: str | Path) -> str:
    """Bar chart of first-order and total Sobol indices with their confidence intervals.

    Where the estimates are noise (:func:`obturator.envelope.sensitivity.sobol_warnings`:
    an interval wider than its index, an index outside [0, 1]) the figure says so in red
    under the title, shades the impossible range outside [0, 1] and hatches the bars
    concerned.
    """
    from ..envelope.sensitivity import sobol_warnings

    names = [str(x) for x in ds["input"].values]
    x = np.arange(len(names))
    import textwrap

    width = max(1.0 + 1.1 * len(names), 6.0)
    warnings = [
        textwrap.fill(line, int(11 * width), subsequent_indent="  ") for line in sobol_warnings(ds)
    ]
    n_lines = sum(line.count("\n") + 1 for line in warnings)
    fig, ax = _figure(1, width=width, height=4.5 + 0.2 * n_lines)
    w = 0.38
    for off, key, label in ((-w / 2, "S1", "first order S1"), (w / 2, "ST", "total ST")):
        v, c = np.asarray(ds[key], dtype=float), np.asarray(ds[f"{key}_conf"], dtype=float)
        bars = ax.bar(x + off, v, w, yerr=c, capsize=3, label=label)
        for bar, vk, ck in zip(bars, v, c, strict=True):
            if (ck > abs(vk) and ck > 0.01) or not -0.01 <= vk <= 1.01:
                bar.set_hatch("///")
                bar.set_edgecolor("0.2")
    ax.set_xticks(x, names, rotation=20)
    ax.set_ylabel("Sobol index of t_cr")
    ax.axhline(0.0, color="k", linewidth=0.6)
    lo, hi = ax.get_ylim()
    if hi > 1.0:
        ax.axhspan(1.0, hi, color="red", alpha=0.08, lw=0)
        ax.axhline(1.0, color="red", lw=0.8, ls=":")
    if lo < 0.0:
        ax.axhspan(lo, 0.0, color="red", alpha=0.08, lw=0)
    ax.set_ylim(lo, hi)
    ax.legend()
    title = str(ds.attrs.get("title", "Sobol indices"))
    if warnings:
        title += "\nNOT RELIABLE (hatched; shaded: impossible, outside [0, 1]):\n" + "\n".join(
            warnings
        )
    ax.set_title(title, **({"fontsize": 9, "color": "firebrick"} if warnings else {}))
    return _save(fig, path)


#: A front whose masses span less than this fraction of the optimum's mass has collapsed
#: to one design: its points overlap at the figure's scale (Table 1's ball beside it).
_COLLAPSED = 0.05


def pareto_collapse(ds: Any) -> str | None:
    """Why the Pareto front has no trade-off to show, or None where it has one.

    The front lowers the mass budget from the optimum's mass to the lightest feasible
    design's (:func:`obturator.envelope.pareto.pareto_front`). Where those two masses lie
    within 5 % of each other the fastest design is already (nearly) the lightest one:
    t_cr and mass do not compete over the design bounds, and every budget returns
    about the same design.

    Parameters
    ----------
    ds : xarray.Dataset
        The front (``mass`` [kg], ``objective`` [s]; attribute
        ``lightest_feasible_mass`` [kg]).

    Returns
    -------
    str or None
        One sentence for the figure and the text output.
    """
    m = np.asarray(ds["mass"].values, dtype=float)
    f = np.asarray(ds["objective"].values, dtype=float)
    m_light = float(ds.attrs.get("lightest_feasible_mass", m.min()))
    if m.size and (m.max() - m_light) <= _COLLAPSED * m.max():
        return (
            f"the front collapsed to one design: the fastest design ({1e3 * m.max():.4g} g, "
            f"{f[int(np.argmax(m))]:.4g} s) is within "
            f"{100 * (m.max() - m_light) / m.max():.2g} % of the lightest feasible one "
            f"({1e3 * m_light:.4g} g), so t_cr and mass do not compete over these bounds "
            "(every mass budget gives about the same design)"
        )
    return None


def plot_pareto(ds: Any, path: str | Path) -> str:
    """Pareto front: robust t_cr objective against ball mass, or, where it collapsed to
    one design (:func:`pareto_collapse`), that design with the reason written on it."""
    fig, ax = _figure(1)
    m = 1000.0 * ds["mass"].values
    collapsed = pareto_collapse(ds)
    ax.plot(
        m,
        ds["objective"].values,
        "o-",
        label="optimised designs" if collapsed is None else "optimised designs (one point)",
    )
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
    ax.legend(loc="lower right")
    if collapsed is not None:
        import textwrap

        ax.set_title("No trade-off between t_cr and mass", color="firebrick")
        ax.text(
            0.03,
            0.97,
            textwrap.fill(collapsed[0].upper() + collapsed[1:] + ".", 52),
            transform=ax.transAxes,
            va="top",
            fontsize=8,
            bbox={"facecolor": "white", "edgecolor": "firebrick", "alpha": 0.9},
        )
    else:
        ax.set_title("Pareto front: robust t_cr against ball mass")
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
