"""Method ``auto``: the set-valued solver at low stick ratio where it takes the case, else
the regularised law; the same choice one by one and in lanes (obturator.solve.dispatch)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from obturator.cli import main
from obturator.core.integrators import auto_radau_tolerances
from obturator.model.cases import flight_case, rig_case
from obturator.model.torques import SlipSpeedLaw
from obturator.runs.digest import study_digest
from obturator.solve import (
    SolverOptions,
    convergence_check,
    dispatch,
    opening_time,
    opening_times,
    pack_parameters,
    simulate,
)
from obturator.solve.dispatch import method_of, stick_ratio

MU_S = 0.5473
AUTO = SolverOptions()
#: Spin [rad/s] at which kappa = 0.6 on the rig at MU_S: kappa = omega_p^2 |C - A|
#: cos(theta_0) sin(theta_0) / (mu_s W R_s) grows as omega_p^2 (0.0768 at 78 rad/s).
EDGE = 78.0 * math.sqrt(0.6 / 0.07677845392030806)


def _kappa(case) -> float:
    y0 = case.initial_state("quaternion")
    return stick_ratio(pack_parameters(case, AUTO, y0), y0)


def test_stick_ratio_is_the_closed_form_at_release():
    """kappa at release on the rig: omega_p^2 |C - A| cos(theta_0) sin(theta_0) / (mu_s W R_s)
    (docs/stick_slip.md section 3), independent of how the state is packed."""
    case = rig_case(123.0, 0.4)
    ball, fr = case.ball, case.torque.friction
    closed = (
        123.0**2
        * abs(ball.axial_inertia - ball.transverse_inertia)
        * abs(math.cos(case.theta0))
        * math.sin(case.theta0)
        / (fr.mu_s * fr.weight * fr.ball_radius)
    )
    assert _kappa(case) == pytest.approx(closed, rel=1e-12)


@pytest.mark.parametrize(
    ("case", "method"),
    [
        (rig_case(40.0, MU_S), "set-valued"),
        (rig_case(EDGE * 0.999, MU_S), "set-valued"),
        (rig_case(EDGE * 1.001, MU_S), "regularised"),
        (rig_case(1000.0, MU_S), "regularised"),
        # the threshold is on kappa: a larger mu_s holds the ball at higher spins
        (rig_case(EDGE * 1.1, 0.8), "set-valued"),
        (rig_case(100.0, MU_S, spin_mode="free"), "set-valued"),
        (flight_case(), "regularised"),  # kappa 4.4 (Mach 3)
        (flight_case(6000.0), "set-valued"),  # kappa 1.1: still sticks and slips
        (rig_case(100.0, MU_S, torque_model="coulomb"), "set-valued"),
        (rig_case(200.0, MU_S, torque_model="coulomb"), "regularised"),
        # refused by the set-valued solver: stay regularised at any spin
        (rig_case(78.0, MU_S, speed_law=SlipSpeedLaw("weakening", 0.5, 0.1)), "regularised"),
        (rig_case(78.0, MU_S, spin_mode="thesis-energy"), "regularised"),
        (rig_case(78.0, MU_S, torque_model="coulomb", patch_radius=0.0), "regularised"),
    ],
)
def test_auto_chooses_by_stick_ratio_and_law(case, method):
    assert method_of(case, AUTO) == method


def test_other_methods_and_the_euler_form_are_not_changed():
    low = rig_case(60.0, MU_S)
    for name in ("regularised", "radau", "rosenbrock", "set-valued"):
        assert method_of(low, SolverOptions(method=name)) == name
    assert method_of(low, SolverOptions(formulation="euler")) == "regularised"


def test_batched_equals_one_by_one_across_the_threshold():
    """opening_times (set-valued points one by one, the rest in lanes) gives every point
    the one-trajectory path's t_cr to the bit, on both sides of the threshold, for both
    laws, and for a slip-speed law (regularised at any spin)."""
    cases = [
        rig_case(60.0, MU_S),
        rig_case(EDGE * 0.99, MU_S),
        rig_case(EDGE * 1.01, MU_S),
        rig_case(400.0, MU_S),
        rig_case(140.0, MU_S, torque_model="coulomb"),
        rig_case(160.0, MU_S, torque_model="coulomb"),
        rig_case(150.0, MU_S, speed_law=SlipSpeedLaw("strengthening", 0.5, 0.1)),
        flight_case(mach=2.0),
    ]
    t_cr, status, stats = opening_times(cases, AUTO)
    one = np.array([opening_time(c, AUTO) for c in cases])
    np.testing.assert_array_equal(t_cr, one)
    assert np.all(np.isfinite(one))
    chosen = [method_of(c, AUTO) for c in cases]
    assert chosen.count("set-valued") == stats["n_set_valued"] == 3
    # the chosen integrator by name gives the same t_cr; a set-valued case at the third
    # of the tolerances auto runs it with (dispatched_controls)
    rtol, atol = auto_radau_tolerances(AUTO.rtol, AUTO.atol)
    for c, m, t in zip(cases, chosen, one, strict=True):
        by_name = replace(AUTO, method=m)  # type: ignore[arg-type]
        if m == "set-valued":
            by_name = replace(by_name, rtol=rtol, atol=atol)
        assert t == opening_time(c, by_name)


def test_default_at_40_rad_s_is_the_width_free_limit():
    """40 rad/s on the rig (t_cr 42.7 s, ~270 revolutions of stick-slip): the default is
    within 1e-6 of the regularised family limit, 42.73197122 s, the mean of the tanh and
    linear families at width 1e-10 omega_p by Radau IIA alone at rtol 1e-12, an independent
    path (docs/stick_slip.md, section 8; the two families differ by 6.9e-8 there). The
    regularised default is 1.3e-3 off there (the width). Its work, not its time: the
    regularised path took 811,837 right-hand sides at rtol 1e-8 (docs/stick_slip.md)."""
    case = rig_case(40.0, MU_S)
    t_cr, _, stats = opening_times([case], AUTO)
    assert t_cr[0] == opening_time(case)
    assert abs(t_cr[0] / 42.73197122 - 1.0) <= 1e-6
    assert stats["n_set_valued"] == 1 and stats["nfev"] <= 100_000


def test_convergence_check_of_a_set_valued_point_reruns_the_regularised_path():
    case = rig_case(78.0, MU_S)
    opts = SolverOptions(rtol=1e-9, atol=1e-11, friction_width=1e-5)
    check = convergence_check(case, opts)
    # auto runs it set-valued at a third of the tolerances, the tighter rerun too
    rtol, atol = auto_radau_tolerances(opts.rtol, opts.atol)
    by_name = replace(opts, method="set-valued", rtol=rtol, atol=atol)
    assert check.opening_time == opening_time(case, by_name)
    assert check.tighter_tolerance == opening_time(case, by_name.tighter())
    assert check.tighter_tolerance == opening_time(case, opts.tighter())
    narrow = replace(opts.tighter(), friction_width=opts.friction_width / 10, method="regularised")
    assert check.narrower_width == opening_time(case, narrow)
    assert check.other_family == opening_time(case, replace(narrow, friction_family="linear"))


def test_result_and_cli_name_the_solver_that_ran(capsys):
    assert simulate(rig_case(78.0, MU_S, t_max=0.05)).summary()["solver"] == "set-valued"
    assert simulate(rig_case(300.0, MU_S, t_max=0.05)).summary()["solver"] == "regularised"
    assert main(["simulate", "--spin-rate", "78", "--mu-s", "0.5473", "--t-max", "0.05"]) == 0
    out = capsys.readouterr().out
    assert "set-valued, no width (method auto: set-valued)" in out and "width 1e-07" not in out
    assert main(["simulate", "--spin-rate", "300", "--mu-s", "0.5473", "--t-max", "0.05"]) == 0
    assert "algebraic, width 1e-07" in capsys.readouterr().out


def test_study_digests_name_the_choice(monkeypatch):
    """A resume store written when ``auto`` was the regularised law, or under other
    thresholds, has another digest (the store refuses it), though the option fields and
    the package version are the same."""
    regularised = study_digest({"options": replace(AUTO, method="regularised")})
    auto = study_digest({"options": AUTO})
    assert auto != regularised
    from obturator.sweeps import SweepSpec

    def sweep(options):
        return SweepSpec(case="spin-rig", axes={"spin_rate": np.array([78.0])}, options=options)

    sweep_auto = sweep(AUTO).digest()
    assert sweep_auto != sweep(replace(AUTO, method="regularised")).digest()
    monkeypatch.setitem(dispatch.SET_VALUED_BELOW, 1, 0.5)
    assert study_digest({"options": AUTO}) != auto and sweep(AUTO).digest() != sweep_auto
    assert study_digest({"options": replace(AUTO, method="regularised")}) == regularised
