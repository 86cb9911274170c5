"""The set-valued stick-slip solver (``method="set-valued"``, docs/stick_slip.md).

References: the closed forms of the admissible set and of stick (thesis Eqs. 5a-5c,
35-36, 61, Appendix A's arm), and the regularised family limit computed here with
Radau IIA at tight settings (an independent path: no events, no closed-form stick).
"""

from __future__ import annotations

import dataclasses
import math
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from obturator.core.friction_sets import (
    breakaway_angle,
    hold_stick,
    required_reaction,
    stick_margin,
    turn_rigidly,
)
from obturator.errors import InputError
from obturator.model.cases import flight_case, rig_case
from obturator.model.torques import SlipSpeedLaw
from obturator.reference import THESIS_MU_S
from obturator.solve import (
    SolverOptions,
    convergence_check,
    opening_time,
    pack_parameters,
    simulate,
)

SET_VALUED = SolverOptions(method="set-valued", rtol=1e-10, atol=1e-12)
RIG = rig_case(200.0, THESIS_MU_S)
P_RIG = pack_parameters(RIG, SET_VALUED)
P_FLIGHT = pack_parameters(flight_case(), SET_VALUED)
M_RIG = THESIS_MU_S * RIG.torque.friction.weight * RIG.ball.radius

finite = st.floats(-1.0, 1.0, allow_nan=False)


@settings(deadline=None)  # the first call loads compiled code
@given(finite, finite, finite)
def test_rig_admissible_set_is_the_horn_torus(gx, gy, gz):
    """Eq. (61) at zero slip: G in F iff G_X^2 + rho^2 <= M rho (rho = |(G_Y, G_Z)|)."""
    g = np.array([gx, gy, gz]) * M_RIG
    rho = math.hypot(g[1], g[2])
    torus = M_RIG * rho - (g[0] ** 2 + rho**2)
    margin = stick_margin(g[0], g[1], g[2], P_RIG)
    if abs(torus) > 1e-9 * M_RIG**2:
        assert (margin > 0.0) == (torus > 0.0)


def test_rig_set_holds_no_moment_about_x():
    """The rig's bottom contact holds no moment about the gravity axis X alone."""
    assert stick_margin(1e-9 * M_RIG, 0.0, 0.0, P_RIG) < 0.0
    assert stick_margin(1e-3 * M_RIG, 0.1 * M_RIG, 0.0, P_RIG) > 0.0


def _attitude(theta: float, psi: float) -> np.ndarray:
    """Quaternion state with hole axis at nutation theta and azimuth psi, in stick."""
    # z-x-z Euler angles (psi, theta, 0): z = (sin th sin ps, -sin th cos ps, cos th)
    ps = psi + 0.5 * math.pi  # so that z_X = sin(theta) cos(psi)
    c1, s1 = math.cos(0.5 * ps), math.sin(0.5 * ps)
    c2, s2 = math.cos(0.5 * theta), math.sin(0.5 * theta)
    y = np.array([c1 * c2, c1 * s2, s1 * s2, s1 * c2, 0.0, 0.0, 0.0, RIG.spin_rate])
    hold_stick(y, RIG.spin_rate)
    return y


P_BY_LAW = {
    "rig": P_RIG,
    "flight": P_FLIGHT,
    # the Coulomb patch law: closed form for the rig's one patch, scanned for the ring
    "coulomb rig": pack_parameters(
        rig_case(200.0, THESIS_MU_S, torque_model="coulomb"), SET_VALUED
    ),
    "coulomb flight": pack_parameters(flight_case(torque_model="coulomb"), SET_VALUED),
}


@settings(max_examples=80, deadline=None)
@given(st.floats(0.2, 1.5), st.floats(0.0, 2 * math.pi), st.sampled_from(list(P_BY_LAW)))
def test_breakaway_angle_is_the_first_exit_from_the_set(theta, psi, which):
    """The exit angle against sampling the margin along the rigid turn."""
    p = P_BY_LAW[which]
    y = _attitude(theta, psi)
    wp = RIG.spin_rate

    def margin(angle: float) -> float:
        out = np.empty(8)
        turn_rigidly(y, angle, out)
        return stick_margin(*required_reaction(out, p, wp), p)

    if margin(0.0) <= 0.0:
        return
    angle = breakaway_angle(y, p, wp)
    grid = np.linspace(0.0, 2.0 * math.pi, 4001)[1:]
    outside = [a for a in grid if margin(a) < 0.0]
    if not outside:
        assert math.isinf(angle)
        return
    assert angle <= outside[0] + 1e-12
    assert margin(angle * (1 - 1e-9)) >= -1e-12 * M_RIG
    assert abs(margin(angle)) < 1e-9 * p[13]
    assert all(margin(a) > 0.0 for a in grid if a < angle * (1 - 1e-6))


