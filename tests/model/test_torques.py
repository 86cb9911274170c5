"""Torque models (thesis Eqs. 32-34, 39-42, 55, 61, Appendix A) and the exact Coulomb contact."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from obturator import (
    CouetteViscous,
    CoulombContactFriction,
    InputError,
    NakabayashiViscous,
    ThesisFlightFriction,
    ThesisRigFriction,
    TorqueModel,
)
from obturator.core.dynamics import (
    applied_torque,
    friction_speed_factor,
    slip_saturation,
)
from obturator.core.layout import (
    FAMILY_ALGEBRAIC,
    FAMILY_LINEAR,
    FAMILY_TANH,
    N_PARAM,
    P_FAMILY,
    P_SPEED,
    P_WIDTH,
    SPEED_STRENGTHENING,
    SPEED_WEAKENING,
)
from obturator.model.torques import SlipSpeedLaw, hertz_patch_radius

R_S, H, MU_F = 7.899e-3, 5.08e-5, 1.917e-5
FAMILIES = {"algebraic": FAMILY_ALGEBRAIC, "tanh": FAMILY_TANH, "linear": FAMILY_LINEAR}
# The three magnitude shapes written out independently of the compiled kernel.
SHAPES = {
    "algebraic": lambda x: x / math.sqrt(1 + x * x),
    "tanh": math.tanh,
    "linear": lambda x: min(x, 1.0),
}


def torque(model: TorqueModel, w, width=0.0, family="algebraic"):
    p = np.zeros(N_PARAM)
    p[P_WIDTH] = width
    p[8:18] = model.pack()
    p[P_FAMILY] = FAMILIES[family]
    return np.array(applied_torque(w[0], w[1], w[2], p))


def test_nakabayashi_reproduces_table1_shear_constant():
    # Table 1: S = 12.38e-9 N m s is Eq. (42) with eps = h/R_s (SPEC section 2)
    assert NakabayashiViscous(R_S, H, MU_F).coefficient == pytest.approx(12.38e-9, rel=1e-3)


def test_couette_eq34_and_small_gap_limit():
    # Eq. (34) closed form; Eq. (42) -> Eq. (34) as eps -> 0 ("identical for small eps", p. 57)
    s34 = 8 / 3 * math.pi * R_S**4 * MU_F / H
    assert CouetteViscous(R_S, H, MU_F).coefficient == pytest.approx(s34, rel=1e-14)
    # Eq. 42 / Eq. 34 = (1 + eps) exactly, eps = h/R_s: -> 1 at the smallest gap accepted
    tiny = 1e-7
    ratio = (
        NakabayashiViscous(R_S, tiny, MU_F).coefficient
        / CouetteViscous(R_S, tiny, MU_F).coefficient
    )
    assert ratio == pytest.approx(1.0 + tiny / R_S, rel=1e-12)
    with pytest.raises(InputError, match="gap"):
        NakabayashiViscous(R_S, 1e-308, MU_F)  # below the continuum limit (0.1 um)


def test_turbulent_branch_switches_at_eq41():
    v = NakabayashiViscous(R_S, H, MU_F, fluid_density=1.225)
    nu = MU_F / 1.225
    eps = H / R_S
    assert v.transition_reynolds == pytest.approx(70 * eps**-1.6)
    model = TorqueModel(v, None)
    w_lo = 0.99 * v.transition_rate
    w_hi = 1.01 * v.transition_rate
    assert torque(model, (w_lo, 0, 0))[0] == pytest.approx(-v.coefficient * w_lo)
    # Eq. (39) evaluated by hand: M = C_m rho R^5 w^2, C_m = 0.053/eps g Re^-1/4
    re = R_S**2 * w_hi / nu
    cm = 0.053 / eps * (1 + 1.75 * eps) / (1 - 1.5 * eps) * re**-0.25
    assert torque(model, (w_hi, 0, 0))[0] == pytest.approx(-cm * 1.225 * R_S**5 * w_hi**2, rel=1e-9)


def test_thesis_rig_friction_eq61():
    # |M_sg| = mu W R_s sqrt(1 - (w_X/w_r)^2), along -w_r (Eq. 61); exact at zero width
    f = ThesisRigFriction(0.5, 0.08, R_S)
    w = np.array([3.0, -4.0, 12.0])
    g = torque(TorqueModel(None, f), w)
    wn = np.linalg.norm(w)
    expected = -0.5 * 0.08 * R_S * math.sqrt(1 - (w[0] / wn) ** 2) * w / wn
    np.testing.assert_allclose(g, expected, rtol=1e-13)


def test_thesis_flight_friction_appendix_a_arm():
    beta = math.asin(4.72 / 7.899)
    f = ThesisFlightFriction(0.35, 64.67, R_S, beta)
    w = np.array([1.0, 2.0, -2.0])
    wn = 3.0
    arm = math.sqrt(1 - math.sin(beta) ** 2 * (1 / wn) ** 2 - math.cos(beta) ** 2 * (2 / wn) ** 2)
    expected = -0.35 * 64.67 * math.cos(beta) * R_S * arm * w / wn
    np.testing.assert_allclose(torque(TorqueModel(None, f), w), expected, rtol=1e-13)


def test_coulomb_single_contact_is_perpendicular_projection():
    # Exact point contact at P = -R X: G = P x F, F = -mu N v/|v|, v = w x P. Worked by hand:
    # G = -mu N R w_perp/|w_perp| with w_perp the part of w normal to X.
    f = CoulombContactFriction(0.5, 0.08, R_S)
    w = np.array([2.0, 1.0, -2.0])
    wp = np.array([0.0, 1.0, -2.0])
    expected = -0.5 * 0.08 * R_S * wp / np.linalg.norm(wp)
    np.testing.assert_allclose(torque(TorqueModel(None, f), w), expected, rtol=1e-13)


@given(
    st.lists(st.floats(-1e3, 1e3), min_size=3, max_size=3).filter(
        lambda v: np.linalg.norm(v) > 1e-3
    )
)
def test_thesis_and_coulomb_rig_dissipate_the_same_power(w):
    # Both laws dissipate mu N |v| (the slip speed at the contact), a consequence of the
    # thesis's arm sqrt(1 - (w_X/w)^2) = |w x X|/|w|. Independent of either implementation.
    w = np.asarray(w)
    th = torque(TorqueModel(None, ThesisRigFriction(0.4, 0.1, R_S)), w)
    co = torque(TorqueModel(None, CoulombContactFriction(0.4, 0.1, R_S)), w)
    slip = R_S * np.linalg.norm(np.cross(w, [-1.0, 0, 0]))
    # sqrt(1 - e_X^2) cancels when w is nearly along X: allow that rounding in abs
    tol = 1e-7 * 0.4 * 0.1 * R_S * np.linalg.norm(w) + 1e-15
    assert th @ w == pytest.approx(-0.4 * 0.1 * slip, rel=1e-9, abs=tol)
    assert co @ w == pytest.approx(-0.4 * 0.1 * slip, rel=1e-9, abs=tol)


MODELS = [
    TorqueModel(NakabayashiViscous(R_S, H), ThesisRigFriction(0.5, 0.08, R_S)),
    TorqueModel(CouetteViscous(R_S, H), ThesisFlightFriction(0.35, 60.0, R_S, 0.64)),
    TorqueModel(None, CoulombContactFriction(0.35, 60.0, R_S, 0.64, 7)),
    TorqueModel(None, CoulombContactFriction(0.35, 60.0, R_S, 0.64, 3, "radial")),
    TorqueModel(None, CoulombContactFriction(0.5, 0.08, R_S, patch_radius=2.8e-4)),
]


@pytest.mark.parametrize("model", MODELS)
@settings(deadline=None)  # the first call of a new model may compile
@given(
    w=st.lists(st.floats(-1e4, 1e4), min_size=3, max_size=3),
    width=st.sampled_from([0.0, 1e-6, 1e-2, 10.0]),
)
def test_every_torque_is_dissipative(model, w, width):
    g = torque(model, np.asarray(w), width)
    assert np.all(np.isfinite(g))
    assert g @ np.asarray(w) <= 1e-12 * (1 + np.linalg.norm(g) * np.linalg.norm(w))


@pytest.mark.parametrize("family", list(FAMILIES))
def test_saturation_families_closed_forms(family):
    for x in (0.0, 1e-3, 0.5, 1.0, 2.0, 30.0):
        assert slip_saturation(x, FAMILIES[family]) == pytest.approx(SHAPES[family](x), rel=1e-14)
    assert slip_saturation(math.inf, FAMILIES[family]) == 1.0  # zero width: the bare law


@pytest.mark.parametrize("family", list(FAMILIES))
@pytest.mark.parametrize("width", [0.0, 1e-6, 1e-2])
@pytest.mark.parametrize("speed", [1e-9, 1e-6, 1e-4, 1e-2, 1.0, 1e3])
def test_rig_arm_is_zero_for_slip_along_x(family, width, speed):
    # Eq. (61) / Appendix A with C(1) = 1: ARM = sqrt(1 - (w_X/w_r)^2) = 0 for w_r along X,
    # whatever |w_r| is relative to the width: the single bottom contact (P = -R_s X)
    # cannot hold a torque about the gravity axis X, at stick or in slip. (Regularising
    # the direction instead gave up to 0.5 mu W R_s here when |w_r| ~ width.)
    m = TorqueModel(None, ThesisRigFriction(0.5473, 0.07987, R_S))
    for sign in (1.0, -1.0):
        assert np.all(torque(m, (sign * speed, 0.0, 0.0), width, family) == 0.0)


@pytest.mark.parametrize("family", list(FAMILIES))
@given(
    u=st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3).filter(
        lambda v: np.linalg.norm(v) > 1e-3
    ),
    x=st.floats(1e-4, 1e2),
)
def test_near_stick_rig_torque_uses_true_direction(family, u, x):
    # |w_r| = x * width: the torque is -M ARM(u) s(x) u with u = w_r/|w_r| (true direction);
    # its X component therefore vanishes as u -> X, however small the slip is.
    width = 2e-5
    u = np.asarray(u) / np.linalg.norm(u)
    f = ThesisRigFriction(0.5473, 0.07987, R_S)
    g = torque(TorqueModel(None, f), x * width * u, width, family)
    expected = -f.moment_scale * math.sqrt(max(1 - u[0] ** 2, 0.0)) * SHAPES[family](x) * u
    # sqrt(1 - u_X^2) cancels as u -> X: an absolute arm error of ~sqrt(machine eps)
    np.testing.assert_allclose(g, expected, rtol=1e-9, atol=1e-7 * f.moment_scale)
    bound = f.moment_scale * abs(u[0]) * math.sqrt(max(1 - u[0] ** 2, 0.0))
    assert abs(g[0]) <= bound * (1 + 1e-9) + 1e-7 * f.moment_scale * abs(u[0])


def test_coulomb_patch_resists_pivoting_about_the_contact_normal():
    # Pure drilling about the rig contact normal X: v = w x P = 0 at P = -R_s X, so a point
    # contact exerts nothing; a patch of radius a gives -mu N eps sign(w_X) X with
    # eps = 3 pi a / 16 (Hertzian pressure; Leine and Glocker 2003). Hand-worked.
    a = 2.79e-4
    w = np.array([5.0, 0.0, 0.0])
    point = TorqueModel(None, CoulombContactFriction(0.5, 0.08, R_S))
    patch = TorqueModel(None, CoulombContactFriction(0.5, 0.08, R_S, patch_radius=a))
    np.testing.assert_array_equal(torque(point, w), 0.0)
    np.testing.assert_allclose(torque(patch, w), [-0.5 * 0.08 * 3 * math.pi * a / 16, 0, 0])
    np.testing.assert_allclose(torque(patch, -w), [0.5 * 0.08 * 3 * math.pi * a / 16, 0, 0])


@given(
    st.lists(st.floats(-1e3, 1e3), min_size=3, max_size=3).filter(
        lambda v: np.linalg.norm(v) > 1e-3
    )
)
def test_coulomb_patch_dissipates_the_contensou_norm(w):
    # Dissipation mu N sqrt(|v|^2 + eps^2 w_n^2): a norm of w_r, hence a monotone law.
    # And the whole vector, summed here from the law's definition at P = -R_s X, n = -X
    # (Leine and Glocker 2003): G = P x F + pivot, F = -mu N v/g, pivot -mu N eps^2
    # (w.n)/g n, against the compiled closed form of the rig's one contact.
    a = 3e-4
    eps = 3 * math.pi * a / 16
    w = np.asarray(w)
    g = torque(TorqueModel(None, CoulombContactFriction(0.4, 0.1, R_S, patch_radius=a)), w)
    pos, normal = np.array([-R_S, 0.0, 0.0]), np.array([-1.0, 0.0, 0.0])
    v = np.cross(w, pos)
    slip = math.sqrt(v @ v + (eps * (w @ normal)) ** 2)
    assert g @ w == pytest.approx(-0.4 * 0.1 * slip, rel=1e-9)
    pivot = -0.4 * 0.1 * eps**2 * (w @ normal) / slip * normal
    expected = np.cross(pos, -0.4 * 0.1 * v / slip) + pivot
    np.testing.assert_allclose(g, expected, rtol=1e-12, atol=1e-15 * np.max(np.abs(expected)))


def test_hertz_patch_radius_closed_form():
    # a = (3 N R* / (4 E*))^(1/3), R* = R (R + h) / h; steel on lucite (E 200/3.0 GPa,
    # nu 0.29/0.37), evaluated by hand for the Table 1 rig: 0.2787 mm.
    e_star = 1 / ((1 - 0.29**2) / 200e9 + (1 - 0.37**2) / 3.0e9)
    r_star = R_S * (R_S + H) / H
    a = (3 * 0.07987 * r_star / (4 * e_star)) ** (1 / 3)
    assert hertz_patch_radius(0.07987, R_S, H, seat_material="lucite") == pytest.approx(a)
    assert a == pytest.approx(2.787e-4, rel=1e-3)
    with pytest.raises(InputError, match="seat_material"):
        hertz_patch_radius(0.08, R_S, H, seat_material="wood")


def test_regularised_torque_vanishes_at_corotation():
    # SPEC section 4: at release omega_r = 0 and the Coulomb direction is 0/0
    for model in MODELS:
        assert np.all(torque(model, np.zeros(3), width=1e-3) == 0.0)


def test_ring_of_many_contacts_is_axisymmetric():
    # A ring of N >> 1 points gives the same torque for w rotated about Z (symmetry check)
    f = CoulombContactFriction(0.35, 60.0, R_S, 0.64, 360)
    m = TorqueModel(None, f)
    w = np.array([3.0, 0.0, 1.0])
    a = 0.7
    rot = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    np.testing.assert_allclose(torque(m, rot @ w), rot @ torque(m, w), rtol=1e-6, atol=1e-12)


@pytest.mark.parametrize(
    ("factory", "field"),
    [
        (lambda: ThesisRigFriction(-0.1, 0.08, R_S), "mu_s"),
        (lambda: ThesisFlightFriction(0.3, -1.0, R_S, 0.6), "pressure_force"),
        (lambda: ThesisFlightFriction(0.3, 1.0, R_S, 2.0), "contact_angle"),
        (lambda: CoulombContactFriction(0.3, 1.0, R_S, 0.6, 0), "n_contacts"),
        (lambda: CoulombContactFriction(0.3, 1.0, R_S, 0.6, 2, "bogus"), "normal_load"),
        (lambda: CoulombContactFriction(0.3, 1.0, R_S, patch_radius=-1e-4), "patch_radius"),
        (lambda: NakabayashiViscous(R_S, -1e-5), "gap"),
        (lambda: CouetteViscous(R_S, 1e-5, -1.0), "viscosity"),
    ],
)
def test_bad_torque_parameters(factory, field):
    with pytest.raises(InputError) as err:
        factory()
    assert err.value.field == field


@pytest.mark.parametrize("v", [0.0, 0.01, 0.05, 0.2, 5.0])
def test_slip_speed_laws_closed_forms(v):
    # mu(v)/mu_s: Stribeck-type weakening r + (1-r) exp(-(v/v_s)^2) and strengthening
    # r + (1-r) v/(v+v_s), written out here independently of the kernel.
    r, vs = 0.4, 0.05
    weak = r + (1 - r) * math.exp(-((v / vs) ** 2))
    strong = r + (1 - r) * v / (v + vs)
    assert friction_speed_factor(v, SPEED_WEAKENING, r, vs) == pytest.approx(weak, rel=1e-14)
    assert friction_speed_factor(v, SPEED_STRENGTHENING, r, vs) == pytest.approx(strong, rel=1e-14)
    assert friction_speed_factor(v, 0.0, r, vs) == 1.0


def test_slip_speed_law_scales_the_rig_torque():
    # thesis rig law with mu(v), v = R_s |omega_r|: the torque scales by phi(v) exactly
    w = np.array([0.0, 3.0, 4.0])  # |w| = 5 rad/s
    law = SlipSpeedLaw("strengthening", 0.5, 0.02)
    f = ThesisRigFriction(0.5, 0.08, R_S)
    base = torque(TorqueModel(None, f), w)
    p = np.zeros(N_PARAM)
    p[8:18] = TorqueModel(None, f, law).pack()
    p[P_SPEED : P_SPEED + 3] = law.pack()
    g = np.array(applied_torque(*w, p))
    v = 5.0 * R_S
    np.testing.assert_allclose(g, base * (0.5 + 0.5 * v / (v + 0.02)), rtol=1e-13)
    for kw, field in (
        ({"kind": "bogus"}, "speed_law"),
        ({"ratio": 0.0}, "speed_ratio"),
        ({"speed": -1.0}, "slip_speed"),
    ):
        with pytest.raises(InputError) as err:
            SlipSpeedLaw(**kw)
        assert err.value.field == field
