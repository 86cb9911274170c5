"""Trajectory-coupled opening: constant-load limit, segment convergence, signs, statuses."""

from __future__ import annotations

import math

import pytest

from obturator.envelope.coupled import (
    STATUS_OPENED,
    STATUS_SUBSONIC,
    ObturatorDesign,
    constant_opening,
    coupled_convergence,
    coupled_opening,
)
from obturator.envelope.drag import DragTable
from obturator.envelope.model import FlightModel, exceeds
from obturator.envelope.trajectory import Launch, Projectile, fly
from obturator.errors import InputError
from obturator.model.cases import flight_case
from obturator.solve import opening_time
from obturator.status import Status

STILL = Projectile(drag=DragTable.constant(0.0), roll_damping=0.0)


def test_frozen_flight_reproduces_the_constant_load_case():
    """No drag, gravity or roll damping: the segmented run equals one thesis flight case."""
    tr = fly(STILL, Launch(mach=3.0, gravity=0.0, spin_rate=12042.0), t_end=0.1)
    res = coupled_opening(ObturatorDesign(), tr, segment=3e-3)
    ref = opening_time(flight_case(12042.0, p1=101_325.0))
    assert res.status == STATUS_OPENED
    assert res.n_segments == math.ceil(ref / 3e-3)
    assert res.t_cr == pytest.approx(ref, rel=1e-8)


def test_segment_halving_converges():
    tr = fly(Projectile(), Launch(mach=3.0), t_end=0.1)
    d = ObturatorDesign()
    t = {h: coupled_opening(d, tr, segment=h).t_cr for h in (16e-3, 8e-3, 4e-3, 0.5e-3)}
    ref = t[0.5e-3]
    e16, e8, e4 = (abs(t[h] / ref - 1.0) for h in (16e-3, 8e-3, 4e-3))
    assert e8 < 0.5 * e16 and e4 < 0.5 * e8  # (at least) first-order; midpoint rule ~ second
    assert e4 < 1e-4


def test_deceleration_lengthens_and_spin_decay_shortens_the_opening():
    launch = Launch(mach=1.5, spin_rate=6000.0)
    d = ObturatorDesign()
    t_const, conv = constant_opening(d, launch)
    assert conv is not None and conv["converged"]
    drag_only = fly(Projectile(roll_damping=0.0), launch, t_end=0.5)
    spin_only = fly(Projectile(drag=DragTable.constant(0.0)), launch, t_end=0.5)
    assert coupled_opening(d, drag_only).t_cr > t_const * 1.005  # F_p falls with M
    assert coupled_opening(d, spin_only).t_cr < t_const  # t_cr ~ omega_p (thesis Eq. 96)


def test_spin_override_scales_the_spin_history():
    tr = fly(Projectile(), Launch(mach=3.0), t_end=0.1)
    a = coupled_opening(ObturatorDesign(), tr, spin_rate=10_000.0)
    b = coupled_opening(
        ObturatorDesign(), fly(Projectile(), Launch(mach=3.0, spin_rate=10_000.0), t_end=0.1)
    )
    assert a.t_cr == pytest.approx(b.t_cr, rel=1e-7)


def test_convergence_report_for_table1():
    tr = fly(Projectile(), Launch(mach=3.0), t_end=0.1)
    conv = coupled_convergence(ObturatorDesign(), tr)
    assert conv.converged
    # tolerance, width, a second regularisation family and the load segment
    assert set(conv.variants) == {
        "tighter_tolerance",
        "narrower_width",
        "other_family",
        "half_segment",
    }
    assert abs(conv.variants["other_family"] / conv.t_cr - 1.0) < 1e-3
    assert conv.to_dict()["converged"] is True


def test_subsonic_before_opening():
    tr = fly(Projectile(drag=DragTable.constant(6.0)), Launch(mach=1.05), t_end=1.0)
    res = coupled_opening(ObturatorDesign(), tr)
    assert res.status == STATUS_SUBSONIC and not res.opened


def test_design_validation():
    with pytest.raises(InputError, match="^hole_radius:"):
        ObturatorDesign(hole_radius=6e-3)
    with pytest.raises(InputError, match="^bore_radius:"):
        ObturatorDesign(bore_radius=8e-3)
    with pytest.raises(InputError, match="^design:"):
        ObturatorDesign().with_(radius=1.0)
    assert ObturatorDesign().mass == pytest.approx(0.07987 / 9.80665, rel=3e-3)


