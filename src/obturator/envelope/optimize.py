"""Robust design optimisation of the obturator over the firing envelope.

The thesis recommends coupling the model to "a numerical optimization routine
for optimizing the BOT design for the desired performance criteria"
(chapter VI). Here the design variables

    hole radius r_s, ball radius R_s, ball density rho (material), gap h,
    sliding friction mu_s (surface treatment, within a range)

minimise a robust measure of t_cr over a set of flight conditions (muzzle
Mach x launch altitude): the worst case (``"max"``) or a high quantile
(``"quantile:0.9"``, linear interpolation between the sorted t_cr). A flight
condition where the bore does not open by t_max counts as 2 t_max.

Constraints (each written g(x) >= 0 in :meth:`DesignProblem.constraints`):

1. the ball can be bored: r_s <= (1 - 0.01) R_s / sqrt(2) (thesis p. 77;
   :class:`obturator.model.geometry.BoredBall`);
2. the hole does not throttle the bore: r_s >= r_p (a lower bound);
3. the ball fits the projectile with a socket wall: R_s <= R_p - t_wall (an
   upper bound; default t_wall = Table 1's R_p - R_s = 2.061 mm, so the Table 1
   ball is the largest);
4. the ball blocks the bore at launch: the mouth of the hole (a cone of
   half-angle beta_s = asin(r_s/R_s) about the hole axis) stays clear of the
   bore's contact ring (half-angle beta = asin(r_p/R_s) about Z, Eq. 47) at
   theta_0: theta_0 - beta - beta_s >= margin (default 2 deg; Table 1:
   87.25 - 36.69 - 36.69 = 13.9 deg);
5. mass budget: ball mass <= m_max (default the Table 1 ball's 8.16 g).

The bore radius r_p, theta_0, the projectile and the flight conditions are not
design variables. The optimiser is SciPy's differential evolution (global,
derivative-free, with the constraints handled by Lampinen's feasibility
rules), its generations evaluated by the package's runner (local processes or
Dask, resumable), followed by an SLSQP polish in scaled variables. During the
search t_cr is computed without the refined reruns; the Table 1 design and the
optimum are then re-evaluated with convergence checks at every flight
condition. The Pareto front of the objective against ball mass is traced by
the epsilon-constraint method: SLSQP from the optimum with the mass budget
lowered step by step.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._docs import field_docs
from ..errors import InputError, check_range
from ..runs import Runner
from .model import FlightModel, warm_integrators

__all__ = [
    "split_objective",
    "DESIGN_VARIABLES",
    "DEFAULT_BOUNDS",
    "DesignProblem",
    "DesignPoint",
    "OptimisationResult",
    "optimise",
    "CONSTRAINT_NAMES",
]

#: Design variables and their units.
DESIGN_VARIABLES = {
    "hole_radius": "m",
    "ball_radius": "m",
    "density": "kg/m^3",
    "gap": "m",
    "mu_s": "1",
}

#: Default bounds: hole from the bore radius up; ball up to the Table 1 ball;
#: titanium alloy (4430) to steel (7850); gap 1 to 4 thousandths of an inch;
#: friction 0.25 to 0.45 (Table 1: 0.35; the rig calibration gave 0.55).
DEFAULT_BOUNDS: dict[str, tuple[float, float]] = {
    "hole_radius": (4.72e-3, 5.6e-3),
    "ball_radius": (6.8e-3, 7.899e-3),
    "density": (4430.0, 7850.0),
    "gap": (25.4e-6, 101.6e-6),
    "mu_s": (0.25, 0.45),
}

_BORE_FACTOR = (1.0 - 0.01) / math.sqrt(2.0)
#: Names of the constraints of :meth:`DesignProblem.constraints`, in order.
CONSTRAINT_NAMES = (
    "hole <= 0.99 R_s/sqrt(2)",
    "bore blocked at launch (theta_0 - beta - beta_s >= margin)",
    "mass budget",
)


def _objective_value(t: np.ndarray, kind: str, t_max: float) -> float:
    y = np.where(np.isfinite(t), t, 2.0 * t_max)
    if kind == "max":
        return float(y.max())
    q = float(kind.split(":", 1)[1])
    return float(np.quantile(y, q))


def split_objective(text: str) -> tuple[str, str]:
    """``"t_start"``, ``"t_start:quantile:0.9"``, ``"max"`` -> (time, aggregate).

    The time (``t_cr``, ``t_start`` or ``t_start_late``,
    :data:`obturator.envelope.model.TIMES`) selects the model's event; the aggregate
    over the conditions is checked by :class:`DesignProblem`. Without a prefix the
    time is t_cr.
    """
    head, _, rest = text.partition(":")
    if head in ("t_cr", "t_start", "t_start_late"):
        return head, rest or "max"
    return "t_cr", text


def _check_objective(kind: str) -> str:
    if kind == "max":
        return kind
    if kind.startswith("quantile:"):
        try:
            q = float(kind.split(":", 1)[1])
        except ValueError:
            raise InputError(
                "objective", f"{kind!r}: expected quantile:Q with Q a number"
            ) from None
        check_range("objective", q, 0.0, 1.0)
        return f"quantile:{q:g}"
    raise InputError("objective", f"{kind!r}; allowed: max, quantile:Q (0 <= Q <= 1)")


@dataclass(frozen=True)
class DesignProblem:
    """What to optimise, over which flight conditions, under which constraints.

    Parameters
    ----------
    model : FlightModel
        Baseline design, projectile, load model and solver settings.
    conditions : sequence of mapping
        Flight conditions, e.g. ``{"mach": 1.5, "altitude_m": 10000.0}``.
    variables : mapping of str to (float, float)
        Design variables (names of :data:`DESIGN_VARIABLES`) and bounds (SI).
    objective : str
        ``"max"`` or ``"quantile:Q"`` of t_cr over the conditions.
    mass_budget : float, optional
        Largest ball mass [kg]; default the baseline ball's.
    wall : float, optional
        Smallest socket wall R_p - R_s [m]; default the baseline's.
    block_margin_deg : float
        Required theta_0 - beta - beta_s [deg].
    """

    model: FlightModel
    conditions: tuple[Mapping[str, float], ...]
    variables: Mapping[str, tuple[float, float]] = field(
        default_factory=lambda: dict(DEFAULT_BOUNDS)
    )
    objective: str = "max"
    mass_budget: float | None = None
    wall: float | None = None
    block_margin_deg: float = 2.0

    def __post_init__(self) -> None:
        if not self.conditions:
            raise InputError("conditions", "give at least one flight condition")
        object.__setattr__(self, "conditions", tuple(dict(c) for c in self.conditions))
        object.__setattr__(self, "objective", _check_objective(self.objective))
        var: dict[str, tuple[float, float]] = {}
        for name, (lo, hi) in dict(self.variables).items():
            if name not in DESIGN_VARIABLES:
                raise InputError("variables", f"{name!r}; allowed: {', '.join(DESIGN_VARIABLES)}")
            lo = check_range(f"{name} lower bound", lo, 0.0, lo_open=True)
            hi = check_range(f"{name} upper bound", hi, lo, hi_open=False)
            if not hi > lo:
                raise InputError(name, f"bounds [{lo:g}, {hi:g}] are empty")
            var[name] = (lo, hi)
        if not var:
            raise InputError("variables", "give at least one design variable")
        d = self.model.design
        if "hole_radius" in var and var["hole_radius"][0] < d.bore_radius * (1 - 1e-12):
            raise InputError(
                "hole_radius",
                f"lower bound {var['hole_radius'][0]:g} m is below the bore radius "
                f"{d.bore_radius:g} m (the hole would throttle the bore)",
            )
        wall = self.projectile_radius - d.ball_radius if self.wall is None else self.wall
        check_range("wall", wall, 0.0, self.projectile_radius, hi_open=True, unit="m")
        object.__setattr__(self, "wall", wall)
        if "ball_radius" in var and var["ball_radius"][1] > self.max_ball_radius * (1 + 1e-12):
            raise InputError(
                "ball_radius",
                f"upper bound {var['ball_radius'][1]:g} m exceeds R_p - wall = "
                f"{self.max_ball_radius:g} m",
            )
        budget = d.mass if self.mass_budget is None else self.mass_budget
        object.__setattr__(
            self, "mass_budget", check_range("mass_budget", budget, 0.0, lo_open=True, unit="kg")
        )
        check_range("block_margin_deg", self.block_margin_deg, 0.0, 90.0, unit="deg")
        object.__setattr__(self, "variables", var)

    # -- geometry
    @property
    def projectile_radius(self) -> float:
        """R_p [m]."""
        return self.model.projectile.radius

    @property
    def max_ball_radius(self) -> float:
        """R_p - wall [m]."""
        return self.projectile_radius - float(self.wall)  # type: ignore[arg-type]

    @property
    def names(self) -> tuple[str, ...]:
        """Design variable names, in vector order."""
        return tuple(self.variables)

    @property
    def bounds(self) -> list[tuple[float, float]]:
        """Bounds in vector order (SI)."""
        return [self.variables[k] for k in self.names]

    def values(self, x: Sequence[float]) -> dict[str, float]:
        """Design-variable dict of a vector."""
        return {k: float(v) for k, v in zip(self.names, x, strict=True)}

    def baseline(self) -> np.ndarray:
        """The baseline design's variables as a vector (may lie outside the bounds)."""
        d = self.model.design.to_dict()
        return np.array([d[k] for k in self.names], dtype=float)

    def _design_values(self, x: Sequence[float]) -> dict[str, float]:
        d = self.model.design.to_dict()
        d.update(self.values(x))
        return d

    def constraints(self, x: Sequence[float]) -> np.ndarray:
        """Constraint values g(x) >= 0: [bore-able hole, bore blocked at launch, mass budget].

        Scaled to order one: the hole in units of R_s, the block margin in
        radians, the mass relative to the budget.
        """
        d = self._design_values(x)
        big, r_s, r_p = d["ball_radius"], d["hole_radius"], d["bore_radius"]
        g1 = (_BORE_FACTOR * big - r_s) / big
        theta0 = math.radians(d["theta0_deg"])
        if r_p >= big or r_s >= big:
            return np.array([g1, -1.0, -1.0])
        block = theta0 - math.asin(r_p / big) - math.asin(r_s / big)
        g2 = block - math.radians(self.block_margin_deg)
        u = max(big * big - r_s * r_s, 0.0)
        mass = d["density"] * 4.0 / 3.0 * math.pi * u**1.5
        g3 = 1.0 - mass / float(self.mass_budget)  # type: ignore[arg-type]
        return np.array([g1, g2, g3])

    def mass(self, x: Sequence[float]) -> float:
        """Ball mass [kg] of a design vector."""
        d = self._design_values(x)
        u = d["ball_radius"] ** 2 - d["hole_radius"] ** 2
        return d["density"] * 4.0 / 3.0 * math.pi * max(u, 0.0) ** 1.5

    def feasible(self, x: Sequence[float], tol: float = 1e-9) -> bool:
        """All constraints and bounds satisfied."""
        inside = all(
            lo - tol * abs(lo) <= v <= hi + tol * abs(hi)
            for v, (lo, hi) in zip(x, self.bounds, strict=True)
        )
        return inside and bool(np.all(self.constraints(x) >= -tol))

    def identity(self) -> dict[str, Any]:
        """JSON-ready description (resume store)."""
        return {
            "study": "optimize",
            "model": self.model.identity(),
            "conditions": [dict(c) for c in self.conditions],
            "variables": {k: list(v) for k, v in self.variables.items()},
            "objective": self.objective,
            "mass_budget": self.mass_budget,
            "wall": self.wall,
            "block_margin_deg": self.block_margin_deg,
        }


