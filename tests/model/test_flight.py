"""Flight case: Mach and altitude enter through the normal bow shock (Eqs. 1, 3, 43)."""

import numpy as np
import pytest

from obturator import SolverOptions, flight_case, opening_time
from obturator.flow import pressure_force

MACH = [1.5, 2.0, 3.0, 4.0]


@pytest.fixture(scope="module")
def sweep():
    cases = [flight_case(mach=m, altitude_m=0.0) for m in MACH]
    return cases, np.array([opening_time(c) for c in cases])


def test_pressure_force_is_the_normal_shock_load(sweep):
    cases, _ = sweep
    for m, c in zip(MACH, cases, strict=True):
        expected = pressure_force(m, 101325.0, 4.72e-3)
        assert c.torque.friction.pressure_force == pytest.approx(expected, rel=1e-9)


def test_opening_time_inverse_to_friction_moment(sweep):
    # Eq. (93) at high spin: t_cr ~ T2 omega_p with T2 ~ A/(M sin theta0): t_cr * F_p const.
    cases, t = sweep
    f = np.array([c.torque.friction.pressure_force for c in cases])
    assert np.all(np.diff(t) < 0)
    prod = t * f
    assert np.ptp(prod) / prod.mean() < 0.03


def test_mach_sweep_converged(sweep):
    cases, t = sweep
    for c, t0 in zip(cases, t, strict=True):
        t1 = opening_time(c, SolverOptions().tighter(10.0))
        t2 = opening_time(c, SolverOptions(friction_width=1e-7))
        assert abs(t1 - t0) / t0 < 1e-3 and abs(t2 - t0) / t0 < 1e-3


def test_altitude_lowers_the_load_and_delays_opening():
    t0 = opening_time(flight_case(mach=3.0, altitude_m=0.0))
    t10 = opening_time(flight_case(mach=3.0, altitude_m=10_000.0))
    # p(10 km)/p(0) = 0.2615 (US 1976): the load falls ~4x and t_cr grows ~4x
    assert t10 / t0 == pytest.approx(1 / 0.2615, rel=0.05)


def test_flight_case_takes_its_stop_angle_as_a_replaced_case_has_it():
    """theta_cr given to the factory: the same case as built and then replaced (what the
    flight studies did per segment), and the same refusal of an angle at or above theta_0."""
    import math

    from obturator.errors import InputError

    kw = dict(pressure_force=812.5, t_max=0.002)
    built = flight_case(9000.0, 0.35, theta_cr=0.31, **kw)
    assert built == flight_case(9000.0, 0.35, **kw).with_(theta_cr=0.31)
    assert built.opening_angle == 0.31 and flight_case(9000.0, 0.35, **kw).theta_cr is None
    with pytest.raises(InputError, match=r"^theta_cr: .* is outside the allowed range \[0, "):
        flight_case(9000.0, 0.35, theta_cr=math.radians(88.0), **kw)
