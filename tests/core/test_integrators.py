"""One conformance test of the integrator contract, parametrised over the method registry.

Each compiled integrator (:data:`obturator.core.integrators.CORE_METHODS`: every method
:func:`~obturator.core.integrators.integrate` runs, "auto", the set-valued and the
Moreau-Jean ones included) must keep :mod:`obturator.core.integrators.contract`: the
same inputs and labelled outputs, the same event, recording and t_eval semantics, the
shared status enumeration, and an accuracy in line with its tolerance against a closed
form, as far as its declared :class:`Traits` say it applies (a method added to the
registry fails :func:`test_every_registered_method_declares_its_traits` until it does).
"""

import math
from typing import NamedTuple

import numpy as np
import pytest
from conftest import raw_solve

from obturator import Case, SolverOptions, TorqueModel, initial_state, rig_case
from obturator.core.dynamics import nutation_angle_of_state
from obturator.core.integrators import CORE_METHODS, RawSolution
from obturator.errors import InputError
from obturator.model.cases import table1_ball
from obturator.solve.dispatch import core_method
from obturator.status import Status
from obturator.vocab import METHODS as USER_METHODS


class Traits(NamedTuple):
    """What of the contract a method keeps (the module docstrings say why)."""

    #: Integrates any torque model (the regularised law); False: the set-valued law
    #: only, which refuses a torque-free body (no friction law) with InputError.
    any_torque: bool
    #: Records accepted steps and gives output on t_eval (Moreau-Jean: t_cr only).
    history: bool
    #: Recorded rows are the start, one per accepted step and the event (the set-valued
    #: solver adds the stick phases' ends and zero-slip transitions).
    row_per_step: bool
    #: The event is located (its state on theta_cr to rounding, a non-terminal run goes
    #: on); False: the first fixed step past theta_cr, its time interpolated (first order).
    located: bool
    #: Evaluates a Jacobian on the 300 rad/s opening (None: depends on its phases).
    jacobian: bool | None
    #: Stops after max_steps accepted steps with STEP_LIMIT (auto: each of its stretches).
    step_limit: bool


TRAITS: dict[str, Traits] = {
    "auto": Traits(True, True, True, True, False, False),
    "dop853": Traits(True, True, True, True, False, True),
    "radau": Traits(True, True, True, True, True, True),
    "rosenbrock": Traits(True, True, True, True, True, True),
    "set-valued": Traits(False, True, False, True, None, True),
    "moreau-jean": Traits(False, False, False, False, False, True),
}
METHODS = list(CORE_METHODS)
BALL = table1_ball()
A, C = BALL.transverse_inertia, BALL.axial_inertia
THETA0 = math.radians(87.25)


def test_every_registered_method_declares_its_traits():
    """The registry, and nothing else, is what the tests below iterate; every method a
    user can name runs one of its entries."""
    assert set(TRAITS) == set(CORE_METHODS)
    assert len(CORE_METHODS) == len(set(CORE_METHODS))
    assert {core_method(m) for m in USER_METHODS if m != "auto"} <= set(CORE_METHODS)


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
    if not TRAITS[method].any_torque:
        with pytest.raises(InputError):
            raw_solve(case, SolverOptions(rtol=rtol, atol=atol), method=method, y0=y0)
        return
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
    """Labelled outputs, recorded rows, event state and bracket, the same for every
    method as far as its traits go (Moreau-Jean: t_cr and the state of the step past
    theta_cr only)."""
    traits = TRAITS[method]
    case = rig_case(300, 0.5473)
    opt = SolverOptions(rtol=1e-10, atol=1e-12, friction_width=1e-6)
    if not traits.history:
        with pytest.raises(InputError):
            raw_solve(case, opt, method=method, record=True)
    out, p = raw_solve(case, opt, method=method, record=traits.history)
    # the status is an integer code: an outcome (Status) or, mid-run only, a HandOff signal
    assert isinstance(out, RawSolution) and isinstance(out.status, int)
    assert Status(out.status) == Status.OPENED
    assert out.nfev > 0 and out.n_steps > 0 and out.n_rejected >= 0
    if traits.jacobian is not None:
        assert (out.njev > 0) == traits.jacobian
    if traits.history:
        assert out.t.shape[0] == out.y.shape[0]
        assert out.t[0] == 0.0 and out.t[-1] == out.t_event == out.t_end
        np.testing.assert_array_equal(out.y[-1], out.y_event)
        if traits.row_per_step:  # start, accepted steps, event
            assert out.t.shape[0] == out.n_steps + 2 and np.all(np.diff(out.t) > 0)
        else:
            assert 2 <= out.t.shape[0] and np.all(np.diff(out.t) >= 0)
    else:
        assert out.t.shape[0] == out.y.shape[0] == 0
    if not traits.located:  # the first step at or past theta_cr, t_cr inside it
        assert out.t_event <= out.t_end
        assert nutation_angle_of_state(out.y_event, p) <= case.opening_angle
        return
    np.testing.assert_array_equal(out.y_end, out.y_event)
    before, _ = raw_solve(case, opt, method=method, t_max=out.t_event - 1e-9, terminal=False)
    assert before.status == Status.T_MAX
    assert nutation_angle_of_state(before.y_end, p) > case.opening_angle
    # located to a time bracket of event_tol [s]: theta within |dtheta/dt| event_tol of
    # theta_cr (the rate from the state 1e-9 s before), plus rounding
    rate = (nutation_angle_of_state(before.y_end, p) - case.opening_angle) / 1e-9
    miss = abs(nutation_angle_of_state(out.y_event, p) - case.opening_angle)
    assert miss <= 1.1 * rate * opt.event_tol + 1e-15
    # not terminal: the same event, and on to t_max
    cont, _ = raw_solve(case, opt, method=method, t_max=out.t_event + 0.01, terminal=False)
    assert cont.status == Status.T_MAX and cont.t_end == pytest.approx(out.t_event + 0.01)
    assert cont.t_event == pytest.approx(out.t_event, rel=1e-12)


@pytest.mark.parametrize("method", METHODS)
def test_t_eval_stops_at_the_event(method):
    case = rig_case(300, 0.5473)
    t = np.linspace(0.0, 0.5, 51)
    if not TRAITS[method].history:
        with pytest.raises(InputError, match="t_eval"):
            raw_solve(case, SolverOptions(), method=method, t_eval=t)
        return
    out, _ = raw_solve(case, SolverOptions(friction_width=1e-6), method=method, t_eval=t)
    assert out.status == Status.OPENED
    assert np.all(out.t <= out.t_event) and len(out.t) == np.sum(t <= out.t_event)


@pytest.mark.parametrize("method", [m for m in METHODS if TRAITS[m].step_limit])
def test_step_limit(method):
    out, _ = raw_solve(rig_case(300, 0.5473), SolverOptions(), method=method, max_steps=10)
    assert out.status == Status.STEP_LIMIT and out.n_steps == 10
    assert math.isnan(out.t_event) and np.all(np.isnan(out.y_event))