def test_stuck_ball_turns_rigidly_with_the_socket():
    """Pure stick (closed form): until the breakaway, theta stays at theta_0 and the
    ball's rates stay omega_p Z, whatever the integrator does elsewhere."""
    case = rig_case(40.0, THESIS_MU_S)
    y0 = case.initial_state("quaternion")
    p = pack_parameters(case, SET_VALUED)
    # release at an azimuth inside the stick set: turn the release state rigidly
    y = y0.copy()
    turn_rigidly(y0, 0.5 * math.pi, y)
    stuck = breakaway_angle(y, p, 40.0) / 40.0
    assert 0.0 < stuck < math.inf
    times = np.linspace(0.0, 0.999 * stuck, 7)[1:]
    res = simulate(dataclasses.replace(case, t_max=stuck), SET_VALUED, y0=y, t_eval=times)
    assert np.ptp(res.theta) < 1e-13
    assert res.theta[0] == pytest.approx(math.radians(87.25), abs=1e-12)
    assert np.max(res.omega_r) < 1e-12
    assert res.n_steps == 0


def test_no_torque_no_breakaway():
    """theta_0 = 90 deg exactly: G_req = 0 lies in F forever, so the ball never opens."""
    case = rig_case(200.0, THESIS_MU_S, theta0_deg=90.0, t_max=5.0)
    res = simulate(case, SET_VALUED)
    assert math.isnan(res.opening_time)
    assert res.n_steps == 0


def _regularised_limit(case) -> tuple[float, float]:
    """t_cr of the tanh and linear families at width 1e-10 omega_p, Radau IIA, rtol 1e-12."""
    out = []
    for family in ("tanh", "linear"):
        opts = SolverOptions(
            method="radau", rtol=1e-12, atol=1e-14, friction_width=1e-10, friction_family=family
        )
        out.append(opening_time(case, opts))
    return out[0], out[1]


@pytest.mark.parametrize("spin", [200.0, 300.0])
def test_rig_agrees_with_the_regularised_limit(spin):
    """Two independent answers: event-driven exact stick vs the width -> 0 limit."""
    case = rig_case(spin, THESIS_MU_S)
    t_sv = opening_time(case, SolverOptions(method="set-valued", rtol=1e-12, atol=1e-14))
    t_tanh, t_lin = _regularised_limit(case)
    spread = abs(t_tanh - t_lin) / t_sv
    assert abs(t_sv - t_tanh) / t_sv < max(2e-8, 2 * spread)


@pytest.mark.parametrize(("mach", "mu_s"), [(3.0, 0.35), (1.5, THESIS_MU_S)])
def test_flight_agrees_with_the_regularised_path(mach, mu_s):
    """Flight slips throughout: the set-valued t_cr is the regularised one to 1e-7."""
    case = flight_case(mu_s=mu_s, mach=mach)
    t_sv = opening_time(case, SolverOptions(method="set-valued", rtol=1e-12, atol=1e-14))
    t_reg = opening_time(case, SolverOptions(rtol=1e-12, atol=1e-14, friction_width=1e-9))
    assert t_sv == pytest.approx(t_reg, rel=1e-7)


@pytest.mark.parametrize("case", [rig_case(700.0, THESIS_MU_S), flight_case()])
def test_outputs_through_the_dop853_stretches(case):
    """Fast slip runs in DOP853 stretches: the recorded run ends at the opening that
    opening_time finds in the mode loop (bit for bit; the last slip in the DOP853 lanes,
    the default route, within the tolerances), and states at given times match the
    regularised path's."""
    t_cr = opening_time(case, dataclasses.replace(SET_VALUED, slip_lanes=False))
    rec = simulate(case, SET_VALUED)
    assert rec.opening_time == t_cr
    assert opening_time(case, SET_VALUED) == pytest.approx(t_cr, rel=1e-9)
    assert rec.t[-1] == t_cr and np.all(np.diff(rec.t) > 0.0)
    times = np.linspace(0.1, 0.9, 5) * t_cr
    sv = simulate(case, SET_VALUED, t_eval=times)
    reg = simulate(case, SolverOptions(rtol=1e-10, atol=1e-12), t_eval=times)
    assert np.allclose(sv.t, times) and np.allclose(sv.theta, reg.theta, atol=1e-7)


def test_tolerance_convergence_near_stick():
    """78 rad/s (stick-slip over 40 revolutions): rtol 1e-10 and 1e-12 within 1e-8."""
    case = rig_case(78.0, THESIS_MU_S)
    t10 = opening_time(case, SET_VALUED)
    t12 = opening_time(case, SolverOptions(method="set-valued", rtol=1e-12, atol=1e-14))
    assert t10 == pytest.approx(t12, rel=1e-8)


