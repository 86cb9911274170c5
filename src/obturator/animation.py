"""The opening as an animation: the ball in its socket, nutating, its hole turning into line.

One standalone Plotly figure (plotly.js inline, so the HTML file works offline): on the
left the bored ball (thesis Fig. 2: a sphere of radius R_s bored along one diameter with
a hole of radius r_s) in the projectile's bore, seen in the projectile's frame; on the
right theta(t) with the opening angle theta_cr = beta_s and a marker at the frame's time.
A slider (and a play button) steps through the frames.

Orientation: the run's z-x-z Euler angles (thesis Fig. 7; body -> inertial
R = Rz(psi) Rx(theta) Rz(phi), :mod:`obturator.core.dynamics`). The projectile turns
about the inertial Z axis by Omega(t) = integral of omega_p dt; the view turns back by
Omega, R' = Rz(psi - Omega) Rx(theta) Rz(phi), so the socket and bore stand still and
the ball's own motion relative to the projectile is what moves (a ball carried round
rigidly with the projectile stands still). The hole axis makes the angle theta with
the bore axis Z; the bore opens (first light) when theta reaches beta_s.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    import plotly.graph_objects as go

    from .result import NutationResult

__all__ = ["animation_figure", "animation_html", "write_animation"]

#: Frames of an animation: enough to follow theta (a frame per 1 % of the run).
N_FRAMES = 100
_N_POLAR, _N_AZIMUTH = 15, 32  # surface grid of the ball (small: every frame carries it)
_MM = 1e3  # the view is drawn in millimetres


def _rotation(psi: float, theta: float, phi: float) -> np.ndarray:
    """z-x-z rotation matrix Rz(psi) Rx(theta) Rz(phi) (body -> projectile axes)."""
    cp, sp, ct, st, cf, sf = (
        math.cos(psi),
        math.sin(psi),
        math.cos(theta),
        math.sin(theta),
        math.cos(phi),
        math.sin(phi),
    )
    rz1 = np.array([[cp, -sp, 0.0], [sp, cp, 0.0], [0.0, 0.0, 1.0]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, ct, -st], [0.0, st, ct]])
    rz2 = np.array([[cf, -sf, 0.0], [sf, cf, 0.0], [0.0, 0.0, 1.0]])
    return rz1 @ rx @ rz2


def _ball_mesh(radius: float, hole: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Body-frame points of the ball's outer surface, of its hole's wall, and the
    stripe colour of the outer surface (so the ball's own spin phi shows).

    Returns arrays of shape (3, n_polar, n_azimuth), (3, 2, n_azimuth) and
    (n_polar, n_azimuth).
    """
    cap = math.asin(min(hole / radius, 1.0))  # polar half-angle of each hole's mouth
    a = np.linspace(cap, math.pi - cap, _N_POLAR)[:, None]
    b = np.linspace(0.0, 2.0 * math.pi, _N_AZIMUTH)[None, :]
    outer = radius * np.array(
        [np.sin(a) * np.cos(b), np.sin(a) * np.sin(b), np.cos(a) * np.ones_like(b)]
    )
    h = math.sqrt(max(radius**2 - hole**2, 0.0))
    zb = np.array([[-h], [h]])
    wall = np.array(
        [hole * np.cos(b) * np.ones_like(zb), hole * np.sin(b) * np.ones_like(zb), zb * (b * 0 + 1)]
    )
    stripes = (np.floor(np.ones_like(a) * b / (math.pi / 4)) % 2).astype(float)
    return outer, wall, stripes


def _xyz(trace: dict[str, Any]) -> dict[str, Any]:
    return {k: trace[k] for k in ("x", "y", "z")}


def _turned(points: np.ndarray, rot: np.ndarray) -> np.ndarray:
    # micrometre resolution [mm, 3 decimals]: far below a pixel, and a smaller file
    return np.round(np.einsum("ij,j...->i...", rot, points), 3)


