"""Tests of obturator.atmosphere against the U.S. Standard Atmosphere 1976 tables.

Reference values are the published 1976 tables (NOAA-S/T 76-1562): Table 4
(layer bases, geopotential) and Table I (geometric altitude). Note that
5474.9 Pa belongs to geopotential 20 km (geometric 20.063 km); at geometric
20 km the table gives 5529.3 Pa, and 0.088910 kg/m^3 is the density there.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from obturator.errors import InputError
from obturator.flow.atmosphere import (
    geometric_altitude,
    geopotential_altitude,
    mach_from_velocity,
    standard_atmosphere,
    sutherland_viscosity,
)


def test_sea_level() -> None:
    a = standard_atmosphere(0.0)
    assert a.pressure == 101325.0
    assert a.temperature == 288.15
    assert a.density == pytest.approx(1.2250, rel=1e-4)
    assert a.speed_of_sound == pytest.approx(340.29, abs=0.005)
    assert a.dynamic_viscosity == pytest.approx(1.7894e-5, rel=1e-4)
    assert a.kinematic_viscosity == pytest.approx(1.4607e-5, rel=2e-4)
    assert all(type(v) is float for v in (a.pressure, a.density, a.speed_of_sound))


# Geometric altitude [m]: (T [K], P [Pa], rho [kg/m^3]) from the 1976 table.
# Hand check at 20 km: H = 6356766*20000/6376766 = 19937.3 m'; isothermal from
# 11 km': P = 22632.06 exp(-0.0341632 * 8937.3/216.65) = 22632.06 * 0.24431
# = 5529.3; rho = 5529.3/(287.053 * 216.65) = 0.088910.
GEOMETRIC_TABLE = {
    11_000.0: (216.774, 22700.0, 0.36480),
    20_000.0: (216.650, 5529.3, 0.088910),
    30_000.0: (226.509, 1197.0, 0.018410),
    50_000.0: (270.650, 79.779, 1.0269e-3),
    86_000.0: (186.87, 0.37338, 6.958e-6),
}


@pytest.mark.parametrize("z", sorted(GEOMETRIC_TABLE))
def test_geometric_table(z: float) -> None:
    t, p, rho = GEOMETRIC_TABLE[z]
    a = standard_atmosphere(z)
    assert a.temperature == pytest.approx(t, abs=0.005)
    assert a.pressure == pytest.approx(p, rel=5e-5)
    assert a.density == pytest.approx(rho, rel=1e-4)


# Layer bases (geopotential m'): (T_b, P_b) from the 1976 standard, Table 4.
BASES = {
    11_000.0: (216.65, 22632.06),
    20_000.0: (216.65, 5474.889),
    32_000.0: (228.65, 868.0187),
    47_000.0: (270.65, 110.9063),
    51_000.0: (270.65, 66.93887),
    71_000.0: (214.65, 3.956420),
}


@pytest.mark.parametrize("h", sorted(BASES))
def test_layer_bases(h: float) -> None:
    t, p = BASES[h]
    a = standard_atmosphere(geometric_altitude(h))
    assert a.temperature == pytest.approx(t, abs=1e-9)
    assert a.pressure == pytest.approx(p, rel=2e-6)
    assert a.geopotential_m == pytest.approx(h, abs=1e-6)


def test_brief_values_11_and_20_km() -> None:
    # 11 km geopotential is ~11.019 km geometric.
    z11 = geometric_altitude(11_000.0)
    assert z11 == pytest.approx(11_019.07, abs=0.01)
    assert standard_atmosphere(z11).pressure == pytest.approx(22632.0, abs=0.5)
    # 20 km geopotential: 5474.9 Pa, 0.088035 kg/m^3 (hand: 5474.889/(287.053*216.65)).
    a = standard_atmosphere(geometric_altitude(20_000.0))
    assert a.pressure == pytest.approx(5474.9, abs=0.05)
    assert a.density == pytest.approx(0.088035, rel=1e-4)
    b = standard_atmosphere(20_000.0)
    assert (b.temperature, b.density) == (pytest.approx(216.65), pytest.approx(0.08891, rel=1e-4))


def test_speed_of_sound_and_viscosity_at_86_km() -> None:
    # The standard takes a from the molecular-scale temperature (186.946 K) and
    # mu from the kinetic one (186.87 K); table: a = 274.10 m/s.
    a = standard_atmosphere(86_000.0)
    assert a.speed_of_sound == pytest.approx(274.10, abs=0.01)
    assert a.dynamic_viscosity == pytest.approx(sutherland_viscosity(a.temperature))


def test_continuous_across_layer_bases() -> None:
    for h in BASES:
        z = geometric_altitude(h)
        lo, hi = standard_atmosphere([z - 1e-6, z + 1e-6]).pressure
        assert lo == pytest.approx(hi, rel=1e-9)


@settings(max_examples=100, deadline=None)
@given(z=st.floats(min_value=0.0, max_value=85_999.0), dz=st.floats(min_value=1.0, max_value=1e4))
def test_pressure_decreases_and_is_hydrostatic(z: float, dz: float) -> None:
    z2 = min(z + dz, 86_000.0)
    a, b = standard_atmosphere(z), standard_atmosphere(z2)
    assert b.pressure < a.pressure
    # Geopotential round trip.
    assert geometric_altitude(geopotential_altitude(z)) == pytest.approx(z, abs=1e-6)


def test_vectorised_shapes() -> None:
    z = np.array([[0.0, 5000.0], [10_000.0, 20_000.0]])
    a = standard_atmosphere(z)
    assert a.pressure.shape == (2, 2)
    assert a.pressure[1, 1] == pytest.approx(5529.3, rel=5e-5)


def test_mach_from_velocity() -> None:
    assert mach_from_velocity(340.2941, 0.0) == pytest.approx(1.0, rel=1e-6)
    m = mach_from_velocity([1020.88, 885.21], [0.0, 20_000.0])
    np.testing.assert_allclose(m, [3.0, 3.0], rtol=1e-4)
    with pytest.raises(InputError) as err:
        mach_from_velocity(-1.0, 0.0)
    assert err.value.field == "v"


@given(st.lists(st.floats(0.0, 86_000.0), min_size=1, max_size=5))
@settings(max_examples=60, deadline=None)
def test_one_altitude_is_the_array_path_to_the_bit_asked_twice(zs: list[float]) -> None:
    """A scalar altitude is memoised; its record equals the array computation's element to
    the bit (an independent path through the same formulas), the first call and the
    memoised second alike, for -0.0 too."""
    arr = standard_atmosphere(np.array(zs))
    for k, z in enumerate(zs):
        for _ in range(2):
            one = standard_atmosphere(z)
            for name in ("geopotential_m", "temperature", "pressure", "density"):
                assert getattr(one, name) == getattr(arr, name)[k]
            assert isinstance(one.pressure, float)
    neg = standard_atmosphere(-0.0)
    assert str(neg.altitude_m) == "-0.0" and str(standard_atmosphere(0.0).altitude_m) == "0.0"
    assert standard_atmosphere(1000) == standard_atmosphere(1000.0)  # an int is its float


@pytest.mark.parametrize("bad", [-1.0, 86_000.5, 1e6, float("nan"), float("inf"), "high"])
def test_altitude_out_of_range(bad: object) -> None:
    with pytest.raises(InputError) as err:
        standard_atmosphere(bad)
    assert err.value.field == "altitude_m"


def test_array_altitude_names_first_offender() -> None:
    with pytest.raises(InputError, match=r"element \[1\]: -5 m is outside the allowed range"):
        standard_atmosphere([1000.0, -5.0, 90_000.0])


def test_sutherland_rejects_nonpositive_temperature() -> None:
    with pytest.raises(InputError) as err:
        sutherland_viscosity(0.0)
    assert err.value.field == "temperature"
