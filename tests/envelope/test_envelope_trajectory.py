"""Point-mass trajectory: closed forms (vacuum, constant-C_D flat fire), energy balance, inputs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from obturator.envelope.drag import TUBULAR_OPEN, ClosedInletDrag, DragTable, drag_model
from obturator.envelope.trajectory import TABLE1_TWIST, Launch, Projectile, fly
from obturator.errors import InputError

# Sea-level air of the 1976 standard from its defining constants (independent of the code)
R_AIR = 8.31432 / 0.0289644
RHO0 = 101_325.0 / (R_AIR * 288.15)
A0 = math.sqrt(1.4 * R_AIR * 288.15)


def test_vacuum_is_a_parabola():
    proj = Projectile(drag=DragTable.constant(0.0), roll_damping=0.0)
    launch = Launch(mach=2.0, elevation_deg=30.0, spin_rate=10_000.0)
    tr = fly(proj, launch, t_end=0.5)
    t = np.linspace(0.0, 0.5, 11)
    v0, e, g = 2.0 * A0, math.radians(30.0), 9.80665
    y = tr.state(t)
    np.testing.assert_allclose(y[0], v0 * math.cos(e) * t, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(y[1], v0 * math.sin(e) * t - 0.5 * g * t**2, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(y[4], 10_000.0, rtol=1e-12)
    # energy: kinetic + potential constant
    np.testing.assert_allclose(tr.energy(t), tr.energy(0.0), rtol=1e-10)


def test_flat_fire_constant_cd_closed_forms():
    """g = 0, horizontal, constant C_D: V = V0/(1 + k V0 t), V(x) = V0 exp(-k x), spin exp(c x)."""
    cd, clp = 0.4, -0.02
    proj = Projectile(drag=DragTable.constant(cd), roll_damping=clp)
    launch = Launch(mach=3.0, gravity=0.0, spin_rate=12_000.0)
    tr = fly(proj, launch, t_end=0.3)
    r_p, m, ip = 9.96e-3, 0.141, 8.58e-6
    s, d = math.pi * r_p**2, 2 * r_p
    k = RHO0 * s * cd / (2 * m)
    v0 = 3.0 * A0
    t = np.linspace(0.0, 0.3, 7)
    x = tr.state(t)[0]
    np.testing.assert_allclose(tr.velocity(t), v0 / (1.0 + k * v0 * t), rtol=1e-8)
    np.testing.assert_allclose(x, np.log1p(k * v0 * t) / k, rtol=1e-8)
    np.testing.assert_allclose(tr.velocity(t), v0 * np.exp(-k * x), rtol=1e-8)
    c = 0.5 * RHO0 * s * d * d * clp / ip
    np.testing.assert_allclose(tr.spin_rate(t), 12_000.0 * np.exp(c * x), rtol=1e-8)
    np.testing.assert_allclose(tr.state(t)[1], 0.0, atol=1e-12)


def test_energy_balance_with_drag_and_gravity():
    tr = fly(Projectile(), Launch(mach=2.5, elevation_deg=40.0, altitude_m=1000.0), t_end=0.4)
    for t in (0.1, 0.25, 0.4):
        lost = tr.energy(0.0) - tr.energy(t)
        assert lost > 0
        assert lost == pytest.approx(tr.drag_work(t), rel=1e-7)


def test_flight_quantities_and_twist():
    launch = Launch(mach=3.0)
    # the twist law reproduces Table 1's 12042 rad/s at Mach 3, sea level
    assert launch.muzzle_spin == pytest.approx(12042.0, rel=1e-12)
    assert TABLE1_TWIST / 0.01992 == pytest.approx(26.74, abs=0.01)
    tr = fly(Projectile(), launch, t_end=0.05)
    assert float(tr.mach(0.0)) == pytest.approx(3.0)
    assert float(tr.mach(0.05)) < 3.0  # decelerates
    assert float(tr.spin_rate(0.05)) < 12042.0  # roll damping
    # normal-shock load at the muzzle (thesis Eqs. 1, 3, 43 by hand)
    m = 3.0
    p2p1 = 1.0 + 2.8 / 2.4 * (m * m - 1.0)
    f = math.pi * 4.72e-3**2 * 101_325.0 * (p2p1 - 1.0)
    assert float(tr.pressure_force(0.0, 4.72e-3)) == pytest.approx(f, rel=1e-12)
    ds = tr.to_xarray(11)
    assert set(ds.data_vars) >= {"mach", "pressure", "spin_rate", "velocity"}


def test_goes_subsonic_and_stops():
    tr = fly(Projectile(drag=DragTable.constant(8.0)), Launch(mach=1.05), t_end=5.0)
    assert tr.subsonic and tr.t_end < 5.0
    assert float(tr.mach(tr.t_end)) == pytest.approx(1.0, abs=1e-6)
    with pytest.raises(InputError, match="^t:"):
        tr.mach(tr.t_end + 1.0)


def test_drag_curves():
    assert TUBULAR_OPEN(1.3) > 2 * TUBULAR_OPEN(1.6)  # choked jump (thesis p. 22)
    closed = ClosedInletDrag()
    m = 3.0
    inc = (4.72 / 9.96) ** 2 * 4 * (m * m - 1) / (2.4 * m * m)
    assert closed(m) == pytest.approx(TUBULAR_OPEN(m) + inc, rel=1e-12)
    assert closed(0.9) == TUBULAR_OPEN(0.9)
    assert drag_model("tubular-open") is TUBULAR_OPEN


def test_drag_table_csv(tmp_path):
    p = tmp_path / "cd.csv"
    p.write_text("Mach,CD,comment\n1.0,0.5,a\n2.0,0.3,b\n4.0,0.2,c\n")
    tab = drag_model(str(p))
    assert tab(1.5) == pytest.approx(0.4)
    assert tab(5.0) == pytest.approx(0.2)  # end value held
    bad = tmp_path / "bad.csv"
    bad.write_text("mach,cd\n2.0,0.3\n1.0,0.5\n")
    with pytest.raises(InputError, match="cd_table.mach"):
        DragTable.from_csv(bad)


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"mach": 0.9}, "mach"),
        ({"altitude_m": -5.0}, "altitude_m"),
        ({"elevation_deg": 95.0}, "elevation_deg"),
        ({"temperature_offset_k": -120.0}, "temperature_offset_k"),
        ({"spin_rate": -1.0}, "spin_rate"),
    ],
)
def test_launch_validation(kwargs, field):
    with pytest.raises(InputError, match=f"^{field}:.*allowed range"):
        Launch(**kwargs)


def test_projectile_validation():
    with pytest.raises(InputError, match="^roll_damping:"):
        Projectile(roll_damping=0.1)
    with pytest.raises(InputError, match="^projectile_mass:"):
        Projectile(mass=0.0)
