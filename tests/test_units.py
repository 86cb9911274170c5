"""Quantities at the edge: frequencies carry 2 pi, angles are not pure numbers, no arithmetic."""

import math
import time

import pytest

from obturator.cli import main
from obturator.errors import InputError
from obturator.units import MAX_QUANTITY_TEXT, parse_quantity


@pytest.mark.parametrize(
    ("text", "unit", "expected"),
    [
        ("30 Hz", "rad/s", 2 * math.pi * 30),  # cycles per second: 2 pi rad per cycle
        ("2 kHz", "rad/s", 2 * math.pi * 2000),
        ("30 rev/s", "rad/s", 2 * math.pi * 30),
        ("115000 rpm", "rad/s", 115000 * 2 * math.pi / 60),
        ("200 rad/s", "rad/s", 200.0),
        ("20 deg/s", "rad/s", math.radians(20)),
        ("1.5 rad", "deg", math.degrees(1.5)),
        ("7.899 mm", "m", 7.899e-3),
        ("1.917e-5 Pa*s", "Pa*s", 1.917e-5),
        ("1.917e-5 Pa s", "Pa*s", 1.917e-5),
        ("7669.6 kg/m^3", "kg/m^3", 7669.6),
        ("0.099 MPa", "Pa", 0.099e6),
        ("50 %", "", 0.5),
        ("0.5473", "", 0.5473),
    ],
)
def test_conversions(text, unit, expected):
    assert parse_quantity("x", text, unit) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(
    ("text", "unit", "message"),
    [
        ("30 deg", "", "cannot be converted to a pure number"),  # an angle is not mu_s
        ("0.1 rad", "", "cannot be converted"),
        ("10 rad/s^2", "rad/s", "cannot be converted"),
        ("9**9**9 rad/s", "rad/s", "not a number or a number with a unit"),  # no arithmetic
        ("2*3 m", "m", "not a number"),
        ("1e999 m", "m", "not finite"),
        ("1e308 km", "m", "not finite"),
        ("3 blorbs", "m", "unknown unit"),
        ("", "m", "not a number"),
        ("x" * (MAX_QUANTITY_TEXT + 1), "m", "longer than"),
    ],
)
def test_rejections_name_the_field(text, unit, message):
    with pytest.raises(InputError, match=message) as err:
        parse_quantity("spin_rate", text, unit)
    assert err.value.field == "spin_rate"


def test_hostile_text_is_answered_fast():
    t0 = time.perf_counter()
    for text in ("9**9**9 rad/s", "1" * 70 + " m", "(" * 60, "1 " + "m*" * 30 + "m"):
        with pytest.raises(InputError):
            parse_quantity("x", text, "m")
    assert time.perf_counter() - t0 < 2.0


def test_pint_quantity_is_accepted():
    from obturator.units import _registry

    q = _registry().Quantity(30.0, "Hz")
    assert parse_quantity("spin_rate", q, "rad/s") == pytest.approx(60 * math.pi)


def test_cli_spin_rate_in_hz_is_2pi_rad_per_cycle(capsys):
    import json

    assert main(["simulate", "--spin-rate", "47.746 Hz", "--no-check", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["spin_rate_rad_s"] == pytest.approx(2 * math.pi * 47.746)


def test_cli_mu_in_degrees_is_rejected(capsys):
    assert main(["simulate", "--mu-s", "30 deg", "--no-check"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("obturator: error: --mu-s:") and err.count("\n") == 1


def test_case_factories_accept_pint_quantities():
    import pint

    from obturator import flight_case, opening_time, rig_case

    u = pint.UnitRegistry()  # the user's own registry
    a = rig_case(u.Quantity(2865.79, "rpm"), 0.5473, theta0_deg=u.Quantity(87.25, "deg"))
    b = rig_case(2865.79 * 2 * math.pi / 60, 0.5473)
    assert a.spin_rate == pytest.approx(b.spin_rate, rel=1e-12)
    assert opening_time(a) == pytest.approx(opening_time(b), rel=1e-6)  # same case to ~1 ulp
    f = flight_case(mach=u.Quantity(3.0, ""), p1=u.Quantity(0.099, "MPa"))
    assert f.torque.friction.pressure_force == pytest.approx(
        flight_case().torque.friction.pressure_force, rel=1e-12
    )
    with pytest.raises(InputError, match="mu_s"):
        rig_case(300.0, u.Quantity(30, "deg"))
