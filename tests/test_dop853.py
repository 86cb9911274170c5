"""Explicit DOP853 integrator and the "auto" method (DOP853, Radau IIA fallback when stiff).

Errors are compared with the requested tolerance or with Radau IIA (never with wall time).
"""

import math

import numpy as np
import pytest

from obturator import Case, SolverOptions, TorqueModel, _dop853, initial_state, rig_case, simulate
from obturator.cases import flight_case, table1_ball
from obturator.dynamics import nutation_angle_of_state
from obturator.solve import _scale, opening_time, pack_parameters

BALL = table1_ball()
A, C = BALL.transverse_inertia, BALL.axial_inertia
LAM = C / A - 1.0
THETA0 = math.radians(87.25)
MU = 0.5473


def raw(
    case: Case, options: SolverOptions, *, t_max=None, terminal=True, t_eval=None, record=False
):
    """Call the compiled DOP853 integrator directly (the tuple solve.py unpacks)."""
    y0 = initial_state(case.theta0, case.spin_rate, formulation=options.formulation)
    p = pack_parameters(case, options, y0)
    period = 2 * math.pi / case.spin_rate
    te = np.empty(0) if t_eval is None else np.asarray(t_eval, float)
    out = _dop853.integrate(
        y0,
        p,
        float(case.t_max if t_max is None else t_max),
        options.rtol,
        options.atol,
        _scale(case, options.formulation),
        1e-4 * period,
        0.1 * period,
        int(options.max_steps),
        te,
        record,
        terminal,
        options.event_tol,
    )
    return out, p


def test_auto_is_the_default():
    assert SolverOptions().method == "auto"


@pytest.mark.parametrize("rtol", [1e-5, 1e-7, 1e-9])
def test_torque_free_body_rates_match_closed_form(rtol):
    # Closed form of Eqs. (5) with G = 0: w3 const, (w1, w2) rotate at lambda*w3.
    spin = 300.0
    case = Case(BALL, TorqueModel(), spin, THETA0, t_max=0.1)
    t = np.linspace(0.0, 0.1, 201)
    out, _ = raw(case, SolverOptions(rtol=rtol, atol=rtol * 1e-2), terminal=False, t_eval=t)
    status, ys, njev = out[0], out[4], out[6]
    assert status == _dop853.STATUS_T_MAX and njev == 0
    w3 = spin * math.cos(THETA0)
    wt = spin * math.sin(THETA0)
    om = LAM * w3
    expected = np.column_stack([-wt * np.sin(om * t), wt * np.cos(om * t), np.full_like(t, w3)])
    err = np.max(np.abs(ys[:, 4:7] - expected)) / spin
    # global error scales with the tolerance (t_eval values are re-stepped, not interpolated)
    assert err < 100 * rtol


CASES = {
    "rig200": rig_case(200, MU),
    "rig300": rig_case(300, MU),
    "rig450": rig_case(450, MU),
    "rig700": rig_case(700, MU),
    "flight": flight_case(),
    "flight_coulomb": flight_case(torque_model="coulomb"),
    "rig450_coulomb": rig_case(450, MU, torque_model="coulomb"),
}


@pytest.mark.parametrize("name", list(CASES))
def test_auto_agrees_with_radau(name):
    """t_cr of "auto" equals Radau's at the default tolerances to 1e-6 relative.

    Both at width 1e-6 omega_p: at the default 1e-7 Radau's default-tolerance error is
    ~4e-6 (see tests/test_radau.py), DOP853's ~1e-9.
    """
    case = CASES[name]
    t_rad = opening_time(case, SolverOptions(method="radau", friction_width=1e-6))
    t_auto = opening_time(case, SolverOptions(friction_width=1e-6))
    assert math.isfinite(t_rad)
    assert t_auto == pytest.approx(t_rad, rel=1e-6)


@pytest.mark.parametrize("name", [n for n in CASES if n != "rig200"])
def test_dop853_runs_without_fallback_and_agrees_with_tight_radau(name):
    """Slipping cases: DOP853 itself opens (no stiffness report), t_cr to 1e-6 of tight Radau."""
    case = CASES[name]
    tight = SolverOptions(method="radau", rtol=1e-11, atol=1e-13)
    out, _ = raw(case, SolverOptions(rtol=1e-10, atol=1e-12))
    assert out[0] == _dop853.STATUS_OPENED and out[6] == 0
    assert out[1] == pytest.approx(opening_time(case, tight), rel=1e-6)
    res = simulate(case)  # the default path takes DOP853 alone: no Jacobians
    assert res.status == _dop853.STATUS_OPENED and res.njev == 0


@pytest.mark.parametrize(
    "case",
    [rig_case(78, MU, t_max=1.0), rig_case(150, MU)],
    ids=["rig78_near_stick", "rig150_near_stick"],
)
def test_auto_falls_back_to_radau_on_sticking(case):
    out, _ = raw(case, SolverOptions(), record=True)  # as simulate() records
    assert out[0] == _dop853.STATUS_STIFF
    auto = simulate(case)
    rad = simulate(case, SolverOptions(method="radau"))
    assert auto.status == rad.status
    assert auto.njev == rad.njev > 0 and auto.n_steps == rad.n_steps
    assert auto.nfev == rad.nfev + out[5]
    np.testing.assert_array_equal(auto.t, rad.t)
    assert (math.isnan(auto.opening_time) and math.isnan(rad.opening_time)) or (
        auto.opening_time == rad.opening_time
    )


def test_event_state_and_bracket():
    """theta(y_event) = theta_cr, and theta crosses theta_cr within 1e-9 s of t_event."""
    case = rig_case(300, MU)
    opt = SolverOptions(rtol=1e-10, atol=1e-12)
    out, p = raw(case, opt)
    status, t_ev, y_ev = out[0], out[1], out[2]
    assert status == _dop853.STATUS_OPENED
    assert out[9] == t_ev
    assert nutation_angle_of_state(y_ev, p) == pytest.approx(case.opening_angle, abs=1e-12)
    before, _ = raw(case, opt, t_max=t_ev - 1e-9, terminal=False)
    after, _ = raw(case, opt, t_max=t_ev + 1e-9, terminal=False)
    assert nutation_angle_of_state(before[10], p) > case.opening_angle
    assert nutation_angle_of_state(after[10], p) < case.opening_angle
    assert before[0] == _dop853.STATUS_T_MAX and math.isfinite(after[1])


def test_record_rows_and_non_terminal_run():
    case = rig_case(300, MU, t_max=0.35)
    res = simulate(case)
    assert res.t.shape[0] == res.n_steps + 2  # start, accepted steps, event
    assert np.all(np.diff(res.t) > 0) and res.t[-1] == res.opening_time
    cont = simulate(case, terminal=False)
    assert cont.status == 0 and cont.t[-1] == pytest.approx(0.35)
    assert cont.opening_time == pytest.approx(res.opening_time, rel=1e-12)
