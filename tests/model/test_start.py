"""Open area through the tilted ball and the start of the internal flow (thesis ch. I, Eq. 2).

References: closed forms (A(0) = bore area, A(beta_s) = 0, the lens of two
circles), an independent Monte Carlo ray trace through the solid ball, and the
Kantrowitz-Donaldson limit of :mod:`obturator.flow.inlet` (Eq. 2, tested there
against NACA 1135).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from obturator.errors import InputError
from obturator.flow import start_mach, swallow_area_ratio
from obturator.model.cases import flight_case, table1_ball
from obturator.model.geometry import BoredBall
from obturator.model.passage import (
    open_angle,
    open_area,
    open_area_ray_count,
    ring_contact_fraction,
    turned_open_angle,
    turned_open_area,
)
from obturator.model.start import full_bore_start_mach, start_condition
from obturator.reference import TABLE1
from obturator.solve import opening_time, simulate

R_S, R_HOLE, R_BORE = TABLE1["ball_radius"], TABLE1["hole_radius"], TABLE1["bore_radius"]
BETA_S = math.asin(R_HOLE / R_S)


def test_open_area_aligned_is_the_bore_and_zero_at_first_light():
    assert open_area(0.0, R_S, R_HOLE, R_BORE) == pytest.approx(math.pi * R_BORE**2, rel=1e-14)
    # a narrower bore cuts the hole's circle: pi r_p^2; a wider one does not: pi r_s^2
    assert open_area(0.0, R_S, R_HOLE, 3e-3) == pytest.approx(math.pi * 3e-3**2, rel=1e-9)
    assert open_area(0.0, R_S, R_HOLE, 5.5e-3) == pytest.approx(math.pi * R_HOLE**2, rel=1e-14)
    assert open_area(BETA_S, R_S, R_HOLE, R_BORE) == pytest.approx(0.0, abs=1e-20)
    assert open_area(BETA_S + 0.1, R_S, R_HOLE, R_BORE) == 0.0
    assert open_area(BETA_S - 1e-6, R_S, R_HOLE, R_BORE) > 0.0


@given(
    t1=st.floats(0.0, 1.2),
    t2=st.floats(0.0, 1.2),
    bore=st.floats(1e-3, 6e-3),
)
def test_open_area_falls_monotonically(t1, t2, bore):
    lo, hi = sorted((t1, t2))
    assert open_area(lo, R_S, R_HOLE, bore) >= open_area(hi, R_S, R_HOLE, bore) - 1e-18


@pytest.mark.parametrize("deg", [3.0, 12.0, 25.0, 33.0])
def test_quadrature_branch_meets_the_closed_form(deg):
    # r_p just below r_s takes the clipped-lens quadrature; the lens lies inside the
    # circle r_s, so the clip removes nothing and the closed form must come back
    t = math.radians(deg)
    exact = open_area(t, R_S, R_HOLE, R_BORE)
    quad = open_area(t, R_S, R_HOLE, R_HOLE * (1.0 - 1e-12))
    assert quad == pytest.approx(exact, rel=1e-9, abs=1e-18)


@pytest.mark.parametrize(
    ("deg", "bore"),
    [(5.0, R_BORE), (15.0, R_BORE), (30.0, R_BORE), (35.0, R_BORE), (20.0, 3.5e-3), (8.0, 3e-3)],
)
def test_open_area_against_ray_count(deg, bore):
    # independent reference: 400 000 rays traced through sphere and hole cylinder;
    # tolerance 5 standard errors (the error is about 2.5e-4 of the bore area here)
    t = math.radians(deg)
    mc, se = open_area_ray_count(t, R_S, R_HOLE, bore, rays=400_000, seed=7)
    assert open_area(t, R_S, R_HOLE, bore) == pytest.approx(mc, abs=5 * se)


def test_open_angle_inverts_open_area():
    full = math.pi * R_BORE**2
    for frac in (0.0, 0.1, 0.5, 0.9, 1.0):
        t = open_angle(frac * full, R_S, R_HOLE, R_BORE)
        assert open_area(t, R_S, R_HOLE, R_BORE) == pytest.approx(frac * full, abs=1e-12 * full)
    assert open_angle(0.0, R_S, R_HOLE, R_BORE) == pytest.approx(BETA_S)
    with pytest.raises(InputError, match="area"):
        open_angle(1.1 * full, R_S, R_HOLE, R_BORE)


def test_ring_contact_fraction_closed_forms():
    # r_p = r_s: q = cot(beta) tan(theta/2); whole ring backed from 2 beta_s on
    assert ring_contact_fraction(2 * BETA_S + 1e-9, R_S, R_HOLE, R_BORE) == 1.0
    c = math.cos(BETA_S)
    at_light = 1.0 - math.acos(c / (1.0 + c)) / math.pi
    assert ring_contact_fraction(BETA_S, R_S, R_HOLE, R_BORE) == pytest.approx(at_light)
    assert ring_contact_fraction(1e-6, R_S, R_HOLE, R_BORE) == pytest.approx(0.5, abs=1e-6)


def test_geometry_input_errors():
    with pytest.raises(InputError, match="bore_radius"):
        open_area(0.1, R_S, R_HOLE, 7e-3)  # beyond sqrt(R_s^2 - r_s^2) = 6.33 mm
    with pytest.raises(InputError, match="theta"):
        open_area(-0.1, R_S, R_HOLE, R_BORE)


def test_theta_start_is_zero_where_the_full_bore_just_starts():
    ball = table1_ball()
    capture = 1.3 * math.pi * R_BORE**2  # a capture area wider than the bore
    m_full = full_bore_start_mach(ball, R_BORE, capture_area=capture)
    assert m_full == pytest.approx(float(start_mach(1.3)))
    at = start_condition(m_full * (1 + 1e-12), ball, R_BORE, capture_area=capture)
    assert at.startable
    assert at.theta_start == pytest.approx(0.0, abs=1e-5)
    below = start_condition(0.99 * m_full, ball, R_BORE, capture_area=capture)
    assert not below.startable and math.isnan(below.theta_start)
    assert below.verdict == "unstartable"
    # the constant-area Table 1 bore starts at any supersonic Mach, at theta -> 0 as M -> 1
    assert full_bore_start_mach(ball) == 1.0
    assert start_condition(1.0 + 1e-9, ball).theta_start < 1e-3


def test_theta_start_solves_the_kantrowitz_limit():
    ball = table1_ball()
    previous = 0.0
    for mach in (1.5, 2.0, 2.5, 3.0, 3.5, 4.0):
        s = start_condition(mach, ball)
        a_t = open_area(s.theta_start, R_S, R_HOLE, R_BORE)
        assert math.pi * R_BORE**2 / a_t == pytest.approx(float(swallow_area_ratio(mach)))
        assert previous < s.theta_start < BETA_S  # later than first light, earlier at low M
        previous = s.theta_start


def test_fanno_choking_flag():
    ball = table1_ball()
    s = start_condition(1.3, ball)  # Table 1 bore chokes below M ~ 1.44 (thesis ch. I.B.4.c)
    assert s.choked and s.verdict == "choked"
    assert 1.40 < s.choke_mach < 1.50
    assert start_condition(2.0, ball).verdict == "starts"
    with pytest.raises(InputError, match="mach"):
        start_condition(1.0, ball)


def test_start_comes_after_first_light_in_flight():
    case = flight_case()
    s = start_condition(TABLE1["mach"], case.ball)
    t_cr = opening_time(case)
    started = simulate(case.with_(theta_cr=s.theta_start))
    assert started.opened
    assert started.opening_time > t_cr
    assert float(started.theta[-1]) == pytest.approx(s.theta_start, abs=1e-6)


def test_wider_bore_than_hole_is_limited_by_the_hole():
    ball = BoredBall(R_S, 4.0e-3, TABLE1["density"])
    s = start_condition(3.0, ball, 4.72e-3)
    # A(0) = pi r_s^2 < A_c = pi r_p^2: ratio 1.3924 > Eq. 2's 1.3904 at Mach 3
    assert not s.startable


def test_start_times_restart_matches_the_continuous_run_and_brackets():
    from obturator.solve import start_times

    case = flight_case()
    s = start_condition(TABLE1["mach"], case.ball)
    st = start_times(case, s)
    continuous = opening_time(case.with_(theta_cr=s.theta_start))
    assert st.t_start == pytest.approx(continuous, rel=1e-8)  # restart at t_cr is exact
    assert st.t_cr == pytest.approx(opening_time(case), rel=1e-12)
    low, high = s.spill_load_factors()
    assert 0.0 < low < 1.0 < high
    # a larger load opens faster (more sliding friction): the bracket holds t_start
    assert st.t_start_high_load < st.t_start < st.t_start_low_load


def test_cli_simulate_flight_reports_t_start(capsys):
    import json

    from obturator.cli import main

    assert main(["simulate", "--case", "flight", "--json", "--no-check", "--mach", "2.5"]) == 0
    out = json.loads(capsys.readouterr().out)["start"]
    assert out["theta_start_deg"] == pytest.approx(7.805, abs=1e-3)
    assert out["t_start_s"] > out["t_cr_s"] > 0.0
    assert out["verdict"] == "starts"


def test_cli_trajectory_reports_t_start(capsys):
    import json

    from obturator.cli import main

    assert main(["trajectory", "--mach", "2.5", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["t_start_coupled_s"] > out["t_cr_coupled_s"]
    assert out["t_start_constant_s"] > out["t_cr_constant_s"]
    assert out["theta_start_muzzle_deg"] == pytest.approx(7.805, abs=1e-3)
    # the flight slows down, so theta_start(M) at the start is below the muzzle value
    assert out["theta_start_at_start_deg"] < out["theta_start_muzzle_deg"]
    assert out["inlet_at_muzzle"] == "starts"
    # the bracket: turned flow earlier, friction and the lowest C_d later (M 2.5 starts)
    assert out["theta_start_early_deg"] > out["theta_start_muzzle_deg"]
    assert out["theta_start_late_deg"] < out["theta_start_muzzle_deg"]
    early, late = out["t_start_constant_early_s"], out["t_start_constant_late_s"]
    assert out["t_cr_constant_s"] < early < out["t_start_constant_s"] < late
    assert out["late_at_muzzle"] == "starts" and out["discharge_coefficient_late"] == 0.84


def test_cli_simulate_flight_prints_the_bracket(capsys):
    from obturator.cli import main

    assert main(["simulate", "--case", "flight", "--mach", "1.5", "--no-check"]) == 0
    lines = {ln.split("  ")[0]: ln for ln in capsys.readouterr().out.splitlines()}
    theta = lines["theta_start bracket, early .. late"]
    assert "5.5928 deg (turned flow) .. never starts: C_d A/A*(M_3) = 0.8739" in theta
    assert lines["t_start bracket, early .. late"].endswith(".. never starts")
    assert "2.83205" in lines["theta_start (shock swallowed, Eq. 2)"]  # today's, unchanged


@pytest.mark.slow
def test_cli_trajectory_prints_the_bracket(capsys):
    from obturator.cli import main

    assert main(["trajectory", "--mach", "1.5"]) == 0
    line = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("t_start bracket")]
    assert len(line) == 1
    assert "early 0.1095 s (theta_start 5.5928 deg" in line[0]
    assert "late never starts (C_d A/A*(M_3) = 0.8739 < A_c/A(0) = 1" in line[0]


def test_coupled_start_with_constant_mach_stop_equals_the_fixed_stop():
    # a stop angle that does not depend on M gives the run to that angle
    from obturator.envelope.coupled import ObturatorDesign, cached_flight, coupled_opening
    from obturator.envelope.trajectory import Launch, Projectile

    design = ObturatorDesign()
    flight = cached_flight(Projectile(), Launch(mach=3.0), 0.2)
    first = coupled_opening(design, flight, stop_angle=lambda m: design.ball().opening_angle)
    plain = coupled_opening(design, flight)
    assert first.t_cr == pytest.approx(plain.t_cr, rel=1e-12)


def test_envelope_maps_t_start_and_delay():
    from obturator.envelope.envelope import EnvelopeSpec, envelope_summary, run_envelope
    from obturator.envelope.model import FlightModel

    spec = EnvelopeSpec(mach=(2.5,), altitude_m=(0.0,), model=FlightModel(check_convergence=False))
    ds = run_envelope(spec).squeeze()

    def val(name):
        return float(ds[name].values)

    assert val("t_start_coupled") > val("t_cr_coupled")
    assert val("delay_constant") == pytest.approx(val("t_start_constant") - val("t_cr_constant"))
    assert val("theta_start_muzzle") == pytest.approx(7.805, abs=1e-3)
    assert val("unstartable") == 0
    assert envelope_summary(ds)["delay_coupled_min_s"] > 0.0
    # the late bound (friction, lowest C_d) starts at M 2.5, later than the lens's
    assert val("never_starts_late") == 0
    assert val("t_start_late_coupled") > val("t_start_coupled")
    assert val("t_start_late_constant") > val("t_start_constant")
    assert val("theta_start_late_muzzle") < val("theta_start_muzzle")
    assert envelope_summary(ds)["never_starts_late_points"] == 0


def test_split_objective():
    from obturator.envelope.optimize import split_objective

    assert split_objective("t_start") == ("t_start", "max")
    assert split_objective("t_start:quantile:0.9") == ("t_start", "quantile:0.9")
    assert split_objective("quantile:0.5") == ("t_cr", "quantile:0.5")
    assert split_objective("t_cr") == ("t_cr", "max")


def test_flight_model_event_start():
    from obturator.envelope.model import FlightModel

    point = {"mach": 3.0}
    first = FlightModel(load="constant", check_convergence=False)(point)
    both = FlightModel(load="constant", check_convergence=False, with_start=True)(point)
    start = FlightModel(load="constant", check_convergence=False, event="start")(point)
    assert start["t_cr"] == pytest.approx(both["t_start"], rel=1e-12)
    assert start["t_cr"] > first["t_cr"] == both["t_cr"]
    with pytest.raises(InputError, match="event"):
        FlightModel(event="later")


def test_cli_optimize_and_probability_for_t_start(capsys, tmp_path):
    import json

    from obturator.cli import main

    common = ["--mach", "3", "--altitude-m", "0", "--no-convergence-check", "--workers", "1"]
    args = ["optimize", *common, "--objective", "t_start", "--variables", "mu_s"]
    args += ["--popsize", "2", "--maxiter", "1", "--no-polish", "--no-progress", "--json"]
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["objective"] == "max" and out["event"] == "start"
    assert out["baseline_objective_s"] == pytest.approx(0.0332, rel=2e-3)  # coupled t_start
    args = ["probability", *common, "--event", "t_start", "--method", "mc", "--samples", "8"]
    args += ["--requirement", "0.02", "--vary", "mu_s=uniform:0.3,0.4", "--no-progress", "--json"]
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    assert "mc" in json.dumps(out)


def test_cli_sensitivity_event_t_start(capsys):
    from obturator.cli import main

    args = ["sensitivity", "--event", "t_start", "--samples", "8", "--resamples", "10"]
    args += ["--no-convergence-check", "--workers", "1", "--no-progress"]
    args += ["--vary", "mu_s=uniform:0.3,0.4", "--vary", "density=uniform:7000,8000"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "Sobol indices of t_start" in out and "mean t_start 0.03" in out
    assert main(["sensitivity", "--case", "spin-rig", "--event", "t_start"]) == 2
    assert "--event" in capsys.readouterr().err


# -- the theta_start bracket: turned-flow window (early) and friction + C_d (late) --


def _window_ray_count(theta: float, bore: float, n: int = 400_000) -> tuple[float, float]:
    """Independent Monte Carlo of the turned-flow window: points of the bore disc whose
    ray along -Z first meets the sphere inside the upstream mouth (x sin + h cos >= c)."""
    import numpy as np

    rng = np.random.default_rng(11)
    rad = bore * np.sqrt(rng.random(n))
    phi = 2 * math.pi * rng.random(n)
    x = rad * np.cos(phi)
    h = np.sqrt(R_S**2 - rad**2)
    c = math.sqrt(R_S**2 - R_HOLE**2)
    p = np.count_nonzero(x * math.sin(theta) + h * math.cos(theta) >= c) / n
    full = math.pi * bore**2
    return full * p, full * math.sqrt(max(p * (1 - p), 1 / n) / n)


@pytest.mark.parametrize(
    ("deg", "bore"), [(3.0, R_BORE), (20.0, R_BORE), (50.0, R_BORE), (10.0, 3e-3)]
)
def test_turned_window_against_ray_count(deg, bore):
    t = math.radians(deg)
    mc, se = _window_ray_count(t, bore)
    assert turned_open_area(t, R_S, R_HOLE, bore) == pytest.approx(mc, abs=5 * se)


def _window_by_quadrature(theta: float, bore: float) -> float:
    """The turned window by adaptive quadrature of the smaller half-width (scipy ``quad``,
    the boundaries' crossings as break points): an independent way to the closed form."""
    from scipy.integrate import quad

    c = math.sqrt(R_S**2 - R_HOLE**2)
    cos_t, sin_t = math.cos(theta), math.sin(theta)
    d = c * sin_t
    lo, hi = max(-bore, d - R_HOLE * cos_t), min(bore, d + R_HOLE * cos_t)
    if hi <= lo:
        return 0.0

    def half_width(x: float) -> float:
        return math.sqrt(max(0.0, min(R_HOLE**2 - ((x - d) / cos_t) ** 2, bore**2 - x * x)))

    qa, qb, qc = sin_t**2, -2.0 * d, d * d - (R_HOLE**2 - bore**2) * cos_t**2
    disc = qb * qb - 4.0 * qa * qc
    points = []
    if qa > 0.0 and disc >= 0.0:
        roots = ((-qb - math.sqrt(disc)) / (2 * qa), (-qb + math.sqrt(disc)) / (2 * qa))
        points = [x for x in roots if lo < x < hi]
    value, _ = quad(half_width, lo, hi, points=points or None, epsabs=0.0, epsrel=1e-13, limit=400)
    return min(2.0 * value, math.pi * min(R_HOLE, bore) ** 2)


@pytest.mark.parametrize("bore", [2e-3, 3e-3, R_BORE, 5.5e-3, 6e-3])
def test_turned_window_closed_form_against_quadrature(bore):
    """The closed form against quadrature over the whole range of angles, the slivers
    where the window closes included (relative to the window where it is at least 1e-6
    of the full bore, else to the full bore)."""
    full = math.pi * min(R_HOLE, bore) ** 2
    closes = BETA_S + math.asin(bore / R_S)
    for t in np.linspace(0.0, min(closes, math.radians(89.0)), 400):
        got = turned_open_area(float(t), R_S, R_HOLE, bore)
        ref = _window_by_quadrature(float(t), bore)
        if ref > 1e-6 * full:
            assert got == pytest.approx(ref, rel=1e-10)
        else:
            assert got == pytest.approx(ref, abs=1e-13 * full)


def test_turned_window_limits_and_inverse():
    full = math.pi * R_BORE**2
    assert turned_open_area(0.0, R_S, R_HOLE, R_BORE) == pytest.approx(full, rel=1e-12)
    closes = BETA_S + math.asin(R_BORE / R_S)  # the mouth's cap leaves the bore's cap
    assert turned_open_area(closes + 1e-6, R_S, R_HOLE, R_BORE) == 0.0
    assert turned_open_area(closes - 1e-3, R_S, R_HOLE, R_BORE) > 0.0
    for deg in (1.0, 10.0, 30.0):
        t = math.radians(deg)
        assert turned_open_area(t, R_S, R_HOLE, R_BORE) > open_area(t, R_S, R_HOLE, R_BORE)
    for frac in (0.2, 0.9):
        t = turned_open_angle(frac * full, R_S, R_HOLE, R_BORE)
        assert turned_open_area(t, R_S, R_HOLE, R_BORE) == pytest.approx(frac * full, rel=1e-9)


@pytest.mark.parametrize("mach", [1.5, 2.0, 2.5, 3.0, 4.0])
def test_bracket_orders_and_late_never_starts_below(mach):
    cond = start_condition(mach, table1_ball())
    assert cond.theta_start_early > cond.theta_start  # the turned flow starts sooner
    ff = cond.theta_start_friction
    assert math.isnan(ff) or ff < cond.theta_start  # friction alone: later
    lo, hi = cond.friction_factors
    assert 0.0 < lo <= hi and cond.friction_fld == pytest.approx(hi * 76.2 / 9.44)
    if mach <= 2.0:  # C_d 0.84 is below C_d A/A*(M_3) = 1 here: never starts
        assert not cond.late_startable and "never starts" in cond.late_verdict
        assert cond.to_dict()["theta_start_late_deg"] is None
    else:
        assert cond.late_startable and cond.theta_start_late < ff
    # with C_d = 1 the late bound is friction alone
    unit = start_condition(mach, table1_ball(), discharge_coefficients=(1.0, 1.0))
    assert unit.theta_start_late == pytest.approx(ff, nan_ok=True)


def test_flight_model_event_start_late():
    from obturator.envelope.model import TIMES, FlightModel

    assert TIMES["t_start_late"] == "start_late"
    kw = {"load": "constant", "check_convergence": False}
    both = FlightModel(**kw, with_start=True)({"mach": 3.0})
    late = FlightModel(**kw, event="start_late")({"mach": 3.0})
    assert late["t_cr"] == pytest.approx(both["t_start_late"], rel=1e-12)
    assert late["t_cr"] > both["t_start"] > both["t_cr"]  # friction and C_d start later
    never = FlightModel(**kw, event="start_late")({"mach": 1.5})  # C_d 0.84 < 0.874
    assert math.isnan(never["t_cr"]) and never["status"] == 0
    from obturator.envelope.optimize import split_objective

    assert split_objective("t_start_late:quantile:0.9") == ("t_start_late", "quantile:0.9")


def test_cli_optimize_sensitivity_t_start_late(capsys):
    import json

    from obturator.cli import main

    common = ["--mach", "3", "--altitude-m", "0", "--no-convergence-check", "--workers", "1"]
    args = ["optimize", *common, "--objective", "t_start_late", "--variables", "mu_s"]
    args += ["--popsize", "2", "--maxiter", "1", "--no-polish", "--no-progress", "--json"]
    assert main(args) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["event"] == "start_late"
    assert out["baseline_objective_s"] > 0.0332  # the coupled t_start's late bound
    args = ["sensitivity", "--event", "t_start_late", "--samples", "8", "--resamples", "10"]
    args += ["--no-convergence-check", "--workers", "1", "--no-progress"]
    args += ["--vary", "mu_s=uniform:0.3,0.4", "--vary", "density=uniform:7000,8000"]
    assert main(args) == 0
    assert "Sobol indices of t_start_late" in capsys.readouterr().out


def test_start_condition_solves_the_choking_mach_once_per_bore_and_altitude():
    """The Fanno choking Mach does not depend on the flight Mach: start conditions at two
    Mach numbers of one flight solve it once (memoised), and the memoised value is the
    one a direct call gives (the same bits)."""
    from obturator.flow import choking_mach_freestream
    from obturator.model import start

    ball = table1_ball()
    altitude = 1234.5  # a value no other test asks for
    before = start._choking_mach.cache_info()
    a = start_condition(2.0, ball, altitude_m=altitude)
    b = start_condition(3.0, ball, altitude_m=altitude)
    after = start._choking_mach.cache_info()
    assert (after.misses - before.misses, after.hits - before.hits) == (1, 1)
    direct = choking_mach_freestream(
        TABLE1["projectile_length"] / (2.0 * TABLE1["bore_radius"]),
        2.0 * TABLE1["bore_radius"],
        altitude_m=altitude,
        gamma=TABLE1["gamma"],
    )
    assert a.choke_mach == b.choke_mach == direct
