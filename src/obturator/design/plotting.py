"""The design figure: each candidate's t_cr over each setting, its band, the planned runs.

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


def design_figure(result: DesignResult, n_runs: int | None = None) -> Figure:
    """Four panels, one per setting: every model's mean t_cr and 95 % predictive band
    along that setting through the plan's leading setting (the others held there); the
    planned runs on that line as markers, the others as ticks on the axis.

    Parameters
    ----------
    result : DesignResult
    n_runs : int, optional
        The plan to mark (default: the recommended one).
    """
    plan = result.plan(n_runs) if n_runs is not None else result.recommended
    ranked = result.ranked_plan(plan.n_runs)
    lead = ranked[0]["setting"]
    cols = setting_arrays(result.settings)
    lead_vals = {
        "spin_rate": lead.spin_rate,
        "theta0_set_deg": lead.theta0_deg,
        "hole_radius": lead.hole_radius,
        "density": lead.density,
    }
    fig = Figure(figsize=(11.0, 7.6), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(2, 2).ravel()
    colours = ("C0", "C3", "C2", "C4", "C1")
    planned = sorted(set(plan.runs))
    for ax, (name, label, scale) in zip(axes, _AXES, strict=True):
        on_line = np.ones(len(result.settings), dtype=bool) & result.candidate_mask
        for other, v in lead_vals.items():
            if other != name:
                on_line &= np.isclose(cols[other], v, rtol=1e-9, atol=0.0)
        idx = np.flatnonzero(on_line)
        idx = idx[np.argsort(cols[name][idx])]
        x = cols[name][idx] * scale
        pred = result.predictive(idx)
        for k, m in enumerate(result.models):
            c = colours[k % len(colours)]
            ax.fill_between(x, pred[m]["lo"], pred[m]["hi"], color=c, alpha=0.18, lw=0)
            ax.plot(x, pred[m]["mean"], color=c, lw=1.6, marker=".", label=m)
        for i in planned:
            count = plan.runs.count(i)
            xi = cols[name][i] * scale
            if i in idx:
                p = result.predictive([i])
                for k, m in enumerate(result.models):
                    ax.plot(
                        xi,
                        p[m]["mean"][0],
                        "o",
                        ms=6 + 2 * count,
                        mfc="none",
                        mec=colours[k % len(colours)],
                        mew=1.8,
                    )
                extrap = result.feasibility and result.feasibility[i].extrapolated
                ax.annotate(
                    f"x{count}" + (" extrap." if extrap else ""),
                    (xi, p[result.models[0]]["mean"][0]),
                    textcoords="offset points",
                    xytext=(6, 6),
                    fontsize=8,
                )
            else:
                ax.plot(xi, 0.0, "|", color="k", ms=10, transform=ax.get_xaxis_transform())
        # the Gaussian band of the < 120 rad/s replicates (SD 0.104 s) reaches below
        # t = 0 where a setting opens sooner than the runs that set it; t_cr cannot
        ax.set_ylim(bottom=0.0)
        ax.set_xlabel(label)
        ax.set_ylabel(r"$t_{cr}$ [s]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="best")
    fig.suptitle(
        "Candidates' $t_{cr}$ with 95 % predictive bands (parameters and replicate noise)\n"
        f"circles: the {plan.n_runs}-run plan (xN: replicates) on each line through its "
        "leading setting; ticks: planned runs off the line; bands cut at $t_{cr}$ = 0;\n"
        "extrap.: outside the measured runs (spin, release, ball or stick ratio); settings "
        "the rig cannot hold (holding moment above its bound) left out",
        fontsize=9,
    )
    return fig


def save_design_figure(result: DesignResult, path: str | Path, **kw: Any) -> Path:
    """Draw :func:`design_figure` into `path` (format from its suffix)."""
    return save(design_figure(result, **kw), path)
