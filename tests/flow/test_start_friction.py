"""The Kantrowitz-Donaldson start with Fanno friction and a discharge coefficient.

References: the frictionless, C_d = 1 limit is Eq. 2 (:func:`swallow_area_ratio`) and
the start angles an independent audit confirmed (2.832, 5.823, 9.102, 10.588 deg at
M 1.5, 2, 3, 4 for Table 1); the friction term against the closed-form Fanno relation
4 f L*/D and the normal-shock Mach written out here, not imported; the audit's friction
numbers (theta_start 4.45 deg at M 2 with f_D L/D = 0.2; no start below ~M 1.36 with
0.12); smooth-pipe friction against Blasius's and Colebrook's printed values.
"""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from obturator.errors import InputError
from obturator.flow import swallow_area_ratio
from obturator.flow.start_friction import (
    DISCHARGE_COEFFICIENT_RANGE,
    blasius_friction_factor,
    flat_plate_friction_factor,
    friction_start_mach,
    post_shock_reynolds,
    start_area_ratio,
    start_friction_range,
)
from obturator.model.passage import open_angle

G = 1.4
R_S, R_HOLE = 7.899e-3, 4.72e-3  # Table 1
BORE = math.pi * R_HOLE**2


def _fanno_4fld(m: float, g: float = G) -> float:
    """Closed-form Fanno choking length 4 f L*/D (Shapiro 1953, Eq. 6.21), written here."""
    return (1 - m * m) / (g * m * m) + (g + 1) / (2 * g) * math.log(
        (g + 1) * m * m / (2 + (g - 1) * m * m)
    )


def _shock_m2(m1: float, g: float = G) -> float:
    """Normal-shock downstream Mach (NACA 1135, Eq. 96), written here."""
    return math.sqrt((1 + 0.5 * (g - 1) * m1 * m1) / (g * m1 * m1 - 0.5 * (g - 1)))


def _area_ratio(m: float, g: float = G) -> float:
    return ((2 / (g + 1)) * (1 + 0.5 * (g - 1) * m * m)) ** ((g + 1) / (2 * (g - 1))) / m


def _subsonic_fanno_mach(fld: float) -> float:
    lo, hi = 1e-3, 1.0  # 4fL*/D falls from +inf to 0 on (0, 1]: bisection
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _fanno_4fld(mid) > fld else (lo, mid)
    return 0.5 * (lo + hi)


@pytest.mark.parametrize(
    ("mach", "theta_deg"), [(1.5, 2.832), (2.0, 5.823), (3.0, 9.102), (4.0, 10.588)]
)
def test_frictionless_unit_cd_limit_is_eq2_and_todays_angles(mach, theta_deg):
    ratio = start_area_ratio(mach, 0.0, 1.0)
    assert ratio == pytest.approx(float(swallow_area_ratio(mach)), rel=1e-12)
    theta = math.degrees(open_angle(BORE / ratio, R_S, R_HOLE, R_HOLE))
    assert theta == pytest.approx(theta_deg, abs=5e-4)  # the audit's 3 decimals


@given(
    mach=st.floats(1.05, 6.0),
    frac=st.floats(0.0, 0.999),
    cd=st.floats(0.5, 1.0),
)
def test_friction_term_against_independent_fanno(mach, frac, cd):
    m2 = _shock_m2(mach)
    fld = frac * _fanno_4fld(m2)  # a tube shorter than the choking length
    m3 = _subsonic_fanno_mach(_fanno_4fld(m2) - fld)
    assert start_area_ratio(mach, fld, cd) == pytest.approx(cd * _area_ratio(m3), rel=1e-8)


@pytest.mark.parametrize("mach", [1.2, 1.5, 2.0, 4.0])
def test_tube_choked_before_the_ball_never_starts(mach):
    fld = _fanno_4fld(_shock_m2(mach))
    assert start_area_ratio(mach, fld * 1.0001) == 0.0
    assert start_area_ratio(mach, fld * 0.999) > 0.0
    # friction_start_mach inverts it: the tube of that f L/D starts from this Mach on
    assert friction_start_mach(fld) == pytest.approx(mach, rel=1e-9)


def test_audit_friction_numbers():
    # theta_start 4.45 deg at M 2 with f_D L/D = 0.2 (frictionless: 5.82)
    ratio = start_area_ratio(2.0, 0.2)
    assert math.degrees(open_angle(BORE / ratio, R_S, R_HOLE, R_HOLE)) == pytest.approx(
        4.45, abs=0.01
    )
    # the aligned bore cannot start below ~M 1.36 with f_D L/D ~0.12
    assert friction_start_mach(0.12) == pytest.approx(1.36, abs=0.01)
    assert friction_start_mach(0.0) == 1.0


def test_cd_below_the_kantrowitz_ratio_never_starts():
    # the aligned bore's throat is A_c: it starts iff C_d A/A*(M_2) >= 1, i.e. C_d above
    # the Kantrowitz ratio A_t/A_c = 1 / A/A*(M_2) (0.914 at M 1.5, 0.822 at M 2)
    for mach, kd in ((1.5, 0.914), (2.0, 0.822)):
        assert 1.0 / _area_ratio(_shock_m2(mach)) == pytest.approx(kd, abs=5e-4)
        assert start_area_ratio(mach, 0.0, kd - 1e-3) < 1.0 < start_area_ratio(mach, 0.0, kd + 1e-3)


def test_friction_factor_range_brackets_smooth_pipe():
    # Blasius 0.3164 Re^-1/4 (Re 1e5: 0.0178); Colebrook smooth at 1e5: 0.0180 (Moody)
    assert blasius_friction_factor(1e5) == pytest.approx(0.3164 / 1e5**0.25, rel=1e-12)
    lo, hi = start_friction_range(3e5, 8.07)
    assert lo == pytest.approx(0.3164 * 3e5**-0.25, rel=1e-12)  # Blasius is the lower here
    # Schlichting's plate, 4 x 0.074 (Re L/D)^-1/5, the higher one for a short tube
    assert hi == pytest.approx(4 * 0.074 * (3e5 * 8.07) ** -0.2, rel=1e-12)
    assert flat_plate_friction_factor(3e5, 8.07) == hi
    assert 0.10 < 8.07 * lo < 8.07 * hi < 0.14  # the audit's f L/D ~0.12
    lo_l, hi_l = start_friction_range(1000.0, 8.07)  # laminar: Hagen-Poiseuille
    assert lo_l == pytest.approx(0.064) and hi_l >= lo_l
    rough = start_friction_range(3e5, 8.07, relative_roughness=0.005)[1]
    assert rough > hi  # commercial-steel roughness raises the high end
    assert DISCHARGE_COEFFICIENT_RANGE == (0.84, 1.0)


def test_post_shock_reynolds_independent():
    # sea level (1976): rho 1.225 kg/m^3, a 340.294 m/s, T 288.15 K; Sutherland at T_2
    m, d = 2.0, 9.44e-3
    t2 = 288.15 * (2 * G * m * m - (G - 1)) * ((G - 1) * m * m + 2) / ((G + 1) ** 2 * m * m)
    mu2 = 1.458e-6 * t2**1.5 / (t2 + 110.4)
    expect = 1.225 * m * 340.294 * d / mu2
    assert post_shock_reynolds(m, d) == pytest.approx(expect, rel=1e-4)


def test_input_errors():
    with pytest.raises(InputError, match="fld"):
        start_area_ratio(2.0, -0.1)
    with pytest.raises(InputError, match="discharge_coefficient"):
        start_area_ratio(2.0, 0.1, 1.2)
    with pytest.raises(InputError, match="mach"):
        start_area_ratio(0.9)
