"""The design figure: every planned run in its own setting, each candidate's t_cr along
each setting through it, the separation the plan claims there.

Built without pyplot (an Agg canvas is attached), as :mod:`obturator.plotting`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..plotting import save
from .results import DesignResult
from .settings import setting_arrays

__all__ = ["design_figure", "save_design_figure"]

_AXES = (
    ("spin_rate", r"spin rate $\omega_p$ [rad/s]", 1.0),
    ("theta0_set_deg", r"release angle as set $\theta_0$ [deg]", 1.0),
    ("hole_radius", r"hole radius $r_s$ [mm]", 1e3),
    ("density", r"ball density $\rho$ [kg/m$^3$]", 1.0),
)


#: Planned settings drawn, one row each (the most important first; a plan of more
#: distinct settings lists the rest in the title).
MAX_ROWS = 4


def design_figure(result: DesignResult, n_runs: int | None = None) -> Figure:
    """One row per planned setting, one panel per setting the rig can change.

    Row k holds the k-th planned setting (most important first: by the loss of the
    Box-Hill criterion without it); its title names the setting, its replicates and the
    separation the design claims there, |difference of the models' mean t_cr| / the
    replicate SD. Each panel varies one setting along the candidate grid and holds the
    other three at that run's values, so every planned run is drawn in its own setting.
    Curves: each model's mean t_cr and 95 % predictive band (parameter uncertainty and
    replicate noise). At the planned value (dotted line) each model's mean carries an
    error bar of one replicate SD, the noise of one run: the separation is read there
    (the bands, which add the parameters' spread and span four SDs, overlap even where
    the means are well apart).

    Parameters
    ----------
    result : DesignResult
    n_runs : int, optional
        The plan to draw (default: the recommended one).
    """
    plan = result.plan(n_runs) if n_runs is not None else result.recommended
    ranked = result.ranked_plan(plan.n_runs)
    rows = ranked[:MAX_ROWS]
    cols = setting_arrays(result.settings)
    fig = Figure(figsize=(14.0, 1.0 + 3.3 * len(rows)), layout="constrained")
    FigureCanvasAgg(fig)
    subfigs = np.atleast_1d(fig.subfigures(len(rows), 1))
    colours = ("C0", "C3", "C2", "C4", "C1")
    first_axes = None
    for r, row in enumerate(rows):
        setting, i = row["setting"], row["index"]
        values = {
            "spin_rate": setting.spin_rate,
            "theta0_set_deg": setting.theta0_deg,
            "hole_radius": setting.hole_radius,
            "density": setting.density,
        }
        at = result.predictive([i])
        sd = float(result.noise_sd[i])
        means = [float(at[m]["mean"][0]) for m in result.models]
        sub = subfigs[r]
        sub.suptitle(
            f"planned run {r + 1} (x{row['replicates']}): {setting.spin_rate:.0f} rad/s, "
            f"release {setting.theta0_deg:.2f} deg, r_s {1e3 * setting.hole_radius:.2f} mm, "
            f"rho {setting.density:.0f} kg/m$^3$; separation "
            f"{row['separation_in_replicate_sd']:.1f} replicate SDs "
            f"(means {1e3 * abs(means[0] - means[1]):.0f} ms apart, SD {1e3 * sd:.0f} ms)"
            + (
                "; extrapolated (outside the measured runs)"
                if result.feasibility and result.feasibility[i].extrapolated
                else ""
            ),
            fontsize=9,
            fontweight="bold",
        )
        axes = sub.subplots(1, len(_AXES))
        if first_axes is None:
            first_axes = axes[0]
        for c, (name, label, scale) in enumerate(_AXES):
            ax = axes[c]
            on_line = result.candidate_mask.copy()
            for other, v in values.items():
                if other != name:
                    on_line &= np.isclose(cols[other], v, rtol=1e-9, atol=0.0)
            idx = np.flatnonzero(on_line)
            idx = idx[np.argsort(cols[name][idx])]
            x = cols[name][idx] * scale
            pred = result.predictive(idx)
            xi = values[name] * scale
            span = float(x.max() - x.min()) if x.size > 1 else 1.0
            for k, m in enumerate(result.models):
                col = colours[k % len(colours)]
                ax.fill_between(x, pred[m]["lo"], pred[m]["hi"], color=col, alpha=0.15, lw=0)
                ax.plot(x, pred[m]["mean"], color=col, lw=1.4, marker=".", label=m)
                # the planned run: the model's mean +- one replicate SD (one run's noise)
                ax.errorbar(
                    xi + (k - 0.5) * 0.015 * span,
                    means[k],
                    yerr=sd,
                    fmt="o",
                    color=col,
                    ms=6,
                    mfc="white",
                    mew=1.8,
                    capsize=4,
                    lw=1.8,
                )
            ax.axvline(xi, color="0.35", ls=":", lw=1.0)
            # the Gaussian band of the < 120 rad/s replicates (SD 0.104 s) reaches below
            # t = 0 where a setting opens sooner than the runs that set it; t_cr cannot
            ax.set_ylim(bottom=0.0)
            ax.set_xlabel(label, fontsize=8)
            ax.set_title(
                f"varying {label.split(' [')[0].split(' $')[0]}; the others held", fontsize=8
            )
            ax.tick_params(labelsize=7)
            ax.grid(alpha=0.3)
            if c == 0:
                ax.set_ylabel(r"$t_{cr}$ [s]")
    if first_axes is not None:
        first_axes.legend(fontsize=7, loc="lower right")
    more = len(ranked) - len(rows)
    fig.suptitle(
        f"The {plan.n_runs}-run plan (P(decisive) {plan.p_decisive:.2f}), one row per planned "
        "setting (xN: replicates); each panel varies one setting through that run and holds "
        "the other three at its values\n"
        "curves: each model's mean t_cr and 95 % predictive band (parameters and noise); at "
        "the planned value (dotted): each model's mean +- one replicate SD (one run's noise)\n"
        "settings the rig cannot hold (holding moment above its bound) are left out"
        + (f"; {more} more planned settings not drawn" if more > 0 else ""),
        fontsize=9,
    )
    return fig


def save_design_figure(result: DesignResult, path: str | Path, **kw: Any) -> Path:
    """Draw :func:`design_figure` into `path` (format from its suffix)."""
    return save(design_figure(result, **kw), path)
