"""Contact ageing of the lucite seat (obturator.model.ageing, issue 29): its closed-form
limits and its reach through rig_case and the validation's candidates."""

from __future__ import annotations

import math

import pytest

from obturator import rig_case
from obturator.errors import InputError
from obturator.model.ageing import ContactAgeing
from obturator.model.torques import SlipSpeedLaw, hertz_patch_radius
from obturator.reference import TABLE1
from obturator.solve import opening_time
from obturator.validation import CANDIDATES


def test_no_ageing_is_the_thesis_case():
    """b = 0 (the null value): the very same case as the thesis's constant-mu law."""
    for w in (78.0, 200.0, 446.0):
        assert rig_case(w, 0.55, ageing=ContactAgeing(0.0, 1e-4)) == rig_case(w, 0.55)
    nominal = CANDIDATES["mu"].build(200.0, [0.55], 5.0)
    aged = CANDIDATES["ageing"].build(200.0, [0.55, 0.0, 1e-4], 5.0)
    assert aged == nominal
    assert opening_time(aged) == opening_time(nominal)


def test_static_friction_closed_form_and_long_cutoff_limit():
    """mu_0 = mu_s + b ln(1 + t_d/tau), t_d = 2a/(R_s omega_p), fading to mu_s at slip
    speeds above D_c/t_d; tau >> t_d leaves mu_0 - mu_s -> b t_d/tau -> 0."""
    w, mu, b, tau = 150.0, 0.5, 0.03, 2e-4
    case = rig_case(w, mu, ageing=ContactAgeing(b, tau))
    a = hertz_patch_radius(
        TABLE1["rig_weight"], TABLE1["ball_radius"], TABLE1["gap"], seat_material="lucite"
    )
    t_d = 2.0 * a / (TABLE1["ball_radius"] * w)
    mu0 = mu + b * math.log(1.0 + t_d / tau)
    assert case.torque.friction.mu_s == pytest.approx(mu0, rel=1e-14)
    law = case.torque.speed_law
    assert law.kind == "weakening"
    assert law.ratio == pytest.approx(mu / mu0, rel=1e-14)
    assert law.speed == pytest.approx(1e-6 / t_d, rel=1e-14)
    # dwell time falls as 1/omega_p: less ageing at higher spin
    hi = rig_case(2 * w, mu, ageing=ContactAgeing(b, tau))
    assert hi.torque.friction.mu_s < mu0
    # long cut-off: linear limit b t_d / tau, and mu_0 -> mu_s
    far = rig_case(w, mu, ageing=ContactAgeing(b, 1e6))
    assert far.torque.friction.mu_s - mu == pytest.approx(b * t_d / 1e6, rel=1e-6)


def test_ageing_refuses_a_second_speed_law_and_bad_values():
    with pytest.raises(InputError, match="ageing"):
        rig_case(200.0, 0.5, ageing=ContactAgeing(0.02), speed_law=SlipSpeedLaw("weakening", 0.5))
    with pytest.raises(InputError, match="ageing_rate"):
        ContactAgeing(-0.01)
    with pytest.raises(InputError, match="ageing_time"):
        ContactAgeing(0.01, 0.0)


def test_ageing_slows_the_opening_more_at_low_spin():
    """Older contacts at low spin: the ageing term lengthens t_cr there relatively more."""
    cand = CANDIDATES["ageing"]
    ratio = {}
    for w in (150.0, 400.0):
        t0 = opening_time(CANDIDATES["mu"].build(w, [0.55], 5.0))
        t1 = opening_time(cand.build(w, [0.55, 0.05, 1e-5], 5.0))
        ratio[w] = t1 / t0
    assert ratio[150.0] > ratio[400.0] >= 1.0 - 1e-6