def test_flight_model_point():
    m = FlightModel(load="both")
    r = m({"mach": 3.0})
    assert r["status"] == 1 and r["status_constant"] == 1
    assert r["change"] < 1e-3 and r["change_constant"] < 1e-3
    assert r["t_cr"] > r["t_cr_constant"]
    bad = m({"hole_radius": 7e-3})
    assert bad["status"] == -2 and "hole_radius" in bad["error"]
    with pytest.raises(InputError, match="^load:"):
        FlightModel(load="other")
    opened, unconverged = int(Status.OPENED), int(Status.UNCONVERGED)
    assert exceeds(0.2, opened, 0.1) and not exceeds(0.05, unconverged, 0.1)
    assert exceeds(math.nan, int(Status.T_MAX), 0.1) and exceeds(0.05, int(Status.STEP_LIMIT), 0.1)
    # spin_factor multiplies the nominal muzzle spin
    assert m.build({"spin_factor": 0.5})[1].muzzle_spin == pytest.approx(6021.0)


def test_many_points_in_lanes_match_one_at_a_time():
    """coupled_openings advances all points segment by segment in lanes; each point's
    answer is the one it gets alone (a point that fails validation does not disturb the
    others), and FlightModel.evaluate_many is its __call__ point by point."""
    from obturator.envelope.coupled import FlightPoints, cached_flight, coupled_openings

    flights = [cached_flight(Projectile(), Launch(mach=m), 1.0) for m in (1.75, 2.5, 3.5)]
    designs = [ObturatorDesign(mu_s=mu) for mu in (0.3, 0.45, 0.6)]
    spins = [None, -1.0, 9000.0]  # the second is invalid
    many = coupled_openings(FlightPoints(designs, flights, spins))
    assert isinstance(many[1], InputError) and "spin_rate" in str(many[1])
    for k in (0, 2):
        one = coupled_opening(designs[k], flights[k], spin_rate=spins[k])
        assert many[k].status == one.status == STATUS_OPENED
        assert many[k].n_segments == one.n_segments and many[k].nfev == one.nfev
        assert many[k].t_cr == pytest.approx(one.t_cr, rel=1e-12)
    model = FlightModel(load="both", check_convergence=True)
    points = [{"mach": 2.0, "mu_s": 0.4}, {"mach": 0.5}, {"mach": 3.0, "altitude_m": 5000.0}]
    rows = model.evaluate_many(points)
    assert rows[1]["status"] == Status.INVALID_INPUT and "mach" in rows[1]["error"]
    for row, values in zip(rows, points, strict=True):
        alone = model(values)
        assert row.keys() == alone.keys()
        for key, value in row.items():
            if isinstance(value, float) and math.isfinite(value):
                assert value == pytest.approx(alone[key], rel=1e-12), key
            else:
                assert value == alone[key] or (value != value and alone[key] != alone[key])


def test_start_angles_are_the_start_conditions_fields_each_computed_once_per_mach():
    """The nominal, late and early start angles of a design at one altitude and Mach are
    the fields of a direct :func:`~obturator.model.start.start_condition` to the bit (the
    flight runs ask for one bound at every segment, which computes only that bound), and
    each is computed once per Mach (memoised)."""
    from obturator.envelope import design as design_module
    from obturator.model.start import start_condition

    d = ObturatorDesign()
    bounds = ("nominal", "late", "early")
    for altitude, mach in [(2345.5, 2.25), (0.0, 1.2), (9000.0, 1.45), (500.0, 5.5)]:
        # (0 m, M 1.2): below the late bound's start; (9 km, M 1.45): late NaN, nominal not
        before = design_module._start_angle.cache_info()
        got = [d.start_angle(altitude, bound)(mach) for bound in bounds]
        again = [d.start_angle(altitude, bound)(mach) for bound in bounds]
        after = design_module._start_angle.cache_info()
        assert (after.misses - before.misses, after.hits - before.hits) == (3, 3)
        cond = start_condition(mach, d.ball(), d.bore_radius, gamma=d.gamma, altitude_m=altitude)
        expect = [cond.theta_start, cond.theta_start_late, cond.theta_start_early]
        assert got == pytest.approx(expect, rel=0.0, abs=0.0, nan_ok=True)
        assert again == pytest.approx(got, rel=0.0, abs=0.0, nan_ok=True)


def test_start_angle_refuses_an_unknown_bound():
    from obturator.errors import InputError
    from obturator.model.start import start_angle

    d = ObturatorDesign()
    with pytest.raises(InputError, match=r"^bound: 'lateish'; allowed: nominal, late, early$"):
        d.start_angle(0.0, "lateish")
    with pytest.raises(InputError, match=r"^bound: 'x'; allowed: nominal, late, early$"):
        start_angle(2.0, d.ball(), d.bore_radius, "x")
