"""Explicit DOP853 integrator and the "auto" method (DOP853, Radau IIA in flight when stiff).

Errors are compared with the requested tolerance or with Radau IIA (never with wall time).
"""

import math

import numpy as np
import pytest
from conftest import THESIS_CASES, raw_solve

from obturator import Case, SolverOptions, TorqueModel, rig_case, simulate
from obturator.core.dynamics import nutation_angle_of_state
from obturator.core.integrators import AUTO_RADAU_TOL_FACTOR
from obturator.model.cases import table1_ball
from obturator.solve import opening_time
from obturator.status import Status

BALL = table1_ball()
A, C = BALL.transverse_inertia, BALL.axial_inertia
LAM = C / A - 1.0
THETA0 = math.radians(87.25)
MU = 0.5473


def raw(case: Case, options: SolverOptions, **kw):
    """Call the compiled DOP853 integrator directly (the raw solution solve.py reads)."""
    return raw_solve(case, options, method="dop853", **kw)


def test_auto_is_the_default():
    assert SolverOptions().method == "auto"


@pytest.mark.parametrize("rtol", [1e-5, 1e-7, 1e-9])
def test_torque_free_body_rates_match_closed_form(rtol):
    # Closed form of Eqs. (5) with G = 0: w3 const, (w1, w2) rotate at lambda*w3.
    spin = 300.0
    case = Case(BALL, TorqueModel(), spin, THETA0, t_max=0.1)
    t = np.linspace(0.0, 0.1, 201)
    out, _ = raw(case, SolverOptions(rtol=rtol, atol=rtol * 1e-2), terminal=False, t_eval=t)
    status, ys, njev = out.status, out.y, out.njev
    assert status == Status.T_MAX and njev == 0
    w3 = spin * math.cos(THETA0)
    wt = spin * math.sin(THETA0)
    om = LAM * w3
    expected = np.column_stack([-wt * np.sin(om * t), wt * np.cos(om * t), np.full_like(t, w3)])
    err = np.max(np.abs(ys[:, 4:7] - expected)) / spin
    # global error scales with the tolerance (t_eval values are re-stepped, not interpolated)
    assert err < 100 * rtol


CASES = THESIS_CASES


@pytest.mark.parametrize("name", list(CASES))
def test_auto_agrees_with_tight_radau(name):
    """t_cr of "auto" at the default tolerances equals tight-tolerance Radau's to 1e-6.

    Both at width 1e-6 omega_p. (Radau at the default tolerances is ~4e-6 off at 200
    rad/s, see tests/test_radau.py; the hand-over keeps DOP853's accuracy through the
    release layer.)
    """
    case = CASES[name]
    tight = SolverOptions(method="radau", rtol=1e-11, atol=1e-13, friction_width=1e-6)
    t_ref = opening_time(case, tight)
    t_auto = opening_time(case, SolverOptions(friction_width=1e-6))
    assert math.isfinite(t_ref)
    assert t_auto == pytest.approx(t_ref, rel=1e-6)


@pytest.mark.parametrize("name", [n for n in CASES if n != "rig200"])
def test_dop853_runs_without_fallback_and_agrees_with_tight_radau(name):
    """Slipping cases: DOP853 itself opens (no stiffness report), t_cr to 1e-6 of tight Radau."""
    case = CASES[name]
    tight = SolverOptions(method="radau", rtol=1e-11, atol=1e-13)
    out, _ = raw(case, SolverOptions(rtol=1e-10, atol=1e-12))
    assert out.status == Status.OPENED and out.njev == 0
    assert out.t_event == pytest.approx(opening_time(case, tight), rel=1e-6)
    res = simulate(case)  # the default path takes DOP853 alone: no Jacobians
    assert res.status == Status.OPENED and res.njev == 0


