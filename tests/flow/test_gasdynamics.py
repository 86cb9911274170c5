"""Tests of obturator.gasdynamics against published tables and the thesis.

Normal-shock and isentropic values are from NACA Report 1135 (Ames Research
Staff 1953), Tables I and II, gamma = 1.4, to the table's 4 significant
figures. Each row carries a hand calculation from the closed forms so that a
transcription slip in a tabulated number would be caught independently.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad, solve_ivp

from obturator import flow as gd
from obturator.errors import InputError

# NACA 1135 Table II (normal shock), gamma = 1.4:
# M1: (M2, p2/p1, rho2/rho1, T2/T1, p02/p01)
#
# Hand checks, g = 1.4, M2^2 = (5 + M1^2)/(7 M1^2 - 1),
# p2/p1 = 1 + (7/6)(M1^2 - 1), rho2/rho1 = 2.4 M1^2/(0.4 M1^2 + 2),
# T2/T1 = ratio of those two, p02/p01 = (rho2/rho1)^3.5 (p2/p1)^-2.5:
# 1.5: M2^2 = 7.25/14.75 = 0.49153 -> 0.70109; p = 1 + 1.16667*1.25 = 2.4583;
#      rho = 5.4/2.9 = 1.8621; T = 1.3202; ln p0 = 3.5*0.62169 - 2.5*0.89948
#      = -0.07278 -> 0.92980
# 2.0: M2^2 = 9/27 -> 0.57735; p = 4.5; rho = 9.6/3.6 = 2.6667; T = 1.6875;
#      ln p0 = 3.5*0.98083 - 2.5*1.50408 = -0.32728 -> 0.72087
# 3.0: M2^2 = 14/62 -> 0.47519; p = 10.333; rho = 21.6/5.6 = 3.8571;
#      T = 2.6790; ln p0 = 3.5*1.34993 - 2.5*2.33537 = -1.11367 -> 0.32834
# 4.0: M2^2 = 21/111 -> 0.43496; p = 18.5; rho = 38.4/8.4 = 4.5714;
#      T = 4.0469; ln p0 = 3.5*1.51983 - 2.5*2.91777 = -1.97501 -> 0.13877
NACA_NORMAL_SHOCK = {
    1.5: (0.7011, 2.458, 1.862, 1.320, 0.9298),
    2.0: (0.5774, 4.500, 2.667, 1.688, 0.7209),
    3.0: (0.4752, 10.33, 3.857, 2.679, 0.3283),
    4.0: (0.4350, 18.50, 4.571, 4.047, 0.1388),
}

# NACA 1135 Table I (isentropic flow), A/A*, gamma = 1.4.
# Hand checks, A/A* = (1/M) ((1 + 0.2 M^2)/1.2)^3:
# 0.5: 2 * 0.875^3 = 1.3398;  1.5: 0.66667 * 1.20833^3 = 1.1762;
# 2.0: 0.5 * 1.5^3 = 1.6875;  3.0: (1/3) * 2.33333^3 = 4.2346;
# 4.0: 0.25 * 3.5^3 = 10.719
NACA_AREA_RATIO = {0.5: 1.3398, 1.5: 1.1762, 2.0: 1.6875, 3.0: 4.2346, 4.0: 10.719}

# Fanno-line tables (Shapiro 1953, vol. 1, appendix; John & Keith, Gas
# Dynamics), listed as 4 f L*/D with the Fanning f, i.e. f_D L*/D, gamma = 1.4.
# Hand checks, f_D L*/D = (1 - M^2)/(1.4 M^2) + (6/7) ln(2.4 M^2/(2 + 0.4 M^2)):
# 0.5: 2.14286 + 0.85714 ln(0.28571) = 2.14286 - 1.07380 = 1.06906
# 1.5: -0.39683 + 0.85714 ln(1.86207) = -0.39683 + 0.53288 = 0.13605
# 2.0: -0.53571 + 0.85714 ln(2.66667) = -0.53571 + 0.84071 = 0.30500
# 3.0: -0.63492 + 0.85714 ln(3.85714) = -0.63492 + 1.15708 = 0.52216
FANNO_TABLE = {0.5: 1.0691, 1.5: 0.1361, 2.0: 0.3050, 3.0: 0.5222}


def agrees_to_4_figures(value: float, tabulated: float) -> bool:
    """True if ``value`` rounds to ``tabulated`` at 4 significant figures.

    Half a unit in the 4th figure, plus a hair for exact ties (1.6875 prints
    as 1.688 in the table).
    """
    half_unit = 0.5 * 10 ** (math.floor(math.log10(abs(tabulated))) - 3)
    return abs(value - tabulated) <= half_unit * (1 + 1e-9)


# ---------------------------------------------------------------------------
# normal shock


@pytest.mark.parametrize("mach", sorted(NACA_NORMAL_SHOCK))
def test_normal_shock_matches_naca_1135(mach: float) -> None:
    m2, p, rho, t, p0 = NACA_NORMAL_SHOCK[mach]
    assert agrees_to_4_figures(gd.normal_shock_mach(mach), m2)
    assert agrees_to_4_figures(gd.normal_shock_pressure_ratio(mach), p)
    assert agrees_to_4_figures(gd.normal_shock_density_ratio(mach), rho)
    assert agrees_to_4_figures(gd.normal_shock_temperature_ratio(mach), t)
    assert agrees_to_4_figures(gd.normal_shock_stagnation_pressure_ratio(mach), p0)


def test_normal_shock_dataclass_vectorised() -> None:
    machs = np.array(sorted(NACA_NORMAL_SHOCK))
    s = gd.normal_shock(machs)
    assert isinstance(s.mach2, np.ndarray) and s.mach2.shape == (4,)
    expected = np.array([NACA_NORMAL_SHOCK[m][4] for m in machs])
    np.testing.assert_allclose(s.stagnation_pressure_ratio, expected, rtol=5e-4)


def test_pressure_ratio_is_thesis_eq_1() -> None:
    # Eq. 1 as printed, (1 + g M1^2)/(1 + g M2^2), with M2 from Eq. 3.
    m1 = np.linspace(1.0, 6.0, 11)
    m2 = gd.normal_shock_mach(m1)
    np.testing.assert_allclose(
        gd.normal_shock_pressure_ratio(m1), (1 + 1.4 * m1**2) / (1 + 1.4 * m2**2), rtol=1e-13
    )


def test_scalars_give_floats_and_broadcasting() -> None:
    assert type(gd.normal_shock_mach(2.0)) is float
    assert type(gd.area_ratio(2.0)) is float
    assert type(gd.fanno_fld(2.0)) is float
    out = gd.normal_shock_pressure_ratio(np.array([[2.0], [3.0]]), np.array([1.3, 1.4, 5 / 3]))
    assert out.shape == (2, 3)
    assert out[0, 1] == pytest.approx(4.5)
    # p2/p1 -> (2g M^2 - (g-1))/(g+1); for g = 5/3, M = 2: (26.667 - 0.667)/2.667 = 4.75
    assert out[0, 2] == pytest.approx(4.75)


def test_normal_shock_identity_at_mach_one() -> None:
    s = gd.normal_shock(1.0)
    for value in (s.mach2, s.pressure_ratio, s.density_ratio, s.stagnation_pressure_ratio):
        assert value == pytest.approx(1.0)


@settings(max_examples=200, deadline=None)
@given(
    mach=st.floats(min_value=1.001, max_value=50.0),
    gamma=st.floats(min_value=1.01, max_value=5.0 / 3.0),
)
def test_normal_shock_invariants(mach: float, gamma: float) -> None:
    s = gd.normal_shock(mach, gamma)
    assert s.mach2 < 1.0
    assert s.stagnation_pressure_ratio <= 1.0
    assert s.pressure_ratio > 1.0 and s.temperature_ratio > 1.0
    assert 1.0 < s.density_ratio < (gamma + 1) / (gamma - 1)
    # The relation is its own inverse: the shock that takes M2 back gives M1.
    m1sq = (2 / (gamma - 1) + s.mach2**2) / (2 * gamma / (gamma - 1) * s.mach2**2 - 1)
    assert math.sqrt(m1sq) == pytest.approx(mach, rel=1e-9)


def test_pressure_force_table_1() -> None:
    # Hand: pi (4.72e-3)^2 = 6.99903e-5 m^2; P2 - P1 = 0.099e6 (10.3333 - 1)
    # = 9.2400e5 Pa; F_p = 64.671 N.
    f = gd.pressure_force(3.0, 0.099e6, 4.72e-3)
    assert f == pytest.approx(64.671, abs=1e-3)
    assert gd.flight_pressure_force(3.0, p1=0.099e6, bore_radius=4.72e-3) == f


def test_flight_pressure_force_from_altitude() -> None:
    f0 = gd.flight_pressure_force(3.0, altitude_m=0.0, bore_radius=4.72e-3)
    # Sea level 101325 Pa instead of 0.099 MPa scales F_p by 1.02348.
    assert f0 == pytest.approx(64.671 * 101325 / 99000, rel=1e-4)
    f = gd.flight_pressure_force(
        np.array([2.0, 3.0]), altitude_m=[0.0, 10_000.0], bore_radius=4.72e-3
    )
    assert f.shape == (2,) and f[1] < f0


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({}, "altitude_m"),
        ({"altitude_m": 0.0, "p1": 1e5}, "altitude_m"),
        ({"altitude_m": 90_000.0}, "altitude_m"),
        ({"p1": -1.0}, "p1"),
    ],
)
def test_flight_pressure_force_bad_input(kwargs: dict, field: str) -> None:
    with pytest.raises(InputError) as err:
        gd.flight_pressure_force(3.0, bore_radius=4.72e-3, **kwargs)
    assert err.value.field == field


# ---------------------------------------------------------------------------
# isentropic area ratio and Kantrowitz-Donaldson


@pytest.mark.parametrize("mach", sorted(NACA_AREA_RATIO))
def test_area_ratio_matches_naca_1135(mach: float) -> None:
    assert gd.area_ratio(mach) == pytest.approx(NACA_AREA_RATIO[mach], rel=5e-5)
    branch = "subsonic" if mach < 1 else "supersonic"
    assert gd.mach_from_area_ratio(NACA_AREA_RATIO[mach], branch=branch) == pytest.approx(
        mach, rel=1e-4
    )


@settings(max_examples=200, deadline=None)
@given(
    mach=st.floats(min_value=0.02, max_value=0.999),
    gamma=st.floats(min_value=1.05, max_value=5.0 / 3.0),
)
def test_area_ratio_inverse_subsonic(mach: float, gamma: float) -> None:
    ratio = gd.area_ratio(mach, gamma)
    assert gd.mach_from_area_ratio(ratio, gamma, "subsonic") == pytest.approx(mach, rel=1e-9)


@settings(max_examples=200, deadline=None)
@given(
    mach=st.floats(min_value=1.001, max_value=20.0),
    gamma=st.floats(min_value=1.05, max_value=5.0 / 3.0),
)
def test_area_ratio_inverse_supersonic(mach: float, gamma: float) -> None:
    ratio = gd.area_ratio(mach, gamma)
    assert gd.mach_from_area_ratio(ratio, gamma) == pytest.approx(mach, rel=1e-9)


def test_swallow_area_ratio_is_eq_2() -> None:
    # Eq. 2 = A/A*(M2) = A/A*(M1) p02/p01; from the NACA values at M1 = 2:
    # 1.6875 * 0.7209 = 1.2165 (hand: A/A* at M2 = 0.57735 is
    # 1.73205 * (1.066667/1.2)^3 = 1.73205 * 0.70233 = 1.21649).
    assert gd.swallow_area_ratio(2.0) == pytest.approx(1.6875 * 0.7209, rel=1e-4)
    # Eq. 4 is the isentropic value at M1 itself.
    assert gd.regurgitate_area_ratio(3.0) == pytest.approx(4.2346, rel=5e-5)


def test_swallow_limit() -> None:
    # Hand: M2 -> sqrt(0.4/2.8) = 0.377964; A/A* = 2.645751 * (1.028571/1.2)^3
    # = 2.645751 * 0.629738 = 1.66613 (not 1.65).
    assert gd.swallow_area_ratio_limit() == pytest.approx(1.66613, abs=1e-5)
    assert gd.swallow_area_ratio(1e6) == pytest.approx(gd.swallow_area_ratio_limit(), rel=1e-9)


def test_start_and_unstart_mach() -> None:
    # Constant-area bore: starts (and stays started) at any supersonic Mach.
    assert gd.start_mach(1.0) == 1.0
    assert gd.unstart_mach(1.0) == 1.0
    # Inverse of Eq. 4 at the NACA value 1.6875 is M1 = 2; of Eq. 2 at 1.2165 also.
    assert gd.unstart_mach(1.6875) == pytest.approx(2.0, rel=1e-9)
    assert gd.start_mach(1.6875 * 0.7209) == pytest.approx(2.0, abs=2e-3)
    ratios = np.array([1.1, 1.2, 1.4, 1.6])
    start, unstart = gd.start_mach(ratios), gd.unstart_mach(ratios)
    assert np.all(start > unstart)  # hysteresis: start needs more Mach
    assert np.all(np.diff(start) > 0)


@settings(max_examples=100, deadline=None)
@given(mach=st.floats(min_value=1.01, max_value=30.0))
def test_start_mach_inverts_eq_2(mach: float) -> None:
    assert gd.start_mach(gd.swallow_area_ratio(mach)) == pytest.approx(mach, rel=1e-6)


def test_start_mach_above_limit_raises() -> None:
    with pytest.raises(InputError, match="never self-starts") as err:
        gd.start_mach(1.7)
    assert err.value.field == "area_ratio"
    with pytest.raises(InputError, match=r"element \[1\]"):
        gd.start_mach([1.2, 1.67, 1.8])
    # The limit itself is only reached as M1 -> infinity.
    with pytest.raises(InputError):
        gd.start_mach(gd.swallow_area_ratio_limit())


# ---------------------------------------------------------------------------
# Fanno flow and friction


@pytest.mark.parametrize("mach", sorted(FANNO_TABLE))
def test_fanno_matches_table(mach: float) -> None:
    assert gd.fanno_fld(mach) == pytest.approx(FANNO_TABLE[mach], abs=6e-5)
    branch = "subsonic" if mach < 1 else "supersonic"
    assert gd.fanno_mach(gd.fanno_fld(mach), branch=branch) == pytest.approx(mach, rel=1e-10)


def _fanno_rhs(_xi: float, y: np.ndarray, g: float = 1.4) -> np.ndarray:
    # Fanno ODE: dM^2 / d(f_D x/D) = g M^4 (1 + (g-1)/2 M^2) / (1 - M^2).
    msq = y[0]
    return np.array([g * msq * msq * (1 + 0.5 * (g - 1) * msq) / (1 - msq)])


@pytest.mark.parametrize(("m_in", "m_out"), [(3.0, 1.5), (2.0, 1.1), (0.3, 0.8)])
def test_fanno_closed_form_vs_ode(m_in: float, m_out: float) -> None:
    # Integrate the Fanno ODE over the closed-form length difference between
    # the two Mach numbers; it must arrive at m_out.
    length = gd.fanno_fld(m_in) - gd.fanno_fld(m_out)
    sol = solve_ivp(_fanno_rhs, (0.0, length), [m_in**2], rtol=1e-11, atol=1e-13)
    assert sol.success
    assert math.sqrt(sol.y[0, -1]) == pytest.approx(m_out, rel=1e-7)


@pytest.mark.parametrize("mach", [0.2, 0.7, 1.41, 2.0, 5.0])
def test_fanno_closed_form_vs_quadrature_to_sonic(mach: float) -> None:
    # The same ODE inverted, d(f_D x/D)/dM^2, is regular at M = 1.
    def dxi(msq: float) -> float:
        return (1 - msq) / (1.4 * msq * msq * (1 + 0.2 * msq))

    xi, _ = quad(dxi, mach**2, 1.0, epsabs=1e-13, epsrel=1e-12)
    assert gd.fanno_fld(mach) == pytest.approx(xi, rel=1e-9, abs=1e-13)


@settings(max_examples=150, deadline=None)
@given(
    fld=st.floats(min_value=1e-6, max_value=0.8),
    gamma=st.floats(min_value=1.1, max_value=5.0 / 3.0),
)
def test_fanno_inverse_both_branches(fld: float, gamma: float) -> None:
    if fld < gd.fanno_fld_limit(gamma):
        m = gd.fanno_mach(fld, gamma)
        assert m > 1 and gd.fanno_fld(m, gamma) == pytest.approx(fld, rel=1e-8)
    m = gd.fanno_mach(fld, gamma, branch="subsonic")
    assert m < 1 and gd.fanno_fld(m, gamma) == pytest.approx(fld, rel=1e-8)


def test_fanno_limit_and_errors() -> None:
    # Hand: (2.4/2.8) ln 6 - 1/1.4 = 0.857143 * 1.791759 - 0.714286 = 0.821508.
    assert gd.fanno_fld_limit() == pytest.approx(0.821508, abs=1e-6)
    with pytest.raises(InputError, match="supersonic Fanno limit"):
        gd.fanno_mach(0.9)
    assert gd.fanno_mach(0.9, branch="subsonic") < 1
    assert gd.fanno_mach(0.0) == 1.0
    with pytest.raises(InputError) as err:
        gd.fanno_mach(0.1, branch="transonic")
    assert err.value.field == "branch"


def test_thesis_fld_check() -> None:
    # Thesis: f L/D = 0.102 corresponds to M ~ 1.41 (Ref. 10, Appendix E).
    assert gd.fanno_mach(0.102) == pytest.approx(1.41, abs=0.01)
    # and f_D L*/D at 1.41 is about 0.103 (hand: M^2 = 1.9881;
    # -0.98810/2.78334 + 0.85714 ln(4.77144/2.79524) = -0.35501 + 0.45834 = 0.10333).
    assert gd.fanno_fld(1.41) == pytest.approx(0.1033, abs=2e-4)


def test_friction_factor_moody_values() -> None:
    # Moody chart / Colebrook, smooth pipe: Re = 1e5 -> 0.0180, Re = 1e6 -> 0.0117;
    # eps/D = 0.001, Re = 1e6 -> 0.0199.
    assert gd.colebrook_friction_factor(1e5) == pytest.approx(0.0180, rel=5e-3)
    assert gd.colebrook_friction_factor(1e6) == pytest.approx(0.0117, rel=5e-3)
    assert gd.colebrook_friction_factor(1e6, 0.001) == pytest.approx(0.0199, rel=5e-3)


@settings(max_examples=100, deadline=None)
@given(re=st.floats(min_value=3e3, max_value=1e8), eps=st.floats(min_value=0.0, max_value=0.05))
def test_colebrook_residual_and_haaland_agreement(re: float, eps: float) -> None:
    f = gd.colebrook_friction_factor(re, eps)
    lhs = 1 / math.sqrt(f)
    rhs = -2 * math.log10(eps / 3.7 + 2.51 / (re * math.sqrt(f)))
    assert lhs == pytest.approx(rhs, rel=1e-10)
    assert gd.haaland_friction_factor(re, eps) == pytest.approx(f, rel=0.03)


def test_friction_factor_vectorised_and_errors() -> None:
    f = gd.friction_factor(np.array([4e5, 6e5]))
    assert f.shape == (2,) and f[0] > f[1]
    for bad in (0.0, -1e5, 100.0):
        with pytest.raises(InputError) as err:
            gd.friction_factor(bad)
        assert err.value.field == "reynolds"
    with pytest.raises(InputError) as err:
        gd.friction_factor(1e5, correlation="moody")
    assert err.value.field == "correlation"
    with pytest.raises(InputError) as err:
        gd.friction_factor(1e5, relative_roughness=-0.1)
    assert err.value.field == "relative_roughness"


# ---------------------------------------------------------------------------
# thesis choking iteration


def test_choking_first_estimate() -> None:
    # Thesis: f read as 0.01275, L/D = 8 -> f L/D = 0.102 -> M ~ 1.41.
    assert gd.choking_mach(8.0, friction_factor=0.01275, iterations=0) == pytest.approx(
        1.41, abs=0.01
    )
    # With Colebrook's own f at the midpoint Re = 5e5 and Table 1's L/D = 8.07.
    assert gd.choking_mach(76.2 / 9.44, iterations=0) == pytest.approx(1.41, abs=0.01)


def test_choking_one_iteration() -> None:
    # Thesis: "After one iteration the Mach number increases to M = 1.44."
    for ld in (8.0, 76.2 / 9.44):
        assert gd.choking_mach(ld, iterations=1) == pytest.approx(1.44, abs=0.02)
    steps = gd.choking_history(8.07, 5e5, iterations=3)
    assert [s.iteration for s in steps] == [0, 1, 2, 3]
    assert steps[1].reynolds == pytest.approx(5e5 * steps[0].mach / 2.5)
    assert steps[1].mach > steps[0].mach  # the thesis: iterating raises M
    assert steps[3].mach == pytest.approx(steps[2].mach, abs=1e-3)


def test_choking_freestream_converged() -> None:
    m = gd.choking_mach_freestream(76.2 / 9.44, 9.44e-3)
    assert m == pytest.approx(1.44, abs=0.01)
    # It is a fixed point of the Fanno/friction map.
    re = gd.freestream_reynolds(m, 9.44e-3, 0.0)
    assert gd.fanno_fld(m) == pytest.approx(gd.friction_factor(re) * 76.2 / 9.44, rel=1e-9)
    # Shorter bore -> lower choking Mach.
    assert gd.choking_mach_freestream(4.0, 9.44e-3) < m


def test_freestream_reynolds_sea_level() -> None:
    # Hand: 1.225 * 340.294 * 9.44e-3 / 1.7894e-5 = 2.1991e5 per unit Mach.
    assert gd.freestream_reynolds(1.0, 9.44e-3) == pytest.approx(2.1991e5, rel=2e-4)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"l_over_d": 0.0}, "l_over_d"),
        ({"l_over_d": -8.0}, "l_over_d"),
        ({"l_over_d": 8.0, "reynolds": 0.0}, "reynolds"),
        ({"l_over_d": 8.0, "reynolds": -5e5}, "reynolds"),
        ({"l_over_d": 8.0, "iterations": -1}, "iterations"),
        ({"l_over_d": 8.0, "iterations": 1.5}, "iterations"),
        ({"l_over_d": 8.0, "gamma": 1.0}, "gamma"),
        ({"l_over_d": 80.0}, "l_over_d"),  # f L/D > 0.82: chokes at every Mach
    ],
)
def test_choking_bad_input(kwargs: dict, field: str) -> None:
    with pytest.raises(InputError) as err:
        gd.choking_mach(**kwargs)
    assert err.value.field == field


def test_choking_freestream_low_reynolds_raises() -> None:
    with pytest.raises(InputError, match="turbulent"):
        gd.choking_mach_freestream(8.0, 1e-5, altitude_m=40_000.0)


# ---------------------------------------------------------------------------
# input validation


@pytest.mark.parametrize(
    ("func", "args", "field"),
    [
        (gd.normal_shock_mach, (0.5,), "mach"),
        (gd.normal_shock_mach, (-2.0,), "mach"),
        (gd.normal_shock_mach, (float("nan"),), "mach"),
        (gd.normal_shock_mach, (2.0, 1.0), "gamma"),
        (gd.normal_shock_mach, (2.0, 0.9), "gamma"),
        (gd.area_ratio, (0.0,), "mach"),
        (gd.area_ratio, ("fast",), "mach"),
        (gd.fanno_fld, (-1.0,), "mach"),
        (gd.fanno_mach, (-0.1,), "fld"),
        (gd.mach_from_area_ratio, (0.9,), "area_ratio"),
        (gd.start_mach, (0.5,), "area_ratio"),
        (gd.regurgitate_area_ratio, (0.8,), "mach"),
        (gd.pressure_force, (3.0, -1.0, 4.72e-3), "p1"),
        (gd.pressure_force, (3.0, 1e5, 0.0), "bore_radius"),
        (gd.pressure_force, (0.8, 1e5, 4.72e-3), "mach"),
    ],
)
def test_bad_input_raises_input_error(func, args, field: str) -> None:
    with pytest.raises(InputError) as err:
        func(*args)
    assert err.value.field == field
    assert "allowed range" in str(err.value) or "expected a number" in str(err.value)


def test_array_reports_first_offending_value() -> None:
    with pytest.raises(InputError, match=r"mach: element \[2\]: 0\.5 is outside") as err:
        gd.normal_shock_mach([2.0, 3.0, 0.5, 0.2])
    assert "[1, 1e+06]" in str(err.value)


def test_shapes_that_do_not_broadcast() -> None:
    with pytest.raises(InputError, match="broadcast"):
        gd.normal_shock([2.0, 3.0], [1.3, 1.4, 1.5])


@given(
    st.lists(st.floats(0.0, 0.8), min_size=2, max_size=4),
    st.lists(st.floats(3000.0, 1e7), min_size=2, max_size=4),
    st.lists(st.floats(1.0, 50.0), min_size=2, max_size=4),
)
@settings(max_examples=40, deadline=None)
def test_scalar_inversions_are_the_array_elements_to_the_bit(fld, reynolds, ratio) -> None:
    """One element is solved without np.vectorize (the flight studies' per-segment calls);
    the value is the array path's element, bit for bit, and a Python float."""
    cases = [
        (lambda x: gd.fanno_mach(x), fld),
        (lambda x: gd.fanno_mach(3.0 * x, 1.3, "subsonic"), fld),
        (lambda x: gd.colebrook_friction_factor(x, 1e-3), reynolds),
        (lambda x: gd.mach_from_area_ratio(x, 1.4, "subsonic"), ratio),
        (lambda x: gd.mach_from_area_ratio(x), ratio),
    ]
    for f, xs in cases:
        arr = f(np.array(xs))
        for k, x in enumerate(xs):
            one = f(x)
            assert type(one) is float and one == arr[k]
