"""The validation figure: data with replicate error bars, each model's t_cr curve, the floor.

Built without pyplot (an Agg canvas is attached), as :mod:`obturator.plotting`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ..files import figure_format
from .floor import BANDS
from .results import ValidationResult

__all__ = ["save_validation_figure", "validation_figure"]


def validation_figure(result: ValidationResult, *, max_models: int = 8) -> Figure:
    """Two panels: t_cr(omega_p) with every model's curve; rms per band against the floor.

    Parameters
    ----------
    result : ValidationResult
    max_models : int
        Curves drawn (best AIC first; the recommended and the thesis's always).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(11.0, 4.8), layout="constrained")
    FigureCanvasAgg(fig)
    ax, bx = fig.subplots(1, 2, width_ratios=(1.6, 1.0))
    fl = result.floor
    w, y = fl.spin_rate, fl.opening_time
    err = fl.cluster_sd()
    ax.errorbar(
        w,
        y,
        yerr=err,
        fmt="o",
        ms=3.5,
        color="k",
        ecolor="0.55",
        elinewidth=0.8,
        capsize=2,
        label="Appendix B runs (bars: cluster SD)",
        zorder=5,
    )
    keep = [m for m in result.models[:max_models]]
    for name in (result.recommended, "thesis-1980"):
        m = next((x for x in result.models if x.name == name), None)
        if m is not None and m not in keep:
            keep.append(m)
    colors: dict[str, Any] = {}
    for i, m in enumerate(keep):
        rec = m.name == result.recommended
        (line,) = ax.plot(
            m.curve_spin,
            m.curve_t,
            lw=2.4 if rec else 1.1,
            ls="-" if rec or i < 6 else "--",
            label=f"{m.name} (rms {m.fit.rms:.3f} s)" + (" [recommended]" if rec else ""),
            zorder=4 if rec else 3,
        )
        colors[m.name] = line.get_color()
    ymax = max(1.0, float(np.nanmax(y)) * 1.6)
    ax.set_ylim(0.0, ymax)
    ax.set_xlabel(r"projectile spin $\omega_p$ [rad/s]")
    ax.set_ylabel(r"opening time $t_{cr}$ [s]")
    ax.set_title("Spin-rig runs and fitted models (all runs)")
    ax.legend(fontsize=7, loc="upper right")
    # right panel: rms per band vs floor
    labels = ["all"] + [b[0] for b in BANDS]
    x = np.arange(len(labels))
    floor = [fl.floor_rms] + [fl.bands[b].floor_rms for b in labels[1:]]
    width = 0.8 / max(len(keep), 1)
    for i, m in enumerate(keep):
        rb = m.fit.rms_by_band
        vals = [m.fit.rms] + [rb[b] for b in labels[1:]]
        bx.bar(x - 0.4 + (i + 0.5) * width, vals, width, color=colors[m.name])
    bx.scatter(x, floor, marker="_", s=900, color="k", zorder=5, label="replicate floor")
    bx.scatter(
        x, [1.25 * f for f in floor], marker="_", s=600, color="0.5", zorder=5, label="1.25 x floor"
    )
    bx.text(
        0.02,
        0.98,
        "bars: models in the order and colours of the left legend",
        transform=bx.transAxes,
        fontsize=7,
        va="top",
    )
    bx.set_xticks(x, labels)
    bx.set_yscale("log")
    bx.set_ylabel("rms residual [s]")
    bx.set_xlabel(r"$\omega_p$ band [rad/s]")
    bx.set_title("rms per band against the pure-error floor")
    bx.legend(fontsize=7, loc="lower right")
    return fig


def save_validation_figure(result: ValidationResult, path: str | Path, dpi: int = 110) -> Path:
    """Draw :func:`validation_figure` and write it to `path` (format from the suffix)."""
    p = Path(path)
    validation_figure(result).savefig(p, dpi=dpi, format=figure_format(p))
    return p
