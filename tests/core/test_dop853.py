"""Explicit DOP853 integrator and the "regularised" method (DOP853, Radau IIA in flight when
stiff; the core's "auto"; solve's default "auto" gives low spins to the set-valued solver).

Errors are compared with the requested tolerance or with Radau IIA (never with wall time).
"""

import math

import numpy as np
import pytest
from conftest import THESIS_CASES, raw_solve

from obturator import Case, SolverOptions, TorqueModel, rig_case, simulate
from obturator.core.dynamics import nutation_angle_of_state, slip_and_spin
from obturator.core.integrators import AUTO_HAND_BACKS, AUTO_RADAU_TOL_FACTOR, HandOff
from obturator.core.integrators.switching import SLIDING_WIDTHS
from obturator.core.layout import P_WIDTH
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
    rad/s, see tests/core/test_radau.py; the hand-over keeps DOP853's accuracy through the
    release layer.)
    """
    case = CASES[name]
    tight = SolverOptions(method="radau", rtol=1e-11, atol=1e-13, friction_width=1e-6)
    t_ref = opening_time(case, tight)
    t_auto = opening_time(case, SolverOptions(friction_width=1e-6, method="regularised"))
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
def test_auto_switches_methods_in_flight(case):
    """``auto`` is DOP853, Radau IIA from DOP853's last accepted state where it is stiff,
    DOP853 again from Radau's where sliding has resumed, and so on.

    The chain is rebuilt here stretch by stretch from the two method modules: the auto
    run's rows are the stretches' rows joined (each switch row once, time increasing),
    its counters their sums, Radau IIA at :data:`AUTO_RADAU_TOL_FACTOR` of the
    tolerances. At 150 rad/s the stick-slip phase ends before the bore opens: Radau
    IIA hands back once, at a slip speed above :data:`SLIDING_WIDTHS` regularisation
    widths, and the sliding that follows never sticks again (one DOP853 stretch to the
    end). t_cr agrees with Radau IIA at rtol 1e-11 from t = 0 (no switching).
    """
    o, f = SolverOptions(), AUTO_RADAU_TOL_FACTOR
    auto, p = raw_solve(case, o, method="auto", record=True)  # as simulate() records
    stretch, _ = raw_solve(case, o, method="dop853", record=True)
    assert stretch.status == HandOff.STIFF and 0.0 < stretch.t_end < case.t_max
    stretches = [stretch]
    while stretch.status in (HandOff.STIFF, HandOff.NONSTIFF):
        stiff = stretch.status == HandOff.STIFF
        if not stiff:
            slip, _ = slip_and_spin(stretch.y_end, p)
            assert slip >= SLIDING_WIDTHS * p[P_WIDTH]
        hand_backs = sum(s.status == HandOff.NONSTIFF for s in stretches)
        stretch, _ = raw_solve(
            case, o, method="radau" if stiff else "dop853", record=True, y0=stretch.y_end,
            t0=stretch.t_end, max_steps=o.max_steps - sum(s.n_steps for s in stretches),
            rtol=o.rtol * f if stiff else None, atol=o.atol * f if stiff else None,
            hand_back=stiff and hand_backs < AUTO_HAND_BACKS,
        )  # fmt: skip
        stretches.append(stretch)
    assert auto.status == stretch.status and auto.njev > 0
    for name in ("nfev", "njev", "n_steps", "n_rejected"):
        assert getattr(auto, name) == sum(getattr(s, name) for s in stretches)
    np.testing.assert_array_equal(
        auto.t, np.concatenate([stretches[0].t] + [s.t[1:] for s in stretches[1:]])
    )
    assert np.all(np.diff(auto.t) > 0.0)
    if case.spin_rate == 150:
        assert [s.status for s in stretches] == [
            HandOff.STIFF, HandOff.NONSTIFF, Status.OPENED
        ]  # fmt: skip
    tight = SolverOptions(method="radau", rtol=1e-11, atol=1e-13)
    ref = opening_time(case, tight)
    assert simulate(case, SolverOptions(method="regularised")).n_steps == auto.n_steps
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
    assert dop.status == HandOff.STIFF
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