def _frame_angles(
    res: NutationResult, n_frames: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Frame times [s] and psi - Omega, theta, phi [rad] there (linear interpolation)."""
    t = np.asarray(res.t, dtype=float)
    spin = np.asarray(res.spin_rate, dtype=float)
    # Omega(t): the projectile's turn about Z (trapezoid rule over the run's own samples)
    omega = np.concatenate(([0.0], np.cumsum(0.5 * (spin[1:] + spin[:-1]) * np.diff(t))))
    end = res.opening_time if res.opening_time == res.opening_time else t[-1]
    times = np.linspace(t[0], end, n_frames)
    psi = np.interp(times, t, np.asarray(res.psi) - omega)
    return times, psi, np.interp(times, t, res.theta), np.interp(times, t, res.phi)


def animation_figure(
    res: NutationResult, title: str | None = None, n_frames: int = N_FRAMES
) -> go.Figure:
    """A Plotly figure animating one run: the ball in its bore and theta(t).

    Parameters
    ----------
    res : NutationResult
        The run (its time series and its case's ball).
    title : str, optional
        Figure title; default names the case, spin, theta_0 and t_cr.
    n_frames : int
        Frames, evenly spaced in time from release to the opening (or the run's end).

    Returns
    -------
    plotly.graph_objects.Figure
        Three 3-D traces (ball, hole wall, hole axis) and the bore in a scene, theta(t)
        in degrees beside it, one frame per time with a slider.
    """
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    ball = res.case.ball
    big, hole = ball.radius * _MM, ball.hole_radius * _MM
    outer, wall, stripes = _ball_mesh(big, hole)
    axis = np.array([[0.0, 0.0], [0.0, 0.0], [-1.5 * big, 1.5 * big]])
    times, psi, theta, phi = _frame_angles(res, n_frames)
    theta_cr = res.case.opening_angle

    def ball_traces(k: int) -> list[dict[str, Any]]:
        rot = _rotation(psi[k], theta[k], phi[k])
        o, w, a = _turned(outer, rot), _turned(wall, rot), _turned(axis, rot)
        return [
            {"type": "surface", "x": o[0], "y": o[1], "z": o[2]},
            {"type": "surface", "x": w[0], "y": w[1], "z": w[2]},
            {"type": "scatter3d", "x": a[0], "y": a[1], "z": a[2]},
        ]

    fig = make_subplots(
        rows=1,
        cols=2,
        column_widths=[0.55, 0.45],
        specs=[[{"type": "scene"}, {"type": "xy"}]],
        subplot_titles=(
            "ball in the projectile's bore (projectile frame)",
            "nutation theta(t)",
        ),
    )
    first = ball_traces(0)
    fig.add_trace(
        go.Surface(
            **_xyz(first[0]),
            surfacecolor=stripes,
            colorscale=[[0.0, "#9aa7b4"], [1.0, "#5b6b7a"]],
            cmin=0.0,
            cmax=1.0,
            showscale=False,
            name="ball",
            hoverinfo="skip",
        ),
        row=1,
        col=1,
    )
    fig.add_trace(
        go.Surface(
            **_xyz(first[1]),
            surfacecolor=np.zeros((2, _N_AZIMUTH)),
            colorscale=[[0.0, "#d9822b"], [1.0, "#d9822b"]],
            showscale=False,
            name="hole wall",
            hoverinfo="skip",
        ),
        row=1,
        col=1,
    )
    fig.add_trace(
        go.Scatter3d(
            **_xyz(first[2]), mode="lines", line={"color": "#d9822b", "width": 6}, name="hole axis"
        ),
        row=1,
        col=1,
    )
    # the projectile's bore (radius r_s, thesis Table 1: the hole's) up- and downstream
    b = np.linspace(0.0, 2.0 * math.pi, _N_AZIMUTH)
    for lo, hi in ((-2.6 * big, -1.02 * big), (1.02 * big, 2.6 * big)):
        z = np.array([[lo], [hi]]) * np.ones_like(b)[None, :]
        fig.add_trace(
            go.Surface(
                x=hole * np.cos(b)[None, :] * np.ones((2, 1)),
                y=hole * np.sin(b)[None, :] * np.ones((2, 1)),
                z=z,
                surfacecolor=np.zeros_like(z),
                colorscale=[[0.0, "#4c78a8"], [1.0, "#4c78a8"]],
                opacity=0.35,
                showscale=False,
                name="bore",
                hoverinfo="skip",
            ),
            row=1,
            col=1,
        )
    fig.add_trace(
        go.Scatter3d(
            x=[0.0, 0.0],
            y=[0.0, 0.0],
            z=[-2.6 * big, 2.6 * big],
            mode="lines",
            line={"color": "#4c78a8", "width": 3, "dash": "dash"},
            name="bore axis Z",
        ),
        row=1,
        col=1,
    )
    t_all, th_all = np.asarray(res.t), np.degrees(np.asarray(res.theta))
    fig.add_trace(
        go.Scatter(x=t_all, y=th_all, mode="lines", line={"color": "#333"}, name="theta(t)"),
        row=1,
        col=2,
    )
    deg_cr = math.degrees(theta_cr)
    fig.add_trace(
        go.Scatter(
            x=[t_all[0], t_all[-1]],
            y=[deg_cr, deg_cr],
            mode="lines+text",
            line={"color": "#d9822b", "dash": "dot"},
            text=["", f"theta_cr = beta_s = {deg_cr:.1f} deg: the bore opens"],
            textposition="top left",
            name="theta_cr",
        ),
        row=1,
        col=2,
    )

    def now(k: int) -> dict[str, Any]:  # the frame's time and theta, marked and written
        deg = math.degrees(theta[k])
        text = f"t = {times[k]:.4g} s, theta = {deg:.1f} deg"
        return {"type": "scatter", "x": [float(times[k])], "y": [deg], "text": [text]}

    fig.add_trace(
        go.Scatter(
            **{k: v for k, v in now(0).items() if k != "type"},
            mode="markers+text",
            textposition="middle right",
            marker={"size": 11, "color": "#d9822b"},
            name="now",
        ),
        row=1,
        col=2,
    )
    moving = [0, 1, 2, len(fig.data) - 1]  # ball, hole wall, hole axis, theta marker
    frames, steps = [], []
    for k, tk in enumerate(times):
        name = f"f{k}"
        frames.append(go.Frame(name=name, data=[*ball_traces(k), now(k)], traces=moving))
        steps.append(
            {
                "method": "animate",
                "label": f"{tk:.3g}",
                "args": [
                    [name],
                    {"mode": "immediate", "frame": {"duration": 0, "redraw": True}},
                ],
            }
        )
    fig.frames = frames
    lim = 2.6 * big
    fig.update_layout(
        title={"text": title or _title(res), "x": 0.02},
        template="plotly_white",
        height=620,
        showlegend=False,
        scene={
            "xaxis": {"range": [-lim, lim], "title": "X [mm]"},
            "yaxis": {"range": [-lim, lim], "title": "Y [mm]"},
            "zaxis": {"range": [-lim, lim], "title": "Z, bore axis [mm]"},
            "aspectmode": "cube",
            "camera": {"eye": {"x": 1.6, "y": 1.2, "z": 0.6}},
        },
        xaxis={"title": "t [s]"},
        yaxis={"title": "theta [deg]"},
        sliders=[
            {
                "active": 0,
                "currentvalue": {"prefix": "t [s] = "},
                "pad": {"t": 40},
                "x": 0.1,
                "len": 0.9,
                "steps": steps,
            }
        ],
        updatemenus=[
            {
                "type": "buttons",
                "showactive": False,
                "x": 0.0,
                "y": -0.12,
                "xanchor": "left",
                "direction": "left",
                "buttons": [
                    {
                        "label": "play",
                        "method": "animate",
                        "args": [
                            None,
                            {"frame": {"duration": 60, "redraw": True}, "fromcurrent": True},
                        ],
                    },
                    {
                        "label": "pause",
                        "method": "animate",
                        "args": [[None], {"mode": "immediate", "frame": {"duration": 0}}],
                    },
                ],
            }
        ],
    )
    return fig


def _title(res: NutationResult) -> str:
    case = res.case
    t_cr = res.opening_time
    opened = f"t_cr = {t_cr:.4g} s" if t_cr == t_cr else "not opened"
    return (
        f"{case.name or 'case'}: omega_p = {case.spin_rate:.4g} rad/s, theta_0 = "
        f"{math.degrees(case.theta0):.2f} deg, {opened}"
    )


def animation_html(
    res: NutationResult,
    div_id: str = "opening-animation",
    include_plotlyjs: bool = True,
    **kw: Any,
) -> str:
    """HTML fragment of :func:`animation_figure` (plotly.js inline unless the page
    already carries it: the file then works offline).

    Parameters
    ----------
    res : NutationResult
        The run.
    div_id : str
        The id of the figure's ``div``.
    include_plotlyjs : bool
        Inline plotly.js (False where the page has it already, as the report does).
    **kw
        Passed to :func:`animation_figure` (``title``, ``n_frames``).

    Returns
    -------
    str
        One ``div`` and the scripts that draw it.
    """
    fig = animation_figure(res, **kw)
    return fig.to_html(
        full_html=False, include_plotlyjs=include_plotlyjs, div_id=div_id, auto_play=False
    )


def write_animation(res: NutationResult, path: str) -> None:
    """Write the standalone animation of `res` to `path` (HTML, plotly.js inline; atomic).

    Parameters
    ----------
    res : NutationResult
        The run.
    path : str
        Output HTML file.
    """
    from .files import atomic_write_text

    fig = animation_figure(res)
    text = fig.to_html(
        full_html=True, include_plotlyjs=True, div_id="opening-animation", auto_play=False
    )
    atomic_write_text(path, text)
