"""Mass properties of the bored ball (thesis Eqs. 6-12, p. 77; SPEC section 2)."""

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import quad

from obturator import BoredBall, InputError

TABLE1 = {"radius": 7.899e-3, "hole_radius": 4.72e-3, "density": 7669.6}


def test_table1_inertias_match_spec_values():
    # SPEC section 2: Table 1 inputs give C = 3.128e-7, A = 2.219e-7 kg m^2 (thesis prints
    # 3.125e-7 and 2.216e-7), lambda = 0.41, W = 0.0800 N (measured 0.0798-0.07987 N).
    b = BoredBall(**TABLE1)
    assert b.axial_inertia == pytest.approx(3.128e-7, rel=1e-3)
    assert b.transverse_inertia == pytest.approx(2.219e-7, rel=1e-3)
    assert b.axial_inertia == pytest.approx(3.125e-7, rel=2e-3)  # thesis Table 1 print
    assert b.transverse_inertia == pytest.approx(2.216e-7, rel=2e-3)
    assert b.inertia_ratio == pytest.approx(0.41, abs=0.005)
    assert b.weight == pytest.approx(0.0800, abs=0.00005)
    # beta_s from the Table 1 radii: 36.694 deg (SPEC section 3)
    assert math.degrees(b.opening_angle) == pytest.approx(36.694, abs=5e-4)


def test_volume_equals_thesis_cap_formula():
    # Thesis p. 77: V = 2 pi R cos(beta) [R^2 (1 - cos^2 beta / 3) - r_p^2] (independent form)
    b = BoredBall(**TABLE1)
    r, rp = TABLE1["radius"], TABLE1["hole_radius"]
    cb = math.cos(math.asin(rp / r))
    v_thesis = 2 * math.pi * r * cb * (r**2 * (1 - cb**2 / 3) - rp**2)
    assert b.volume == pytest.approx(v_thesis, rel=1e-12)


def test_solid_sphere_limit():
    # r_s = 0: C = A = (2/5) m R^2, m = (4/3) pi R^3 rho (closed form)
    b = BoredBall(0.01, 0.0, 7800.0)
    m = 4 / 3 * math.pi * 0.01**3 * 7800
    assert b.mass == pytest.approx(m, rel=1e-12)
    assert b.axial_inertia == pytest.approx(0.4 * m * 0.01**2, rel=1e-12)
    assert b.transverse_inertia == pytest.approx(0.4 * m * 0.01**2, rel=1e-12)
    assert b.inertia_ratio == pytest.approx(0.0, abs=1e-12)


@given(
    radius=st.floats(1e-3, 0.1),
    frac=st.floats(0.0, 0.7),
    density=st.floats(100.0, 20000.0),
)
def test_shell_integrals_by_quadrature(radius, frac, density):
    # Independent check: integrate the thin-shell expressions of Eqs. (7)-(8) numerically.
    r = frac * radius
    b = BoredBall(radius, r, density)

    def h(x):
        return math.sqrt(max(radius**2 - x**2, 0.0))

    def dm(x):
        return 4 * math.pi * density * x * h(x)

    kw = {"epsabs": 0.0, "epsrel": 1e-12, "limit": 200}
    m = quad(dm, r, radius, **kw)[0]
    c = quad(lambda x: x**2 * dm(x), r, radius, **kw)[0]
    a = quad(lambda x: (x**2 / 2 + h(x) ** 2 / 3) * dm(x), r, radius, **kw)[0]
    assert b.mass == pytest.approx(m, rel=1e-7)
    assert b.axial_inertia == pytest.approx(c, rel=1e-7)
    assert b.transverse_inertia == pytest.approx(a, rel=1e-7)
    assert b.axial_inertia >= b.transverse_inertia * (1 - 1e-12)  # lambda >= 0


@pytest.mark.parametrize(
    ("kwargs", "field", "fragment"),
    [
        ({"density": -1.0}, "density", "(0, inf)"),
        ({"density": 0.0}, "density", "(0, inf)"),
        ({"hole_radius": 7.899e-3}, "hole_radius", "R_s/sqrt(2)"),
        ({"hole_radius": 7.899e-3 / math.sqrt(2)}, "hole_radius", "R_s/sqrt(2)"),
        ({"hole_radius": -1e-3}, "hole_radius", "[0, inf)"),
        ({"radius": 0.0}, "radius", "(0, inf)"),
        ({"density": float("nan")}, "density", "(0, inf)"),
        # positive but so small that A underflows below the smallest normal double
        ({"density": 1e-300}, "density", "allowed at this size: >= "),
        ({"radius": 1e-70, "hole_radius": 0.0}, "radius", "allowed at this density: above"),
    ],
)
def test_bad_geometry_is_rejected_with_field_and_range(kwargs, field, fragment):
    with pytest.raises(InputError) as err:
        BoredBall(**{**TABLE1, **kwargs})
    assert err.value.field == field
    assert str(err.value).startswith(field + ":")
    assert fragment in str(err.value)


def test_inertia_floor_is_the_smallest_normal_double():
    """The density the refusal names as the bound is accepted (A >= the smallest normal
    double, 2.2e-308 kg m^2: a closed-form floor, IEEE 754), just below it is refused."""
    import re
    import sys

    with pytest.raises(InputError) as err:
        BoredBall(**{**TABLE1, "density": 1e-300})
    bound = float(re.search(r">= ([0-9.e+-]+) kg/m\^3", str(err.value)).group(1))
    ball = BoredBall(**{**TABLE1, "density": bound * 1.01})
    assert ball.transverse_inertia >= sys.float_info.min
    with pytest.raises(InputError):
        BoredBall(**{**TABLE1, "density": bound * 0.98})


@pytest.mark.parametrize("value", [0.0, 1e-320, -1.0])
def test_projectile_inertia_below_the_smallest_normal_double_is_refused(value):
    """Free spin divides by I_p: from the smallest normal double on (IEEE 754)."""
    import sys
    from dataclasses import replace

    from obturator.model.cases import rig_case

    case = rig_case(300.0, 0.5, spin_mode="free")
    with pytest.raises(InputError, match=r"^projectile_inertia: .* allowed range \[2\.22507e-308"):
        replace(case, projectile_inertia=value)
    assert replace(case, projectile_inertia=sys.float_info.min).projectile_inertia > 0.0
