"""The set-valued solver's last slips in DOP853 lanes (core/integrators/stick_slip_lanes.py).

References: the set-valued solver on each case alone at rtol 1e-12, atol 1e-14 (the
one-case path, no lanes: its own Radau IIA and DOP853 stretches), and the stick ratio
in closed form, kappa = omega_p^2 |C - A| sin(theta) |cos(theta)| / M
(docs/stick_slip.md section 3, from thesis Eqs. 5a-5c and 61: |G_req| depends on the
nutation alone).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from obturator.core.dynamics import nutation_angle_of_state
from obturator.core.friction_sets import moment_scale
from obturator.core.integrators import Status, stick_slip, stick_slip_lanes, stick_slip_modes
from obturator.core.integrators.lanes import LANES, integrate_lanes
from obturator.core.integrators.switching import HandOff
from obturator.core.layout import P_A, P_C
from obturator.model.cases import rig_case
from obturator.reference import THESIS_MU_S
from obturator.solve import SolverOptions, opening_time, opening_times
from obturator.solve.setup import integration_setup

SET_VALUED = SolverOptions(method="set-valued")
TIGHT = SolverOptions(method="set-valued", rtol=1e-12, atol=1e-14)
#: Rig spins whose last slip is long (the ball stops sticking soon after release).
SPINS = (140.0, 175.0, 200.0, 217.0)


def _setup(spin: float, hand_off: bool):
    problem, controls = integration_setup(rig_case(spin, THESIS_MU_S), SET_VALUED)
    return problem, controls._replace(last_slip_to_lanes=hand_off)


def _slip_speed(y: np.ndarray) -> float:
    return stick_slip_modes.slip(y)[3]


def _unit(p: np.ndarray, h_max: float) -> float:
    """(M / A) h_max [rad/s]: the unit of HAND_OFF_SLIP and SLIP_FLOOR."""
    return moment_scale(p) / p[P_A] * h_max


def _stick_ratio(p: np.ndarray, y: np.ndarray) -> float:
    """kappa in closed form from the nutation (see the module)."""
    theta = nutation_angle_of_state(y, p)
    return (
        y[7] ** 2
        * abs(p[P_C] - p[P_A])
        * math.sin(theta)
        * abs(math.cos(theta))
        / (moment_scale(p))
    )


@pytest.mark.parametrize("spin", SPINS)
def test_hand_off_where_the_ball_no_longer_sticks(spin):
    """Asked to, the mode loop stops in a slip (NONSTIFF) whose stick ratio (closed form)
    and slip speed are past the thresholds, before the opening; not asked, it runs to the
    opening."""
    problem, controls = _setup(spin, hand_off=True)
    out = stick_slip.integrate(problem, controls)
    assert out.status == HandOff.NONSTIFF
    p = stick_slip.at_zero_width(problem).p
    assert _stick_ratio(p, out.y_end) >= stick_slip_modes.HAND_OFF_KAPPA
    assert _slip_speed(out.y_end) >= stick_slip_modes.HAND_OFF_SLIP * _unit(p, controls.h_max)
    alone = stick_slip.integrate(*_setup(spin, hand_off=False))
    assert alone.status == Status.OPENED and out.t_end < alone.t_event


def test_front_door_finishes_in_lanes_as_the_one_case_solver_does():
    """Under the default ``auto`` (these spins set-valued) opening_times hands the last
    slips to the lanes (route "set-valued, last slip in lanes"): fewer right-hand sides
    than the mode loop alone (``slip_lanes=False``), t_cr within 1e-8 of that (a
    different integrator on the same slip, to the same tolerance) and within 3e-7 of the
    one-case solver at rtol 1e-12 (the default's accuracy, 5.7e-7,
    AUTO_OPENING_TIME_ACCURACY); each point alone gives the batch's bits."""
    cases = [rig_case(w, THESIS_MU_S) for w in SPINS]
    t_cr, status, stats = opening_times(cases)
    assert np.all(status == Status.OPENED) and stats["n_set_valued"] == len(SPINS)
    assert stats["routes"] == {"set-valued, last slip in lanes": len(SPINS)}
    np.testing.assert_array_equal(t_cr, [opening_time(c) for c in cases])
    t_alone, _, stats_alone = opening_times(cases, SolverOptions(slip_lanes=False))
    np.testing.assert_allclose(t_cr, t_alone, rtol=1e-8, atol=0.0)
    np.testing.assert_allclose(t_cr, [opening_time(c, TIGHT) for c in cases], rtol=3e-7)
    assert stats["nfev"] < stats_alone["nfev"]


