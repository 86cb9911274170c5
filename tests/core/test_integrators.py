"""One conformance test of the integrator contract, parametrised over every method.

Each compiled integrator (and "auto") must keep :mod:`obturator.core.integrators.contract`:
the same inputs and labelled outputs, the same event, recording and t_eval semantics, the
shared status enumeration, and an accuracy in line with its tolerance against a closed form.
"""

import math

import numpy as np
import pytest
from conftest import raw_solve

from obturator import Case, SolverOptions, TorqueModel, initial_state, rig_case
from obturator.core.dynamics import nutation_angle_of_state
from obturator.core.integrators import RawSolution
from obturator.model.cases import table1_ball
from obturator.status import Status

METHODS = ["dop853", "radau", "rosenbrock", "auto"]
BALL = table1_ball()
A, C = BALL.transverse_inertia, BALL.axial_inertia
THETA0 = math.radians(87.25)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("rtol", [1e-6, 1e-9])
def test_closed_form_torque_free_body(method, rtol):
    """Torque-free axisymmetric body (thesis Eqs. 5 with G = 0): w3 constant, (w1, w2)
    turning at (C - A)/A w3, over about 8 turns.

    Error normalised as in scipy's integrator tests, |y - y_exact| / (atol scale + rtol
    |y_exact|), below 5. The Rosenbrock pair is second order and controls the error per
    step, so its global error grows with the number of steps: below 5 per step.
    """
    spin = 500.0
    case = Case(BALL, TorqueModel(), spin, THETA0, t_max=0.05)
    y0 = initial_state(THETA0, spin, theta_dot=40.0, phi_dot=300.0)  # all three rates move
    t = np.linspace(0.0, 0.05, 101)
    atol = rtol * 1e-2
    out, _ = raw_solve(
        case, SolverOptions(rtol=rtol, atol=atol), method=method, y0=y0, t_eval=t, terminal=False
    )
    assert out.status == Status.T_MAX
    np.testing.assert_array_equal(out.t, t)
    lam = (C - A) / A * y0[6]
    assert abs(lam) * 0.05 > 5.0
    z = (y0[4] + 1j * y0[5]) * np.exp(1j * lam * t)
    exact = np.column_stack([z.real, z.imag, np.full_like(t, y0[6])])
    err = np.abs(out.y[:, 4:7] - exact) / (atol * spin + rtol * np.abs(exact))
    assert np.max(err) < 5.0 * (out.n_steps if method == "rosenbrock" else 1)


@pytest.mark.parametrize("method", METHODS)
def test_contract_on_an_opening(method):
    """Labelled outputs, recorded rows, event state and bracket, the same for every method."""
    case = rig_case(300, 0.5473)
    opt = SolverOptions(rtol=1e-10, atol=1e-12, friction_width=1e-6)
    out, p = raw_solve(case, opt, method=method, record=True)
    assert isinstance(out, RawSolution) and isinstance(out.status, Status)
    assert out.status == Status.OPENED
    assert out.t.shape[0] == out.y.shape[0] == out.n_steps + 2  # start, accepted steps, event
    assert out.t[0] == 0.0 and np.all(np.diff(out.t) > 0)
    assert out.t[-1] == out.t_event == out.t_end
    np.testing.assert_array_equal(out.y[-1], out.y_event)
    np.testing.assert_array_equal(out.y_end, out.y_event)
    assert nutation_angle_of_state(out.y_event, p) == pytest.approx(case.opening_angle, abs=1e-12)
    assert out.nfev > out.n_steps and out.n_rejected >= 0
    assert (out.njev == 0) == (method in ("dop853", "auto"))
    before, _ = raw_solve(case, opt, method=method, t_max=out.t_event - 1e-9, terminal=False)
    assert before.status == Status.T_MAX
    assert nutation_angle_of_state(before.y_end, p) > case.opening_angle
    # not terminal: the same event, and on to t_max
    cont, _ = raw_solve(case, opt, method=method, t_max=out.t_event + 0.01, terminal=False)
    assert cont.status == Status.T_MAX and cont.t_end == pytest.approx(out.t_event + 0.01)
    assert cont.t_event == pytest.approx(out.t_event, rel=1e-12)


@pytest.mark.parametrize("method", METHODS)
def test_t_eval_stops_at_the_event(method):
    case = rig_case(300, 0.5473)
    t = np.linspace(0.0, 0.5, 51)
    out, _ = raw_solve(case, SolverOptions(friction_width=1e-6), method=method, t_eval=t)
    assert out.status == Status.OPENED
    assert np.all(out.t <= out.t_event) and len(out.t) == np.sum(t <= out.t_event)


@pytest.mark.parametrize("method", ["dop853", "radau", "rosenbrock"])
def test_step_limit(method):
    out, _ = raw_solve(rig_case(300, 0.5473), SolverOptions(), method=method, max_steps=10)
    assert out.status == Status.STEP_LIMIT and out.n_steps == 10
    assert math.isnan(out.t_event) and np.all(np.isnan(out.y_event))
