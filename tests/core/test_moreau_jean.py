"""Moreau-Jean time-stepping with the exact set (core/integrators/moreau_jean.py): an
event-capturing cross-check of the event-driven set-valued solver (Acary and Brogliato
2008, ch. 10). Reference: the event-driven t_cr at rtol 1e-10 (docs/stick_slip.md)."""

from __future__ import annotations

import dataclasses

import pytest

from obturator.core.integrators import moreau_jean
from obturator.errors import InputError
from obturator.model.cases import rig_case
from obturator.reference import THESIS_MU_S
from obturator.solve import SolverOptions, opening_time, simulate
from obturator.solve.setup import integration_setup

OPTIONS = SolverOptions(method="set-valued", rtol=1e-10, atol=1e-12)


def _moreau_jean(case, h: float) -> float:
    problem, controls = integration_setup(case, OPTIONS)
    out = moreau_jean.integrate(problem, controls._replace(h0=h, max_steps=10**7))
    return out.t_event


def test_first_order_to_the_event_driven_opening():
    """200 rad/s (one stick phase): halving h halves the error (first order), and the
    Richardson extrapolation 2 t(h/2) - t(h) is the event-driven t_cr to 1e-4."""
    case = rig_case(200.0, THESIS_MU_S)
    ref = opening_time(case, OPTIONS)
    t1 = _moreau_jean(case, 1e-5)
    t2 = _moreau_jean(case, 5e-6)
    e1, e2 = (t1 - ref) / ref, (t2 - ref) / ref
    assert 0.0 < e2 < 5e-3
    assert e1 / e2 == pytest.approx(2.0, rel=0.1)
    assert abs(2.0 * t2 - t1 - ref) / ref < 1e-4


def test_out_of_scope_is_refused():
    case = rig_case(200.0, THESIS_MU_S, spin_mode="free")
    problem, controls = integration_setup(case, OPTIONS)
    with pytest.raises(InputError, match="spin_mode"):
        moreau_jean.integrate(problem, controls)
    problem, controls = integration_setup(dataclasses.replace(case, spin_mode="constant"), OPTIONS)
    with pytest.raises(InputError, match="t_eval"):
        moreau_jean.integrate(problem, controls._replace(record=True))


def test_every_method_by_name_reaches_the_same_opening():
    """The three answers by their names in SolverOptions: the regularised path (default
    settings; near stick its width 1e-7 omega_p dominates: measured 2.6e-6), the set-valued
    solver at default settings, and Moreau-Jean at h = 5e-6 and 2.5e-6 s, whose
    Richardson extrapolation 2 t(h/2) - t(h) removes its first-order error (docs table:
    -2.5e-5 at 200 rad/s). Reference: the set-valued t_cr at rtol 1e-10."""
    case = rig_case(200.0, THESIS_MU_S)
    ref = opening_time(case, OPTIONS)
    answers = {
        method: opening_time(case, SolverOptions(method=method))
        for method in ("auto", "set-valued")
    }
    steps = (5e-6, 2.5e-6)
    mj = [opening_time(case, SolverOptions(method="moreau-jean", fixed_step=h)) for h in steps]
    assert abs(answers["auto"] - ref) / ref < 1e-5
    assert abs(answers["set-valued"] - ref) / ref < 1e-7
    assert 0.0 < (mj[1] - ref) / ref < (mj[0] - ref) / ref < 5e-3
    assert abs(2.0 * mj[1] - mj[0] - ref) / ref < 1e-4


def test_fixed_step_is_validated():
    with pytest.raises(InputError, match="fixed_step.*moreau-jean"):
        SolverOptions(fixed_step=1e-5)
    with pytest.raises(InputError, match="fixed_step"):
        SolverOptions(method="moreau-jean", fixed_step=0.0)
    assert (
        SolverOptions.from_settings({"method": "moreau-jean", "fixed_step": 2e-6}).fixed_step
        == 2e-6
    )


def test_moreau_jean_has_no_time_history():
    with pytest.raises(InputError, match="t_eval"):
        simulate(rig_case(200.0, THESIS_MU_S), SolverOptions(method="moreau-jean"))