def test_a_slip_that_sticks_again_comes_back_from_the_lanes():
    """A slip handed over in a window that ends in stick (84 rad/s, the window of largest
    slip before the last one): its lane ends where the slip falls below SLIP_FLOOR, above
    zero, and the case goes on in the mode loop, through its stick phases, to within
    1e-8 of the mode loop run alone (and 3e-7 of the one-case solver at rtol 1e-12)."""
    problem, controls = _setup(84.0, hand_off=False)
    zero = stick_slip.at_zero_width(problem)
    rec = stick_slip.run_cycles()(zero, controls._replace(record=True), math.inf)
    r = np.array([_slip_speed(y) for y in rec.y])
    unit = _unit(zero.p, controls.h_max)
    t_last_stick = rec.t[np.flatnonzero(r < 1e-9 * 84.0)[-1]]  # stick rows: omega_r = 0
    before = np.flatnonzero((rec.t < t_last_stick) & (r > 2.0 * stick_slip_modes.SLIP_FLOOR * unit))
    assert before.size  # such windows exist
    k = before[-1]
    handed = rec._replace(status=HandOff.NONSTIFF, t_end=float(rec.t[k]), y_end=rec.y[k].copy())
    floor = np.array([stick_slip_modes.slip_floor(zero.p, controls.h_max)])
    one = np.ones(1)
    st, _, t_end, y_end, *_ = integrate_lanes(
        rec.y[k][None], rec.t[k] * one, zero.p[None], zero.scale[None], controls.t_max * one,
        0.1 * controls.h_max * one, controls.h_max * one, np.full(1, controls.max_steps),
        np.zeros(1, dtype=np.int64), controls.rtol, controls.atol, controls.event_tol, LANES,
        floor,
    )  # fmt: skip
    assert st[0] == HandOff.STIFF and 0.0 < _slip_speed(y_end[0]) < floor[0]
    assert t_end[0] < t_last_stick
    (done,) = stick_slip_lanes.finish_in_lanes(
        [problem], [controls._replace(last_slip_to_lanes=True)], [handed], LANES
    )
    assert done.status == Status.OPENED
    assert done.t_event == pytest.approx(rec.t_event, rel=1e-8)  # the mode loop alone
    assert done.t_event == pytest.approx(opening_time(rig_case(84.0, THESIS_MU_S), TIGHT), rel=3e-7)


def test_zero_floors_leave_the_lanes_as_they_were():
    """With no floor (the regularised path) no lane ends for its slip speed: the DOP853
    lanes give the scalar DOP853's t_cr (tests/core/test_lanes.py checks it bit for bit)
    and none ends STIFF on a regularised rig point that never nears stick."""
    problem, controls = integration_setup(rig_case(600.0, THESIS_MU_S), SolverOptions())
    one = np.ones(1)
    st, t_ev, *_ = integrate_lanes(
        problem.y0[None], 0.0 * one, problem.p[None], problem.scale[None],
        controls.t_max * one, controls.h0 * one, controls.h_max * one,
        np.full(1, controls.max_steps), np.zeros(1, dtype=np.int64), controls.rtol,
        controls.atol, controls.event_tol, LANES, np.zeros(1),
    )  # fmt: skip
    assert st[0] == Status.OPENED
    regularised = SolverOptions(method="regularised")
    assert t_ev[0] == opening_time(rig_case(600.0, THESIS_MU_S), regularised)


def test_cases_of_different_tolerances_finish_at_their_own():
    """finish_in_lanes runs each set of tolerances in lanes of its own: 200 rad/s at
    rtol 1e-8 and 1e-10, each within 1e-8 of the mode loop alone at its rtol."""
    problems, controls, runs, alone = [], [], [], []
    for rtol in (1e-8, 1e-10):
        problem, ctl = integration_setup(
            rig_case(200.0, THESIS_MU_S), replace(SET_VALUED, rtol=rtol)
        )
        problems.append(problem)
        controls.append(ctl._replace(last_slip_to_lanes=True))
        runs.append(stick_slip.integrate(problem, controls[-1]))
        alone.append(stick_slip.integrate(problem, ctl).t_event)
    assert all(run.status == HandOff.NONSTIFF for run in runs)
    done = stick_slip_lanes.finish_in_lanes(problems, controls, runs, LANES)
    assert [d.status for d in done] == [Status.OPENED, Status.OPENED]
    np.testing.assert_allclose([d.t_event for d in done], alone, rtol=1e-8)
    assert done[1].nfev > done[0].nfev  # the tighter one took more work
