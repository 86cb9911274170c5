"""The opening animation's geometry (``obturator.animation``), frame by frame.

Reference values are closed-form: the hole axis of frame k must make the angle
theta(t_k) with the bore axis Z (z-x-z Euler angles, thesis Fig. 7), every point of the
ball's outer surface lies at R_s from the centre, and the hole's wall at r_s from the
hole axis (the bored ball of thesis Fig. 2, Table 1's 7.899 and 4.72 mm).
"""

from __future__ import annotations

import numpy as np
import pytest

from obturator import rig_case, simulate
from obturator.animation import N_FRAMES, animation_figure, animation_html


@pytest.fixture(scope="module")
def run():
    return simulate(rig_case(spin_rate=300.0, mu_s=0.5473))


def test_each_frame_turns_the_hole_axis_to_theta(run):
    fig = animation_figure(run)
    assert len(fig.frames) == N_FRAMES
    times = np.linspace(0.0, run.opening_time, N_FRAMES)
    theta = np.interp(times, run.t, run.theta)
    for k, frame in enumerate(fig.frames):
        ball, wall, axis, marker = frame.data
        a = np.array([np.diff(axis.x)[0], np.diff(axis.y)[0], np.diff(axis.z)[0]])
        angle = np.arccos(abs(a[2]) / np.linalg.norm(a))
        assert angle == pytest.approx(min(theta[k], np.pi - theta[k]), abs=2e-4)
        r = np.sqrt(np.asarray(ball.x) ** 2 + np.asarray(ball.y) ** 2 + np.asarray(ball.z) ** 2)
        assert np.allclose(r, 7.899, atol=2e-3)  # mm, 3 decimals kept
        # the hole's wall: distance r_s from the hole axis through the centre
        p = np.stack([np.asarray(wall.x), np.asarray(wall.y), np.asarray(wall.z)], axis=-1)
        u = a / np.linalg.norm(a)
        d = np.linalg.norm(p - (p @ u)[..., None] * u, axis=-1)
        assert np.allclose(d, 4.72, atol=3e-3)
        assert marker.x[0] == pytest.approx(times[k])
        assert marker.y[0] == pytest.approx(np.degrees(theta[k]))
    # the last frame is the opening: theta = theta_cr = beta_s
    assert theta[-1] == pytest.approx(run.case.opening_angle, abs=1e-6)


def test_fragment_carries_plotly_inline(run):
    html = animation_html(run, div_id="anim-x")
    assert 'id="anim-x"' in html
    assert "<script src=" not in html and len(html) > 3_000_000  # plotly.js itself inline
