"""Interactive t_cr explorer for the report: standalone Plotly HTML, no server, no network.

Two figures, written as one HTML fragment that carries plotly.js inline (so the
report stays one self-contained file):

* t_cr(omega_p) of the exact rig model (thesis Eq. 61 friction) for several
  mu_s and theta_0, with the 54 measured runs of Appendix B; hovering a run
  shows its number, spin, measured t_cr and the model's t_cr at the thesis's
  mu_s = 0.5473 and theta_0 = 87.25 deg;
* theta(t) of the model for one run at a time, chosen from a drop-down menu.

Plotly is the well-kept library that writes standalone interactive HTML; the
data come from :func:`explorer_data` (a labelled xarray Dataset).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import xarray as xr

from ..calibration import SpinRigData, load_thesis_data
from ..model.cases import rig_case
from ..reference import TABLE1, THESIS_MU_S
from ..solve import SolverOptions, opening_times, simulate

__all__ = ["explorer_data", "explorer_html"]

_N_THETA = 240  # samples kept per theta(t) history


def explorer_data(
    mu_s_values: Sequence[float] = (0.35, 0.45, THESIS_MU_S, 0.5875),
    theta0_deg_values: Sequence[float] = (85.0, TABLE1["theta0_deg"]),
    spin_rates: Sequence[float] | None = None,
    *,
    data: SpinRigData | None = None,
    options: SolverOptions | None = None,
) -> xr.Dataset:
    """t_cr curves, the measured runs with the model at each, and theta(t) per run.

    Parameters
    ----------
    mu_s_values : sequence of float
        Sliding friction coefficients of the curves [-] (Table 1: 0.35; chapter
        IV: 0.5473; exact-model fit to the starred runs: 0.5875).
    theta0_deg_values : sequence of float
        Initial nutation angles of the curves [deg].
    spin_rates : sequence of float, optional
        Curve abscissae [rad/s]; default 28 points log-spaced over 60-700.
    data : SpinRigData, optional
        Measured runs; default Appendix B.
    options : SolverOptions, optional

    Returns
    -------
    xarray.Dataset
        ``t_cr(mu_s, theta0_deg, spin_rate)`` [s]; per run ``measured``,
        ``model`` (thesis mu_s and theta_0) [s], ``spin`` [rad/s], ``run``;
        ``theta(run, sample)`` [deg] on ``t(run, sample)`` [s].
    """
    data = load_thesis_data() if data is None else data
    w = np.geomspace(60.0, 700.0, 28) if spin_rates is None else np.asarray(spin_rates, float)
    mus = [float(m) for m in mu_s_values]
    ths = [float(t) for t in theta0_deg_values]
    cases = [rig_case(x, m, theta0_deg=t) for m in mus for t in ths for x in w]
    curves = opening_times(cases, options, strict=True)[0].reshape(len(mus), len(ths), w.size)
    n = len(data.run)
    theta = np.full((n, _N_THETA), np.nan)
    times = np.full((n, _N_THETA), np.nan)
    model = np.empty(n)
    for i, spin in enumerate(data.spin_rate):
        res = simulate(rig_case(float(spin), THESIS_MU_S), options)
        model[i] = res.opening_time
        k = np.linspace(0, len(res.t) - 1, min(_N_THETA, len(res.t))).astype(int)
        times[i, : k.size] = res.t[k]
        theta[i, : k.size] = np.degrees(res.theta[k])
    return xr.Dataset(
        {
            "t_cr": (("mu_s", "theta0_deg", "spin_rate"), curves, {"units": "s"}),
            "measured": ("run", data.opening_time, {"units": "s", "long_name": "measured t_cr"}),
            "model": (
                "run",
                model,
                {"units": "s", "long_name": f"model t_cr, mu_s = {THESIS_MU_S}"},
            ),
            "spin": ("run", data.spin_rate, {"units": "rad/s"}),
            "starred": ("run", data.starred),
            "t": (("run", "sample"), times, {"units": "s"}),
            "theta": (("run", "sample"), theta, {"units": "deg"}),
        },
        coords={
            "mu_s": ("mu_s", mus),
            "theta0_deg": ("theta0_deg", ths, {"units": "deg"}),
            "spin_rate": ("spin_rate", w, {"units": "rad/s"}),
            "run": ("run", data.run),
        },
        attrs={"title": "t_cr explorer", "model_theta0_deg": TABLE1["theta0_deg"]},
    )


def _tcr_figure(ds: xr.Dataset):
    import plotly.graph_objects as go

    fig = go.Figure()
    for m in ds["mu_s"].values:
        for t in ds["theta0_deg"].values:
            dash = "solid" if math.isclose(t, TABLE1["theta0_deg"]) else "dash"
            fig.add_trace(
                go.Scatter(
                    x=ds["spin_rate"].values,
                    y=ds["t_cr"].sel(mu_s=m, theta0_deg=t).values,
                    mode="lines",
                    line={"dash": dash},
                    name=f"model, mu_s = {m:g}, theta0 = {t:g} deg",
                    hovertemplate="omega_p = %{x:.1f} rad/s<br>t_cr = %{y:.4f} s<extra>"
                    + f"mu_s {m:g}, theta0 {t:g} deg</extra>",
                )
            )
    custom = np.column_stack([ds["run"].values, ds["model"].values])
    for starred, label, symbol in ((True, "starred", "circle"), (False, "other", "circle-open")):
        sel = ds["starred"].values == starred
        fig.add_trace(
            go.Scatter(
                x=ds["spin"].values[sel],
                y=ds["measured"].values[sel],
                customdata=custom[sel],
                mode="markers",
                marker={"symbol": symbol, "size": 8, "color": "black"},
                name=f"measured runs ({label}, Appendix B)",
                hovertemplate="run %{customdata[0]:.0f}<br>omega_p = %{x:.2f} rad/s"
                "<br>measured t_cr = %{y:.4f} s<br>model t_cr = %{customdata[1]:.4f} s"
                f" (mu_s = {THESIS_MU_S}, theta0 = {TABLE1['theta0_deg']} deg)<extra></extra>",
            )
        )
    fig.update_layout(
        title="Opening time t_cr vs spin rate (exact model, spin rig)",
        xaxis_title="projectile spin omega_p [rad/s]",
        yaxis={"title": "t_cr [s]", "type": "log"},
        height=520,
        template="plotly_white",
    )
    return fig


def _theta_figure(ds: xr.Dataset):
    import plotly.graph_objects as go

    fig = go.Figure()
    n = ds.sizes["run"]
    for i in range(n):
        run = int(ds["run"].values[i])
        fig.add_trace(
            go.Scatter(
                x=ds["t"].values[i],
                y=ds["theta"].values[i],
                mode="lines",
                visible=i == 0,
                name=f"run {run}",
                hovertemplate="t = %{x:.4f} s<br>theta = %{y:.2f} deg<extra></extra>",
            )
        )
    buttons = []
    for i in range(n):
        run = int(ds["run"].values[i])
        vis = [j == i for j in range(n)]
        title = (
            f"theta(t) for run {run}: omega_p = {float(ds['spin'][i]):.1f} rad/s, measured "
            f"t_cr = {float(ds['measured'][i]):.4f} s, model {float(ds['model'][i]):.4f} s"
        )
        buttons.append(
            {
                "label": f"run {run}",
                "method": "update",
                "args": [{"visible": vis}, {"title": title}],
            }
        )
    fig.update_layout(
        updatemenus=[{"buttons": buttons, "direction": "down", "x": 1.0, "y": 1.15}],
        title=buttons[0]["args"][1]["title"] if buttons else "theta(t)",
        xaxis_title="time t [s]",
        yaxis_title="nutation angle theta [deg]",
        height=420,
        template="plotly_white",
    )
    return fig


def explorer_html(ds: xr.Dataset) -> str:
    """HTML fragment with both figures and plotly.js inline (works offline).

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`explorer_data`.
    """
    a = _tcr_figure(ds).to_html(full_html=False, include_plotlyjs=True, div_id="tcr-explorer")
    b = _theta_figure(ds).to_html(full_html=False, include_plotlyjs=False, div_id="theta-explorer")
    return f'<div class="explorer">\n{a}\n{b}\n</div>'