def test_convergence_check_compares_with_the_regularised_path():
    """For the set-valued path the own error is the rerun at tighter tolerances; the
    regularised path (widths 1e-7 and 1e-8 omega_p, both families), extrapolated to zero
    width (Richardson: t_cr about linear in the width), is an independent cross-check: at
    200 rad/s it agrees within 1e-6, within its own two-family spread. The regularised
    runs' own width change is that path's error, larger than the set-valued one's."""
    check = convergence_check(RIG, SolverOptions(method="set-valued"))
    assert check.strategy == "set-valued" and check.converged
    assert check.tolerance_change < 1e-7
    assert check.cross_check_change < 1e-6
    assert check.cross_check_change < check.cross_check_spread + 1e-7
    assert check.width_change > check.tolerance_change
    assert check.to_dict()["cross_check"]["regularised_path"]["width_rel_change"] > 0.0


@pytest.mark.parametrize(
    ("case", "field"),
    [
        (
            rig_case(200.0, THESIS_MU_S, torque_model="coulomb", patch_radius=0.0),
            "patch_radius",
        ),
        (
            rig_case(200.0, THESIS_MU_S, speed_law=SlipSpeedLaw("weakening", 0.8)),
            "speed_law",
        ),
        (rig_case(200.0, THESIS_MU_S, spin_mode="thesis-energy"), "spin_mode"),
    ],
)
def test_out_of_scope_cases_are_refused(case, field):
    with pytest.raises(InputError, match=field):
        opening_time(case, SET_VALUED)


def test_euler_formulation_is_refused():
    with pytest.raises(InputError, match="formulation"):
        opening_time(RIG, dataclasses.replace(SET_VALUED, formulation="euler"))


def test_benchmark_rows():
    """benchmarks/stick_slip.py: both paths per case, ratios, errors against the
    tight set-valued reference (200 rad/s and flight)."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[2]))  # benchmarks/ at the root
    from benchmarks.stick_slip import PATHS, cost

    rows = cost((200.0,), repeat=1)
    assert [r["case"] for r in rows] == ["rig 200 rad/s", "flight (Table 1)"]
    for r in rows:
        assert set(r["ratio"]) == set(PATHS) - {"regularised"}
        assert r["set-valued"]["rel_error"] < 1e-7 and r["regularised"]["wall_s"] > 0.0


@pytest.mark.parametrize("case", [rig_case(78.0, THESIS_MU_S), flight_case(mach=3.0)])
def test_zero_width_kernel_is_the_generic_law(case):
    """The slip phases run the specialised kernel at zero width: on random slipping
    states and at exact zero slip (no friction there, as the generic law) it gives the
    generic right-hand side to rounding, and the set-valued t_cr on either code agrees
    to 1e-8 (rounding amplified through the stick-slip; rtol 1e-10)."""
    from obturator.core.dynamics import rhs
    from obturator.core.integrators import stick_slip
    from obturator.core.layout import KERNEL_GENERIC, KERNEL_THESIS, P_KERNEL
    from obturator.solve.setup import integration_setup

    problem, controls = integration_setup(case, SET_VALUED)
    kernel = stick_slip.zero_width(problem.p.copy())
    generic = kernel.copy()
    generic[P_KERNEL] = KERNEL_GENERIC
    assert kernel[P_KERNEL] == KERNEL_THESIS
    rng = np.random.default_rng(7)
    spin = problem.y0[7]
    still = np.array([1.0, 0.0, 0.0, 0.0, 0.0, 0.0, spin, spin])  # omega_r = 0 exactly
    states = []
    for _ in range(200):  # slip of 1e-8 (the kick) to 1e-1 of the spin, any direction
        y = np.concatenate([rng.standard_normal(4), [0.0, 0.0, 0.0, spin]])
        hold_stick(y, spin)  # turning with the socket, then slipping (body axes)
        slip = spin * 10.0 ** rng.uniform(-8, -1) * rng.standard_normal(3)
        y[4:7] += slip
        states.append((y, np.linalg.norm(slip)))
    a, b = np.empty(8), np.empty(8)
    rhs(0.0, still, kernel, a)
    assert a[4] == a[5] == a[6] == 0.0  # no viscous torque and no friction at zero slip
    worst = 0.0
    for y, slip in states:  # the slip is a difference of rates ~ spin: its rounding
        rhs(0.0, y, kernel, a)  # sets the direction's, ~1e-16 spin / |omega_r|
        rhs(0.0, y, generic, b)
        err = np.max(np.abs(a - b)) / np.max(np.abs(b)) / (1e-14 * spin / slip + 1e-12)
        worst = max(worst, err)
    assert worst < 1.0
    run = stick_slip.run_cycles()
    t_kernel = run(problem._replace(p=kernel), controls, math.inf).t_event
    t_generic = run(problem._replace(p=generic), controls, math.inf).t_event
    # two implementations of one law differ by rounding (checked above per evaluation);
    # the adaptive steps and the event search carry that to the order of rtol in t_cr
    assert t_kernel == pytest.approx(t_generic, rel=5e-8)
