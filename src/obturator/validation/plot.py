"""Validation figure: the runs with their replicate scatter, each model, the floor."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..calibration import SpinRigData, model_opening_times
from .floor import cluster_runs
from .study import CANDIDATES, ValidationStudy

__all__ = ["validation_figure"]


def validation_figure(study: ValidationStudy, data: SpinRigData, t_max: float = 10.0) -> Any:
    """t_cr(omega_p): cluster means with +-1 SD bars, every run, each fitted model's curve.

    Parameters
    ----------
    study : ValidationStudy
    data : SpinRigData
        The runs the study used.
    t_max : float
        Horizon of the model curves [s].
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.2, 4.8), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    w, t = data.spin_rate, data.opening_time
    labels = cluster_runs(w)
    ax.plot(w, t, "o", color="0.6", ms=3, label="runs (Appendix B)")
    for g in np.unique(labels):
        sel = labels == g
        if sel.sum() > 1:
            ax.errorbar(
                w[sel].mean(), t[sel].mean(), yerr=t[sel].std(ddof=1), fmt="ks", ms=4, capsize=3
            )
    grid = np.linspace(max(w.min() - 5.0, 30.0), w.max() + 10.0, 40)
    for m in study.models:
        cand = CANDIDATES[m.name]
        kw = {p: v["value"] for p, v in m.params.items()}
        curve = model_opening_times(grid, **kw, t_max=t_max, **cand.options)
        ax.plot(grid, curve, lw=1.2, label=f"{m.name} (rms {m.rms_all_s:.3f} s)")
    ax.set(
        xlabel="projectile spin omega_p [rad/s]",
        ylabel="opening time t_cr [s]",
        ylim=(0.0, min(1.2, 1.3 * float(t.max()))),
        title="Models vs all runs; replicate floor "
        + (
            f"{study.floor['floor_rms_s']:.3f} s"
            if study.floor["floor_rms_s"] is not None
            else "n/a (no repeated runs)"
        )
        + " (squares: cluster mean +-1 SD)",
    )
    ax.legend(fontsize=7)
    return fig