@dataclass(frozen=True)
class DesignPoint:
    """Point function: one design (task = design-variable dict) over all conditions.

    Picklable; returns ``objective`` [s], ``t_cr`` and ``status`` lists (one
    per condition) and ``mass`` [kg].
    """

    problem: DesignProblem
    check_convergence: bool = False

    def evaluate_many(self, tasks: Sequence[Mapping[str, float]]) -> list[dict[str, Any]]:
        """Every design of `tasks` over every condition, in one batch of the model
        (:meth:`FlightModel.evaluate_many`: the lanes)."""
        pb = self.problem
        model = pb.model.with_(check_convergence=self.check_convergence)
        xs = [[float(task[k]) for k in pb.names] for task in tasks]
        rows = model.evaluate_many([{**pb.values(x), **cond} for x in xs for cond in pb.conditions])
        n = len(pb.conditions)
        out = []
        for j, x in enumerate(xs):
            mine = rows[j * n : (j + 1) * n]
            ts = [float(r["t_cr"]) for r in mine]
            out.append({
                "objective": _objective_value(np.array(ts), pb.objective, pb.model.t_max),
                "t_cr": ts,
                "status": [int(r["status"]) for r in mine],
                "change": [float(r.get("change", math.nan)) for r in mine],
                "mass": pb.mass(x),
            })  # fmt: skip
        return out

    def __call__(self, task: Mapping[str, float]) -> dict[str, Any]:
        """One design over all conditions (:meth:`evaluate_many` of one)."""
        return self.evaluate_many([task])[0]


