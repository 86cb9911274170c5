"""Robust design optimisation: constraints, feasibility of the optimum, Pareto front."""

from __future__ import annotations

import math

import numpy as np
import pytest

from obturator.envelope.model import FlightModel
from obturator.envelope.optimize import DesignProblem, optimise
from obturator.envelope.pareto import lightest_design, pareto_front
from obturator.errors import InputError
from obturator.runs import Runner
from obturator.solve import SolverOptions

FAST = SolverOptions(rtol=1e-6, atol=1e-8)
MODEL = FlightModel(load="constant", options=FAST, check_convergence=False)
CONDS = ({"mach": 1.5, "altitude_m": 10_000.0}, {"mach": 3.0, "altitude_m": 0.0})


def test_constraints_closed_form():
    pb = DesignProblem(MODEL, CONDS)
    x = pb.baseline()
    g = pb.constraints(x)
    big, r = 7.899e-3, 4.72e-3
    assert g[0] == pytest.approx((0.99 / math.sqrt(2) * big - r) / big)
    block = math.radians(87.25) - 2 * math.asin(r / big) - math.radians(2.0)
    assert g[1] == pytest.approx(block)
    assert g[2] == pytest.approx(0.0, abs=1e-12)  # the budget is the Table 1 ball's mass
    assert pb.feasible(x)
    vol = 4 / 3 * math.pi * (big**2 - r**2) ** 1.5
    assert pb.mass(x) == pytest.approx(7669.6 * vol)


def test_optimum_respects_bounds_and_constraints():
    bounds = {"hole_radius": (4.72e-3, 5.6e-3), "ball_radius": (6.8e-3, 7.899e-3)}
    pb = DesignProblem(MODEL, CONDS, bounds, block_margin_deg=5.0)
    res = optimise(pb, Runner(workers=1), popsize=5, maxiter=4, seed=1)
    for v, (lo, hi) in zip(res.x, pb.bounds, strict=True):
        assert lo - 1e-12 <= v <= hi + 1e-12
    assert np.all(res.constraints >= -1e-9)
    assert res.optimum["objective"] <= res.baseline["objective"]
    assert all(s == 1 for s in res.optimum["status"])  # opened and converged
    assert res.improvement > 0.2
    assert set(res.sensitivity) == set(bounds)
    d = res.to_dict()
    assert d["optimum_mass_kg"] <= d["baseline_mass_kg"] * (1 + 1e-9)
    front = pareto_front(res, Runner(workers=1), points=3)
    m, f = front["mass"].values, front["objective"].values
    assert np.all(np.diff(m) <= 1e-12) and np.all(np.diff(f) >= -1e-9)
    assert front.attrs["lightest_feasible_mass"] == pytest.approx(pb.mass(lightest_design(pb)))


def test_mass_budget_is_respected():
    bounds = {"density": (4430.0, 7850.0), "mu_s": (0.25, 0.45)}
    pb = DesignProblem(MODEL, CONDS[:1], bounds, objective="quantile:0.5", mass_budget=5e-3)
    res = optimise(pb, Runner(workers=1), popsize=4, maxiter=3, seed=2)
    assert res.mass <= 5e-3 * (1 + 1e-9)
    assert res.x[1] == pytest.approx(0.45, rel=1e-3)  # more friction opens faster


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"objective": "mean"}, "objective"),
        ({"variables": {"colour": (1.0, 2.0)}}, "variables"),
        ({"variables": {"hole_radius": (4.0e-3, 5.0e-3)}}, "hole_radius"),
        ({"variables": {"ball_radius": (7e-3, 9e-3)}}, "ball_radius"),
        ({"mass_budget": -1.0}, "mass_budget"),
    ],
)
def test_problem_validation(kwargs, field):
    with pytest.raises(InputError, match=f"^{field}"):
        DesignProblem(MODEL, CONDS, **kwargs)
