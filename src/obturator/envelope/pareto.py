"""The Pareto front of the robust design: t_cr objective against ball mass.

Split from :mod:`.optimize` (which finds the optimum): the epsilon-constraint
method lowers the mass budget from the optimum to the lightest feasible design.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import InputError, check_range
from ..runs import Runner
from .optimize import DESIGN_VARIABLES, DesignProblem, OptimisationResult, _polish

__all__ = ["lightest_design", "pareto_front"]


def lightest_design(problem: DesignProblem) -> np.ndarray:
    """The lightest design satisfying the bounds and constraints (no t_cr needed)."""
    from scipy.optimize import minimize

    lo = np.array([b[0] for b in problem.bounds])
    hi = np.array([b[1] for b in problem.bounds])

    def phys(s: np.ndarray) -> np.ndarray:
        return lo + np.clip(s, 0.0, 1.0) * (hi - lo)

    best = None
    for s0 in (np.full(lo.size, 0.5), np.zeros(lo.size), np.ones(lo.size)):
        res = minimize(
            lambda s: problem.mass(phys(s)) / float(problem.mass_budget),  # type: ignore[arg-type]
            s0,
            method="SLSQP",
            bounds=[(0.0, 1.0)] * lo.size,
            constraints=[{"type": "ineq", "fun": lambda s: problem.constraints(phys(s))}],
            options={"maxiter": 200, "ftol": 1e-12},
        )
        x = phys(res.x)
        if problem.feasible(x, 1e-7) and (best is None or problem.mass(x) < problem.mass(best)):
            best = x
    if best is None:
        raise InputError("variables", "no design satisfies the bounds and constraints")
    return best


def pareto_front(
    result: OptimisationResult,
    runner: Runner | None = None,
    *,
    points: int = 6,
) -> Any:
    """Objective vs ball mass by the epsilon-constraint method.

    The mass budget is lowered in ``points`` steps from the optimum's mass to
    the lightest feasible design's (:func:`lightest_design`), and SLSQP
    re-optimises from the previous solution each time. When the optimum is
    itself (within 0.5 %) the lightest feasible design, t_cr and mass do not
    compete and the front is that single point (attribute ``degenerate``).

    Returns
    -------
    xarray.Dataset
        Dimension ``point``: ``mass`` [kg], ``objective`` [s], ``mass_budget``
        [kg], ``feasible`` and one variable per design variable.
    """
    import xarray as xr

    pb = result.problem
    runner = runner or Runner(workers=1)
    light = lightest_design(pb)
    m_top, m_min = result.mass, pb.mass(light)
    degenerate = m_top <= m_min * 1.005
    n = 1 if degenerate else int(check_range("points", points, 2, 100))
    budgets = np.linspace(m_top, m_min, n)
    x = result.x.copy()
    rows = [(result.mass, result.objective, True, x.copy())]
    for m in budgets[1:]:
        start = x if pb.mass(x) <= m else light + (x - light) * 0.5
        x, f, _ = _polish(pb, runner, start, mass_budget=float(m) * (1 + 1e-9))
        ok = pb.feasible(x, 1e-7) and pb.mass(x) <= m * (1 + 1e-6)
        rows.append((pb.mass(x), f, ok, x.copy()))
    data = {
        "mass": ("point", np.array([r[0] for r in rows]), {"units": "kg"}),
        "objective": ("point", np.array([r[1] for r in rows]), {"units": "s"}),
        "mass_budget": ("point", budgets, {"units": "kg"}),
        "feasible": ("point", np.array([r[2] for r in rows], dtype=np.int8), {}),
    }
    for i, name in enumerate(pb.names):
        data[name] = ("point", np.array([r[3][i] for r in rows]), {"units": DESIGN_VARIABLES[name]})
    attrs = {
        "objective": pb.objective,
        "baseline_mass": result.baseline_mass,
        "baseline_objective": result.baseline["objective"],
        "lightest_feasible_mass": m_min,
        "degenerate": int(degenerate),
    }
    return xr.Dataset(data, coords={"point": np.arange(len(rows))}, attrs=attrs)