class _GenerationMap:
    """Map-like callable for differential evolution: one runner call per generation."""

    def __init__(self, problem: DesignProblem, runner: Runner) -> None:
        self.point = DesignPoint(problem)
        self.runner = runner
        self.problem = problem
        self.n_eval = 0

    def __call__(self, _func: Any, xs: Any) -> list[float]:
        tasks = [self.problem.values(x) for x in xs]
        self.n_eval += len(tasks)
        return [
            r["objective"]
            for r in self.runner.map(
                self.point.evaluate_many,
                tasks,
                label="designs",
                warm=warm_integrators,
                batched=True,
            )  # fmt: skip
        ]


@field_docs
@dataclass(frozen=True)
class OptimisationResult:
    """Outcome of :func:`optimise`."""

    #: The design problem solved.
    problem: DesignProblem
    #: Optimal design variables (SI, in ``problem.names`` order).
    x: np.ndarray
    #: Objective of the optimum [s] (search settings).
    objective: float
    #: Objective of the baseline (Table 1) design [s].
    baseline_objective: float
    #: Convergence-checked :class:`DesignPoint` result of the optimum (t_cr, status, change per
    #: condition).
    optimum: dict[str, Any]
    #: Convergence-checked :class:`DesignPoint` result of the baseline (Table 1) design (t_cr,
    #: status, change per condition).
    baseline: dict[str, Any]
    #: Ball mass of the optimum [kg].
    mass: float
    #: Ball mass of the baseline design [kg].
    baseline_mass: float
    #: g(x) at the optimum (>= 0).
    constraints: np.ndarray
    #: Per variable: ``derivative`` d objective / d x [s per unit], ``elasticity`` (x / J) dJ/dx,
    #: and ``active`` ("lower", "upper" or "").
    sensitivity: dict[str, dict[str, Any]]
    #: Designs evaluated.
    n_evaluations: int
    #: Optimiser message.
    message: str

    @property
    def improvement(self) -> float:
        """1 - objective / baseline objective (convergence-checked values)."""
        return 1.0 - self.optimum["objective"] / self.baseline["objective"]

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary."""
        pb = self.problem
        return {
            "objective": pb.objective,
            "event": pb.model.event,
            "conditions": [dict(c) for c in pb.conditions],
            "optimum": pb.values(self.x),
            "optimum_objective_s": self.optimum["objective"],
            "optimum_t_cr_s": self.optimum["t_cr"],
            "optimum_status": self.optimum["status"],
            "optimum_rel_change": self.optimum["change"],
            "optimum_mass_kg": self.mass,
            "baseline": pb.values(pb.baseline()),
            "baseline_objective_s": self.baseline["objective"],
            "baseline_t_cr_s": self.baseline["t_cr"],
            "baseline_status": self.baseline["status"],
            "baseline_mass_kg": self.baseline_mass,
            "improvement": self.improvement,
            "constraints_g": self.constraints.tolist(),
            "sensitivity": self.sensitivity,
            "n_evaluations": self.n_evaluations,
            "message": self.message,
        }


def _polish(
    problem: DesignProblem,
    runner: Runner,
    x0: np.ndarray,
    mass_budget: float | None = None,
    maxiter: int = 40,
) -> tuple[np.ndarray, float, int]:
    """SLSQP in scaled variables from x0; returns (x, objective, evaluations)."""
    from scipy.optimize import minimize

    lo = np.array([b[0] for b in problem.bounds])
    hi = np.array([b[1] for b in problem.bounds])
    point = DesignPoint(problem)
    count = [0]

    def phys(s: np.ndarray) -> np.ndarray:
        return lo + np.clip(s, 0.0, 1.0) * (hi - lo)

    def f(s: np.ndarray) -> float:
        count[0] += 1
        return runner.map(point, [problem.values(phys(s))], label="polish")[0]["objective"]

    cons = [{"type": "ineq", "fun": lambda s: problem.constraints(phys(s))}]
    if mass_budget is not None:
        cons.append({"type": "ineq", "fun": lambda s: 1.0 - problem.mass(phys(s)) / mass_budget})
    s0 = (np.asarray(x0) - lo) / (hi - lo)
    res = minimize(
        f,
        s0,
        method="SLSQP",
        bounds=[(0.0, 1.0)] * len(lo),
        constraints=cons,
        options={"maxiter": maxiter, "ftol": 1e-10, "eps": 1e-6},
    )
    x = phys(res.x)
    return x, f(res.x), count[0]


def _sensitivity(
    problem: DesignProblem, runner: Runner, x: np.ndarray, f0: float
) -> dict[str, dict[str, Any]]:
    point = DesignPoint(problem)
    out: dict[str, dict[str, Any]] = {}
    tasks, where = [], []
    for i, (lo, hi) in enumerate(problem.bounds):
        h = 0.01 * (hi - lo)
        for sign in (-1.0, 1.0):
            xi = x.copy()
            xi[i] = min(max(x[i] + sign * h, lo), hi)
            tasks.append(problem.values(xi))
            where.append((i, xi[i]))
    vals = [
        r["objective"]
        for r in runner.map(
            point.evaluate_many, tasks, label="sensitivity", warm=warm_integrators, batched=True
        )
    ]
    for i, name in enumerate(problem.names):
        (_, xm), (_, xp) = where[2 * i], where[2 * i + 1]
        fm, fp = vals[2 * i], vals[2 * i + 1]
        deriv = (fp - fm) / (xp - xm) if xp != xm else math.nan
        lo, hi = problem.bounds[i]
        tol = 1e-6 * (hi - lo)
        active = "lower" if x[i] <= lo + tol else "upper" if x[i] >= hi - tol else ""
        out[name] = {
            "derivative": deriv,
            "elasticity": deriv * x[i] / f0 if f0 else math.nan,
            "active": active,
        }
    return out


def optimise(
    problem: DesignProblem,
    runner: Runner | None = None,
    *,
    seed: int = 0,
    popsize: int = 10,
    maxiter: int = 30,
    tol: float = 1e-4,
    polish: bool = True,
) -> OptimisationResult:
    """Minimise the robust t_cr objective over the design variables.

    Parameters
    ----------
    problem : DesignProblem
    runner : Runner, optional
        Execution of the generations (local processes, Dask, resume store).
    seed : int
        Seed of differential evolution.
    popsize : int
        Population per design variable (SciPy's ``popsize``).
    maxiter : int
        Largest number of generations.
    tol : float
        Relative convergence tolerance of the population's objective spread.
    polish : bool
        Finish with SLSQP in scaled variables.
    """
    from scipy.optimize import NonlinearConstraint, differential_evolution

    runner = runner or Runner(workers=1)
    check_range("popsize", popsize, 2, 1000)
    check_range("maxiter", maxiter, 1, 100_000)
    gen = _GenerationMap(problem, runner)
    res = differential_evolution(
        lambda x: gen(None, [x])[0],
        problem.bounds,
        constraints=NonlinearConstraint(problem.constraints, 0.0, np.inf),
        seed=int(seed),
        popsize=int(popsize),
        maxiter=int(maxiter),
        tol=tol,
        polish=False,
        updating="deferred",
        workers=gen,
        init="sobol",
    )
    x, f = np.asarray(res.x, dtype=float), float(res.fun)
    n_eval = gen.n_eval
    message = str(res.message).rstrip(".")  # scipy's sentence; clauses follow it
    if polish:
        xp, fp, n = _polish(problem, runner, x)
        n_eval += n
        if fp <= f and problem.feasible(xp):
            x, f = xp, fp
            message += "; SLSQP polish improved it"
    checked = DesignPoint(problem, check_convergence=True)
    base_x = problem.baseline()
    opt, base = runner.map(
        checked.evaluate_many, [problem.values(x), problem.values(base_x)], label="check",
        warm=warm_integrators, batched=True,
    )  # fmt: skip
    return OptimisationResult(
        problem,
        x,
        f,
        base["objective"],
        opt,
        base,
        problem.mass(x),
        problem.mass(base_x),
        problem.constraints(x),
        _sensitivity(problem, runner, x, f),
        n_eval,
        message,
    )
