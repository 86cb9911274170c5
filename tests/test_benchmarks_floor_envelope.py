"""The operating-range cost benchmark and the envelope-following study compute what they
say (correctness of their pieces, not timing)."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # benchmarks/ lives at the root

from benchmarks import envelope_following as ef  # noqa: E402
from benchmarks import rhs_floor  # noqa: E402


def test_band_costs_partition_the_grid_and_count_work():
    spins = np.linspace(40.0, 1000.0, 14)
    rows = rhs_floor.band_costs(spins)
    assert sum(r["points"] for r in rows) == spins.size  # every point in exactly one band
    for r in rows:
        assert r["rhs_per_point"] > 100 and r["cpu_s"] > 0.0
        assert math.isclose(r["ns_per_rhs"], 1e9 * r["cpu_s"] / (r["rhs_per_point"] * r["points"]))
    routes = " ".join(r["routes"] for r in rows)
    assert "set-valued" in routes and "regularised" in routes


def test_point_rhs_counts_one_opening_time():
    """A point alone at the defaults: its count is that of ``opening_times`` of a batch
    of one, which integrates at least the start to theta_cr (thousands of evaluations)."""
    n = rhs_floor.point_rhs(np.array([300.0, 700.0]))
    assert np.all(n > 1000) and n[1] > n[0]  # more revolutions to the opening at 700 rad/s


@settings(max_examples=50, deadline=None)
@given(
    theta=st.floats(0.05, math.pi - 0.05),
    rates=st.tuples(*(st.floats(-500.0, 500.0) for _ in range(3))),
)
def test_section_state_and_reduced_coordinates_are_inverse(theta, rates):
    x = np.array([theta, *rates])
    y = ef.state(x, 700.0)
    assert abs(np.linalg.norm(y[:4]) - 1.0) < 1e-14
    assert ef._rotation(y)[0, 2] == pytest.approx(0.0, abs=1e-15)  # on the section psi = 0
    np.testing.assert_allclose(ef.reduced(y), x, rtol=1e-12, atol=1e-10)


def test_reduced_coordinates_ignore_a_turn_about_the_hole_axis():
    """The symmetry the sections rest on: turning the ball about its own axis z (body
    rates turned back by the same angle) changes neither theta nor the nodal rates."""
    y = ef.state(np.array([1.2, 3.0, -20.0, 150.0]), 700.0)
    a = 0.7
    qz = np.array([math.cos(a / 2), 0.0, 0.0, math.sin(a / 2)])
    q = y[:4]
    turned = np.array(
        [
            q[0] * qz[0] - q[3] * qz[3],
            q[1] * qz[0] + q[2] * qz[3],
            q[2] * qz[0] - q[1] * qz[3],
            q[3] * qz[0] + q[0] * qz[3],
        ]
    )
    c, s = math.cos(a), math.sin(a)
    w = y[4:7]
    body = np.array([c * w[0] + s * w[1], -s * w[0] + c * w[1], w[2]])
    np.testing.assert_allclose(ef.reduced(np.r_[turned, body, y[7]]), ef.reduced(y), atol=1e-10)


def test_whole_sweep_benchmark_times_a_real_sweep_and_reads_its_compute_time():
    """One small sweep of this tree in a fresh process: the wall time from outside covers
    the summary line's compute time (the workers' part), the processor time of the
    process tree covers most of that compute time (it is spent computing, in the sweep's
    process or its workers: a count of this process's own time would be near zero), and
    the ratios' reference is the first tree (1 against itself)."""
    from benchmarks import sweeps

    rec = sweeps.measure([sweeps.ROOT], ((300.0, 400.0, 40),), workers=1, rounds=1, warm_points=4)
    (row,) = rec["rows"]
    assert row["sweep"] == "40 points, 300-400 rad/s" and row["speed_up"] == 1.0
    assert 0.0 < row["compute_s"] < row["wall_s"]
    assert row["outside_s"] == pytest.approx(row["wall_s"] - row["compute_s"])
    assert row["cpu_s"] > 0.5 * row["compute_s"] and row["cpu_ratio"] == 1.0
    assert sweeps._parse_sweeps("40:1000:10000,100:700:20") == (
        (40.0, 1000.0, 10000),
        (100.0, 700.0, 20),
    )


def test_time_scales_against_an_independent_integration():
    """The ball's turns in its socket to the opening at 300 rad/s, against the same
    integral computed independently: scipy's DOP853 on the package's right-hand side with
    the integral of |omega_r| as a ninth state (rtol 1e-10), stopped at theta_cr. The
    ball turns in its socket fewer times than the socket turns; the smallest moment arm
    of a revolution lies in (0, 1) (thesis Eq. 61)."""
    from scipy.integrate import solve_ivp

    spin = 300.0
    rec = ef.time_scales(spin)
    run = ef.Revolutions(spin, 1e-10)
    dy = np.empty(8)

    def f(t, y):
        run._rhs(t, y[:8], run.p, dy)
        w_r = ef._rotation(y[:8]) @ y[4:7] - y[7] * ef.Z
        return np.r_[dy, np.linalg.norm(w_r)]

    def opening(t, y):
        return ef.reduced(y[:8])[0] - run.theta_cr

    opening.terminal, opening.direction = True, -1.0
    atol = 1e-12 * np.r_[1, 1, 1, 1, spin, spin, spin, spin, 1.0]
    sol = solve_ivp(f, (0.0, 1.0), np.r_[run.y0, 0.0], method="DOP853", rtol=1e-10,
                    atol=atol, events=opening)  # fmt: skip
    t_cr = float(sol.t_events[0][0])
    turns = float(sol.y_events[0][0][8]) / (2.0 * math.pi)
    assert rec["t_cr_s"] == pytest.approx(t_cr, rel=1e-6)
    assert rec["revolutions"] == pytest.approx(t_cr * spin / (2.0 * math.pi), rel=1e-6)
    # the sampled trapezoid (256 a revolution) against the quadrature state
    assert rec["turns"] == pytest.approx(turns, rel=1e-4)
    assert 1.0 < rec["turns"] < rec["revolutions"]
    assert 0.0 < rec["smallest_arm"] < 1.0


def test_cost_per_revolution_of_full_integrations():
    """At 300 rad/s the default setting is the sweep's count (``rhs_floor.point_rhs``,
    the front door at the defaults) per revolution and within the package's t_cr accuracy
    (1e-6); the looser settings cost fewer right-hand sides a revolution."""
    spin = 300.0
    rows = ef.per_revolution(spin)
    assert [r["setting"] for r in rows] == [s[0] for s in ef.FULL_SETTINGS]
    default = rows[0]
    assert abs(default["rel_error"]) < 1e-6
    t_cr = ef.time_scales(spin)["t_cr_s"]
    n = int(rhs_floor.point_rhs(np.array([spin]))[0])
    assert default["rhs_per_revolution"] == pytest.approx(n * 2.0 * math.pi / spin / t_cr, rel=1e-9)
    costs = [r["rhs_per_revolution"] for r in rows]
    assert costs[0] > costs[1] > costs[2] > costs[3] > 50.0
