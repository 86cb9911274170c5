"""The Python API refuses what the command line refuses, from the one registry (issue 46).

A case's spin starts at the registry's 1 rad/s (``params.PARAMS["spin_rate"]``), and its
hole radius at R_s/10 (``params.MIN_HOLE_FRACTION``): below it the bored ball is nearly
a sphere (lambda = C/A - 1 = 1.25 (r_s/R_s)^2 to first order in Eqs. 10b and 11, checked
here against the exact inertias), and a 0.1 mm or 4 um hole ran for minutes past 1 GB.
The geometry itself still takes any hole from 0 (the solid sphere).
"""

from __future__ import annotations

import math

import pytest

from obturator import rig_case
from obturator.cli import main
from obturator.errors import InputError
from obturator.model.cases import flight_case, table1_ball
from obturator.model.geometry import BoredBall
from obturator.params import MIN_HOLE_FRACTION, PARAMS

R_S = 7.899e-3  # Table 1 ball radius [m]


@pytest.mark.parametrize("factory", [rig_case, flight_case])
@pytest.mark.parametrize("spin", [0.5, 0.0, -1.0, 1.1e6])
def test_spin_outside_the_registry_range_is_refused(factory, spin):
    with pytest.raises(InputError, match=r"^spin_rate: .*allowed range \[1, 1e\+06\] rad/s"):
        factory(spin_rate=spin)


def test_spin_at_the_ends_is_taken():
    rng = PARAMS["spin_rate"].range
    assert rng is not None
    assert rig_case(spin_rate=rng.lo).spin_rate == 1.0
    assert rig_case(spin_rate=rng.hi).spin_rate == 1e6


@pytest.mark.parametrize("hole", [0.0, 4e-6, 1e-4, 0.999 * MIN_HOLE_FRACTION * R_S])
def test_a_hole_below_the_bound_is_refused_at_construction(hole):
    ball = table1_ball(hole_radius=hole)  # the geometry takes it
    with pytest.raises(InputError, match=r"^hole_radius: .*allowed range \[0.0007899, "):
        rig_case(ball=ball)
    with pytest.raises(InputError, match="^hole_radius: "):
        flight_case(ball=ball)


def test_the_bound_itself_is_taken():
    case = rig_case(ball=table1_ball(hole_radius=MIN_HOLE_FRACTION * R_S))
    assert case.ball.hole_radius == pytest.approx(7.899e-4)


@pytest.mark.parametrize("fraction", [0.02, 0.05, 0.1])
def test_inertia_ratio_of_a_small_hole(fraction):
    """lambda = 1.25 x^2 (x = r_s/R_s) to first order, the argument for the bound: the
    O(x^4) rest is below 2 x^4 relative."""
    ball = BoredBall(R_S, fraction * R_S, 7669.6)
    x2 = fraction**2
    assert ball.inertia_ratio == pytest.approx(1.25 * x2, rel=2.0 * x2)


def test_the_command_line_says_the_same(capsys, tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text('[ball]\nhole_radius = "0.1 mm"\n')
    assert main(["simulate", "--config", str(cfg)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("obturator: error: ball.hole_radius: ")
    assert main(["simulate", "--spin-rate", "0.5"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "spin-rate" in err[0]


def test_pint_quantities_are_checked_too():
    pint = pytest.importorskip("pint")
    ureg = pint.UnitRegistry()
    with pytest.raises(InputError, match="^spin_rate: "):
        rig_case(spin_rate=ureg.Quantity(3.0, "rpm"))  # 0.314 rad/s
    assert rig_case(spin_rate=ureg.Quantity(60.0, "rpm")).spin_rate == pytest.approx(2.0 * math.pi)