@pytest.mark.parametrize(
    "case",
    [rig_case(78, MU, t_max=1.0), rig_case(150, MU)],
    ids=["rig78_near_stick", "rig150_near_stick"],
)
def test_auto_hands_over_to_radau_in_flight(case):
    """A stiff DOP853 run continues with Radau from DOP853's last accepted state.

    Checks: DOP853 reports STIFF; the auto run's rows are DOP853's rows followed by
    Radau's (time increasing, the hand-over row once); counters add up; the hand-over
    row is DOP853's end state (Radau at :data:`AUTO_RADAU_TOL_FACTOR` of the tolerances);
    t_cr agrees with tight-tolerance Radau from t = 0.
    """
    dop, _ = raw(case, SolverOptions(), record=True)  # as simulate() records
    assert dop.status == Status.STIFF and 0.0 < dop.t_end < case.t_max
    auto, _ = raw_solve(case, SolverOptions(), method="auto", record=True)
    assert auto.njev > 0  # Radau took over
    n_dop = dop.t.shape[0]
    np.testing.assert_array_equal(auto.t[:n_dop], dop.t)
    assert auto.t[n_dop - 1] == dop.t_end
    np.testing.assert_array_equal(auto.y[n_dop - 1], dop.y_end)
    assert np.all(np.diff(auto.t) > 0.0)
    o, f = SolverOptions(), AUTO_RADAU_TOL_FACTOR  # auto's Radau runs at a third of the tolerances
    rest, _ = raw_solve(
        case, o, method="radau", record=True, y0=dop.y_end, t0=dop.t_end,
        rtol=o.rtol * f, atol=o.atol * f,
    )  # fmt: skip
    assert auto.nfev == dop.nfev + rest.nfev
    assert auto.n_steps == dop.n_steps + rest.n_steps
    np.testing.assert_array_equal(auto.t[n_dop:], rest.t[1:])
    tight = SolverOptions(method="radau", rtol=1e-11, atol=1e-13)
    ref = opening_time(case, tight)
    assert simulate(case).n_steps == auto.n_steps
    if math.isnan(ref):
        assert math.isnan(auto.t_event)
    else:
        assert auto.t_event == pytest.approx(ref, rel=1e-6)


def test_stiffness_detected_early():
    """Hairer's h*lambda test stops DOP853 long before the step budget would.

    At 150 rad/s the run sticks; the budget guard alone allowed STEP_ALLOWANCE
    (1000) steps beyond the per-period budget, the h*lambda test needs STIFF_STEPS.
    """
    from obturator.core.integrators.dop853 import STEP_ALLOWANCE, STEPS_PER_PERIOD

    case = rig_case(150, MU)
    dop, _ = raw(case, SolverOptions())
    assert dop.status == Status.STIFF
    budget = STEPS_PER_PERIOD * 150 / (2 * math.pi) * dop.t_end + STEP_ALLOWANCE
    assert dop.n_steps + dop.n_rejected < 0.5 * budget


def test_event_state_and_bracket():
    """theta(y_event) = theta_cr, and theta crosses theta_cr within 1e-9 s of t_event."""
    case = rig_case(300, MU)
    opt = SolverOptions(rtol=1e-10, atol=1e-12)
    out, p = raw(case, opt)
    status, t_ev, y_ev = out.status, out.t_event, out.y_event
    assert status == Status.OPENED
    assert out.t_end == t_ev
    assert nutation_angle_of_state(y_ev, p) == pytest.approx(case.opening_angle, abs=1e-12)
    before, _ = raw(case, opt, t_max=t_ev - 1e-9, terminal=False)
    after, _ = raw(case, opt, t_max=t_ev + 1e-9, terminal=False)
    assert nutation_angle_of_state(before.y_end, p) > case.opening_angle
    assert nutation_angle_of_state(after.y_end, p) < case.opening_angle
    assert before.status == Status.T_MAX and math.isfinite(after.t_event)


def test_record_rows_and_non_terminal_run():
    case = rig_case(300, MU, t_max=0.35)
    res = simulate(case)
    assert res.t.shape[0] == res.n_steps + 2  # start, accepted steps, event
    assert np.all(np.diff(res.t) > 0) and res.t[-1] == res.opening_time
    cont = simulate(case, terminal=False)
    assert cont.status == 0 and cont.t[-1] == pytest.approx(0.35)
    assert cont.opening_time == pytest.approx(res.opening_time, rel=1e-12)
