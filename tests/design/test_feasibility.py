"""What the rig can hold, new balls' own parameters, flat fit directions and the "neither"
check of the campaigns, against closed forms and independent computations (no study:
milliseconds, a few single-case packs)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from obturator.calibration.data import load_thesis_data
from obturator.design.campaigns import OUTSIDE, decision_rates, discrepancy, discrepancy_at
from obturator.design.feasibility import (
    JET_FORCE,
    ValidatedRange,
    check_setting,
    holding_moment,
    seat_friction_moment,
)
from obturator.design.posterior import Posterior, new_ball_prior_sd
from obturator.design.settings import Setting, design_case
from obturator.design.surrogate import Surrogate
from obturator.model.cases import TABLE1, rig_case
from obturator.solve import SolverOptions
from obturator.solve.dispatch import stick_ratio
from obturator.solve.setup import pack_parameters
from obturator.validation.candidates import CANDIDATES, THESIS_MU_S
from obturator.validation.results import CandidateFit
from obturator.validation.valley import FLAT_CONDITION, flat_directions, valley_starts


def _bored_sphere_inertias(radius: float, hole: float, rho: float) -> tuple[float, float]:
    """C (axial) and A (transverse) of a sphere bored through along z, by numerical
    integration over shells of the solid (independent of obturator.model.geometry)."""
    z = np.linspace(-radius, radius, 20001)
    r_out = np.sqrt(np.maximum(radius**2 - z**2, 0.0))
    r_in = np.minimum(hole, r_out)
    # a disc annulus r_in..r_out at height z: dm = rho pi (ro^2 - ri^2) dz
    ring = rho * math.pi * (r_out**2 - r_in**2)
    c = np.trapezoid(0.5 * ring * (r_out**2 + r_in**2), z)
    a = np.trapezoid(0.25 * ring * (r_out**2 + r_in**2) + ring * z**2, z)
    return float(c), float(a)


def test_holding_moment_is_the_gyroscopic_moment_of_the_bored_ball():
    # issue 47: the 5.58 mm ball held at 70 deg at 200 rad/s needs 1.1e-3 N m, 4.7 times
    # the seat's largest friction moment and about 3.5 times the holding jet's
    c, a = _bored_sphere_inertias(TABLE1["ball_radius"], 5.58e-3, TABLE1["density"])
    th = math.radians(70.0)
    expected = 200.0**2 * abs(c - a) * math.sin(th) * math.cos(th)
    got = holding_moment(200.0, 70.0, 5.58e-3)
    assert got == pytest.approx(expected, rel=1e-5)
    assert got == pytest.approx(1.1e-3, rel=0.05)
    # the new ball's load is its own weight rho V g: sphere - bore cylinder - two caps of
    # height h = R - a (cap volume pi h^2 (3R - h) / 3), a = sqrt(R^2 - r^2)
    big_r, r = TABLE1["ball_radius"], 5.58e-3
    half = math.sqrt(big_r**2 - r**2)
    h = big_r - half
    volume = 4 / 3 * math.pi * big_r**3 - math.pi * r**2 * 2 * half
    volume -= 2 * math.pi * h**2 * (3 * big_r - h) / 3
    weight = TABLE1["density"] * 9.80665 * volume
    seat = THESIS_MU_S * weight * TABLE1["ball_radius"]
    assert seat_friction_moment(5.58e-3) == pytest.approx(seat, rel=1e-6)
    assert got / seat == pytest.approx(4.7, abs=0.05)
    assert got / (JET_FORCE * TABLE1["ball_radius"]) == pytest.approx(3.5, abs=0.1)


@pytest.mark.parametrize("spin", [77.84, 200.0, 446.11])
def test_stick_ratio_is_the_solver_s_kappa_at_release(spin):
    """The holding moment over mu_s W R_s is the core's stick ratio at release (another
    code path: the packed case and the state, thesis Eq. 61 scale)."""
    case = rig_case(spin_rate=spin, mu_s=THESIS_MU_S)
    opts = SolverOptions()
    y0 = case.initial_state(opts.formulation)
    kappa = stick_ratio(pack_parameters(case, opts, y0), y0)
    f = check_setting(Setting(spin), ValidatedRange.of(load_thesis_data()))
    assert f.stick_ratio == pytest.approx(kappa, rel=1e-9)


def test_validated_range_of_the_thesis_runs_and_what_is_excluded():
    v = ValidatedRange.of(load_thesis_data())
    # the 54 runs needed 0.08-2.5 seat friction moments (issue 47)
    assert v.stick_ratio[0] == pytest.approx(0.0765, abs=5e-4)
    assert v.stick_ratio[1] == pytest.approx(2.51, abs=0.01)
    assert v.theta0_deg == (87.25,)
    # the recommended setting is beyond the rig
    f = check_setting(Setting(200.0, 70.0, 5.58e-3), v)
    assert not f.feasible and f.holding_moment > f.bound
    assert {"release angle", "new ball", "stick ratio"} <= set(f.extrapolated)
    # every measured run is feasible and none is extrapolated
    for w in load_thesis_data().spin_rate:
        g = check_setting(Setting(float(w)), v)
        assert g.feasible and g.extrapolated == ()
    # a release 0.5 deg off at a measured spin is within the stated +-1 deg
    assert check_setting(Setting(200.0, 87.75), v).extrapolated == ()
    assert check_setting(Setting(200.0, 85.0), v).extrapolated == ("release angle",)


def _fit(params, values, cov, name="theta0") -> CandidateFit:
    n = 6
    return CandidateFit(
        name=name,
        selection="all",
        params=tuple(params),
        values=dict(values),
        stderr={k: math.nan for k in params},
        ci95={k: (math.nan, math.nan) for k in params},
        ci_method={k: "wald" for k in params},
        plausible={k: True for k in params},
        sigma=0.01,
        nll=0.0,
        k=len(params) + 1,
        spin_rate=np.linspace(100, 400, n),
        measured=np.zeros(n),
        model=np.zeros(n),
        slope=np.zeros(n),
        sd=np.full(n, 0.01),
        band=np.array(["x"] * n),
        run=np.arange(n),
        t_max=20.0,
        covariance=np.asarray(cov, dtype=float),
    )


def test_a_new_ball_gets_the_prior_of_its_offset_not_the_fitted_one():
    # theta0 fitted 85.3 deg (offset -1.95) with SE 0.25 deg; scale of theta0_deg: 10
    fit = _fit(("mu_s", "theta0_deg"), {"mu_s": 0.6, "theta0_deg": 85.3}, [[1e-4, 0], [0, 0.0625]])
    post = Posterior.from_fit(fit)
    assert post.params == ("mu_s", "theta0_deg", "theta0_deg@new_ball")
    # prior SD: the stated +-1 deg as a uniform range, 1/sqrt 3 deg, whatever was fitted
    assert new_ball_prior_sd("theta0_deg") == pytest.approx(1.0 / math.sqrt(3.0))
    assert math.sqrt(post.covariance[2, 2]) == pytest.approx(0.1 / math.sqrt(3.0))  # /10
    assert post.covariance[2, :2] == pytest.approx([0.0, 0.0])
    assert post.to_values(post.mean)["theta0_deg@new_ball"] == pytest.approx(87.25)
    cand = CANDIDATES["theta0"]
    vals = {"mu_s": 0.6, "theta0_deg": 85.3, "theta0_deg@new_ball": 88.0}
    # as built: set 87.25 + fitted offset -1.95; a new ball: set + its own offset +0.75
    old = design_case(cand, Setting(200.0), vals, 1.0)
    new = design_case(cand, Setting(200.0, hole_radius=4.0e-3), vals, 1.0)
    assert math.degrees(old.theta0) == pytest.approx(85.3)
    assert math.degrees(new.theta0) == pytest.approx(88.0)


def test_flat_direction_of_a_correlated_pair_is_the_closed_form():
    """For two parameters with correlation rho the correlation matrix has eigenvalues
    1 +- rho: axis ratio sqrt((1 + rho)/(1 - rho)), direction (1, 1)/sqrt 2."""
    rho = 0.995
    sd = np.array([0.05, 0.02])  # mu_s and speed_ratio, linear transforms
    cov = np.outer(sd, sd) * np.array([[1.0, rho], [rho, 1.0]])
    fit = _fit(("mu_s", "speed_ratio"), {"mu_s": 0.7, "speed_ratio": 0.3}, cov, "x")
    (d,) = flat_directions(fit)
    assert d["axis_ratio"] == pytest.approx(math.sqrt((1 + rho) / (1 - rho)), rel=1e-9)
    assert d["direction"]["mu_s"] == pytest.approx(d["direction"]["speed_ratio"])
    assert d["axis_ratio"] ** 2 > FLAT_CONDITION
    starts = valley_starts(fit)
    assert len(starts) == 2  # two SDs either way along the valley
    assert starts[0]["mu_s"] - 0.7 == pytest.approx(-(starts[1]["mu_s"] - 0.7))
    # a weak correlation: no valley, no restarts
    weak = _fit(("mu_s", "speed_ratio"), {"mu_s": 0.7, "speed_ratio": 0.3}, np.diag(sd**2), "x")
    assert flat_directions(weak) == [] and valley_starts(weak) == []


def test_campaigns_expose_a_truth_outside_the_candidates():
    """Two one-setting candidates 0.10 s and 0.14 s, replicate SD 0.01 s: data from a
    candidate fail both predictive checks at about the rate the 5 % test allows; data
    0.08 s above both (a truth outside) fail both nearly always."""
    s = 4
    a = Surrogate("a", np.full(s, 0.10), np.zeros((s, 1)), np.zeros((s, 1)))
    b = Surrogate("b", np.full(s, 0.14), np.zeros((s, 1)), np.zeros((s, 1)))
    noise = np.full(s, 0.01)
    n = 4000
    exact = {
        "a": np.full((n, s), 0.10),
        "b": np.full((n, s), 0.14),
        OUTSIDE.format("a"): np.full((n, s), 0.22),
    }
    rates = decision_rates(exact, [0, 1, 2, 3], {"a": a, "b": b}, noise, np.random.default_rng(1))
    # under "a" both fail only if "a" fails (p 0.05): chi^2_4 tail, binomial SE 0.0035
    assert rates["a"].p_misfit == pytest.approx(0.05, abs=0.012)
    out = rates[OUTSIDE.format("a")]
    assert out.p_misfit > 0.99 and math.isnan(out.p_decisive)


def test_discrepancy_interpolates_cluster_means_in_log_spin():
    w = np.array([96.0, 96.5, 200.0, 400.0])
    r = np.array([0.06, 0.08, 0.0, -0.01])
    table = discrepancy(w, r, np.array([0, 0, 1, 2]))
    assert table[1] == pytest.approx([0.07, 0.0, -0.01])
    mid = math.exp(0.5 * (math.log(96.25) + math.log(200.0)))
    assert discrepancy_at(table, np.array([mid, 50.0, 900.0])) == pytest.approx(
        [0.035, 0.07, -0.01]
    )


@given(
    spin=st.floats(20.0, 2000.0),
    theta=st.floats(45.0, 89.5),
    hole=st.floats(1e-3, 5.58e-3),
    rho=st.floats(1000.0, 20000.0),
)
@settings(max_examples=60, deadline=None)
def test_holding_moment_scales_and_feasibility_is_the_bound(spin, theta, hole, rho):
    """M_hold grows as omega_p^2 and with rho (both inertias scale with it); a setting is
    feasible exactly when M_hold is within the bound, and the bound is never below the
    largest moment the measured runs needed."""
    m = holding_moment(spin, theta, hole, rho)
    assert holding_moment(2.0 * spin, theta, hole, rho) == pytest.approx(4.0 * m, rel=1e-12)
    assert holding_moment(spin, theta, hole, 2.0 * rho) == pytest.approx(2.0 * m, rel=1e-12)
    v = _THESIS_RANGE
    f = check_setting(Setting(spin, theta, hole, rho), v)
    assert f.bound >= v.holding_moment_max
    assert f.feasible == (f.holding_moment <= f.bound)
    assert f.stick_ratio == pytest.approx(f.holding_moment / f.seat_moment, rel=1e-12)


_THESIS_RANGE = ValidatedRange.of(load_thesis_data())
