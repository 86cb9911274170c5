"""Kernel groups too small for lanes run one by one, to the same t_cr.

Reference: the one-trajectory path (:func:`obturator.solve.opening_time`) and the lanes
forced on the same points; the lanes are bit-equal to the scalar DOP853 and hand so few
stiff points to the scalar Radau IIA, so all three must agree to the bit.
"""

from __future__ import annotations

import numpy as np
import pytest

from obturator.model.cases import rig_case
from obturator.model.torques import SlipSpeedLaw
from obturator.solve import SolverOptions, many, opening_time, opening_times

MU_S = 0.5473
REGULARISED = SolverOptions(method="regularised")


def _cases(law, spins):
    return [rig_case(w, MU_S, speed_law=law) for w in spins]


@pytest.mark.parametrize(
    ("law", "family", "spins"),
    [
        (None, "algebraic", (120.0, 300.0, 450.0)),  # thesis kernel, under THESIS_LANES_MIN
        (SlipSpeedLaw("strengthening", 0.3, 0.1), "algebraic", (80.0, 120.0, 300.0, 450.0)),
        (None, "tanh", (80.0, 120.0, 300.0, 450.0, 600.0)),  # under GENERIC_LANES_MIN
    ],
    ids=["thesis kernel", "thesis kernel (strengthening)", "generic kernel"],
)
def test_small_group_runs_one_by_one_to_the_same_bits(monkeypatch, law, family, spins):
    cases = _cases(law, spins)
    options = SolverOptions(method="regularised", friction_family=family)
    kernel = many.pack_points(cases, options).p[0, many.P_KERNEL]
    assert len(cases) < many.lanes_pay_from(kernel)
    t_one, s_one, stats = opening_times(cases, options)
    np.testing.assert_array_equal(t_one, [opening_time(c, options) for c in cases])
    lanes = []
    real = many.integrate_lanes
    monkeypatch.setattr(many, "integrate_lanes", lambda *a: lanes.append(1) or real(*a))
    monkeypatch.setattr(many, "THESIS_LANES_MIN", 1)
    monkeypatch.setattr(many, "GENERIC_LANES_MIN", 1)
    t_lanes, s_lanes, stats_lanes = opening_times(cases, options)
    assert lanes, "the forced run must go through the lanes"
    np.testing.assert_array_equal(t_lanes, t_one)
    np.testing.assert_array_equal(s_lanes, s_one)
    # one by one, a point counts as stiff where Radau IIA evaluated a Jacobian
    assert stats["n_stiff"] == stats_lanes["n_stiff"] >= 1


def test_five_thesis_points_take_the_lanes(monkeypatch):
    lanes = []
    real = many.integrate_lanes
    monkeypatch.setattr(many, "integrate_lanes", lambda *a: lanes.append(1) or real(*a))
    cases = _cases(None, np.linspace(300.0, 500.0, many.THESIS_LANES_MIN))
    opening_times(cases, REGULARISED)
    assert lanes
