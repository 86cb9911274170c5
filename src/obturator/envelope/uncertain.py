"""Uncertain inputs: distributions, the map from standard-normal space, point functions.

Distributions are the package's :class:`obturator.sweeps.Distribution`
(``normal:MEAN,SD``, ``uniform:LO,HI``, ``lognormal:MEDIAN,SIGMA_LN``,
``truncnormal:MEAN,SD,LO,HI``). Reliability and sensitivity methods work in a
space of independent standard normal variables z; :func:`ppf` maps each
z_i to its input by the inverse-CDF (Rosenblatt) transform x_i = F_i^-1(Phi(z_i)),
so every input may have any of the four distributions.

:func:`performance` turns a point function (a :class:`~obturator.envelope.model.FlightModel`
or a :class:`RigModel`) and a :class:`~obturator.runs.Runner`
into the vectorised function of input lists that the studies call.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.special import ndtr, ndtri
from scipy.stats import truncnorm

from ..errors import InputError
from ..runs import Runner
from ..solve import SolverOptions
from ..sweeps import Distribution, SweepSpec
from ..sweeps.distributions import parse_distribution_args, split_assignment, support
from .model import INPUTS, opening_rows, warm_integrators

__all__ = [
    "RIG_INPUTS",
    "RigModel",
    "parse_input_distribution",
    "check_point_support",
    "ppf",
    "points_from_normal",
    "points_from_uniform",
    "performance",
    "Performance",
]

#: Inputs the spin-rig model accepts (as :class:`obturator.sweeps.SweepSpec`).
RIG_INPUTS = ("spin_rate", "mu_s", "theta0_deg", "density", "hole_radius", "gap")

_HELP = "normal:MEAN,SD | uniform:LO,HI | lognormal:MEDIAN,SIGMA_LN | truncnormal:MEAN,SD,LO,HI"


def parse_input_distribution(
    text: str, allowed: Sequence[str] = tuple(INPUTS)
) -> tuple[str, Distribution]:
    """Parse ``NAME=KIND:ARGS`` (e.g. ``mu_s=normal:0.35,0.03``, ``gap=normal:50.8,2.5 um``).

    The numbers are read as a sweep axis reads them (SI unless a unit is written:
    one after the last number applies to all;
    :func:`obturator.sweeps.distributions.parse_distribution_args`), and the
    distribution is checked against the input's range in
    :data:`obturator.params.PARAMS` (:func:`~obturator.sweeps.distributions.check_support`).

    Parameters
    ----------
    text : str
    allowed : sequence of str
        Input names accepted (hyphens in NAME are read as underscores).
    """
    from ..params import PARAMS

    name, kind, args = split_assignment(text, "vary", f"NAME=KIND:ARGS ({_HELP})", ":")
    name = name.strip().replace("-", "_")
    if name not in allowed:
        raise InputError("vary", f"unknown input {name!r}; allowed: {', '.join(allowed)}")
    par = PARAMS.get(name)
    unit = par.pint_unit if par is not None else INPUTS[name].unit.replace("1", "")
    rng = par.range if par is not None else None
    return name, parse_distribution_args(name, kind, args, unit, rng)


def check_point_support(
    model: Callable[..., Any], dists: Mapping[str, Distribution], unit_of: Mapping[str, str]
) -> None:
    """Refuse a distribution whose support's ends the model refuses as inputs.

    Each end of :func:`~obturator.sweeps.distributions.support` is built alone (the
    other inputs at their nominal values) by the model's own checks
    (:meth:`FlightModel.build`, or the spin-rig case of :class:`RigModel`), which hold
    limits the registry's ranges do not (the trajectory's Mach and altitude, the
    hole inside the ball), so a study never samples points that are all invalid.

    Raises
    ------
    InputError
        Naming the input, the distribution, the end and the model's reason.
    """
    build = getattr(model, "build", None)
    if build is None and isinstance(model, RigModel):
        spec = model._spec()
        build = spec.build_case
    if build is None:
        return
    for name, dist in dists.items():
        for end in support(dist):
            try:
                build({name: end})
            except InputError as exc:
                u = unit_of.get(name, "")
                u = "" if u in ("", "1") else f" {u}"
                form = "uniform:LO,HI" if dist.kind == "uniform" else "truncnormal:MEAN,SD,LO,HI"
                raise InputError(
                    name,
                    f"{dist} draws {end:.6g}{u}, which the model refuses ({exc}); "
                    f"use {form} with LO, HI inside the allowed range",
                ) from None


def ppf(dist: Distribution, z: np.ndarray) -> np.ndarray:
    """Input values F^-1(Phi(z)) for standard-normal z (same shape)."""
    p = dist.params
    z = np.asarray(z, dtype=float)
    if dist.kind == "normal":
        return p[0] + p[1] * z
    if dist.kind == "lognormal":
        return p[0] * np.exp(p[1] * z)
    if dist.kind == "uniform":
        return p[0] + (p[1] - p[0]) * ndtr(z)
    a, b = (p[2] - p[0]) / p[1], (p[3] - p[0]) / p[1]
    return truncnorm.ppf(ndtr(z), a, b, loc=p[0], scale=p[1])


def points_from_normal(dists: Mapping[str, Distribution], z: np.ndarray) -> list[dict[str, float]]:
    """Input dicts for the rows of z (shape (n, d), columns in `dists` order)."""
    names = list(dists)
    z = np.atleast_2d(np.asarray(z, dtype=float))
    if z.shape[1] != len(names):
        raise InputError("z", f"expected {len(names)} columns, got {z.shape[1]}")
    cols = [ppf(dists[k], z[:, j]) for j, k in enumerate(names)]
    return [{k: float(c[i]) for k, c in zip(names, cols, strict=True)} for i in range(z.shape[0])]


def points_from_uniform(dists: Mapping[str, Distribution], u: np.ndarray) -> list[dict[str, float]]:
    """Input dicts for the rows of u in the unit hypercube (probability space)."""
    u = np.clip(np.asarray(u, dtype=float), 1e-12, 1.0 - 1e-12)
    return points_from_normal(dists, ndtri(u))


@dataclass(frozen=True)
class RigModel:
    """t_cr on the spin rig (Table 1 "gravitational model", Eqs. 56-61) for given inputs.

    Built with :meth:`obturator.sweeps.SweepSpec.build_case`, so the
    rig's normal load follows the ball's weight when density or hole radius
    are varied (thesis Figs. 16-17), as in ``obturator sweep``.

    Parameters
    ----------
    varied : tuple of str
        Names of the inputs that will be given (subset of :data:`RIG_INPUTS`).
    fixed : mapping
        Values held fixed (SI).
    options : SolverOptions
    check_convergence : bool
        Status 2 when the package's :func:`obturator.solve.convergence_check`
        moves t_cr by more than 1e-3.
    """

    varied: tuple[str, ...] = ()
    fixed: Mapping[str, float] = field(default_factory=dict)
    options: SolverOptions = field(default_factory=SolverOptions)
    check_convergence: bool = True

    def __post_init__(self) -> None:
        for k in (*self.varied, *self.fixed):
            if k not in RIG_INPUTS:
                raise InputError("vary", f"{k!r} is not a rig input; allowed: {RIG_INPUTS}")
        object.__setattr__(self, "varied", tuple(self.varied))
        object.__setattr__(self, "fixed", dict(self.fixed))

    def _spec(self) -> SweepSpec:
        fixed = dict(self.fixed)
        for k in ("density", "hole_radius"):
            if k in self.varied and k not in fixed:
                fixed[k] = {"density": 7669.6, "hole_radius": 4.72e-3}[k]
        return SweepSpec("spin-rig", {}, fixed, options=self.options)

    def identity(self) -> dict[str, Any]:
        """JSON-ready description (resume store)."""
        return {
            "rig": self._spec().identity(),
            "varied": list(self.varied),
            "check_convergence": self.check_convergence,
        }

    def evaluate_many(self, values: Sequence[Mapping[str, float]]) -> list[dict[str, Any]]:
        """``t_cr`` [s], ``status`` and ``change`` of many points as :class:`FlightModel`
        returns them, through the front door (lanes) with batched convergence checks."""
        spec = self._spec()
        cases: list[Any] = []
        for v in values:
            try:
                cases.append(spec.build_case(v))
            except InputError as exc:
                cases.append(exc)
        return opening_rows(cases, self.options, self.check_convergence)

    def __call__(self, values: Mapping[str, float]) -> dict[str, Any]:
        """One point (:meth:`evaluate_many` of one)."""
        return self.evaluate_many([values])[0]


#: A vectorised performance function: input dicts -> (t_cr [s], status) arrays.
Performance = Callable[[list[dict[str, float]]], tuple[np.ndarray, np.ndarray]]


def performance(
    model: Callable[[Mapping[str, float]], dict[str, Any]], runner: Runner, label: str
) -> Performance:
    """Wrap a point function and a runner as a vectorised :data:`Performance`."""

    many = getattr(model, "evaluate_many", None)  # the lanes, a chunk of points per call

    def f(points: list[dict[str, float]]) -> tuple[np.ndarray, np.ndarray]:
        if many is not None:
            res = runner.map(many, points, label=label, warm=warm_integrators, batched=True)
        else:
            res = runner.map(model, points, label=label, warm=warm_integrators)
        t = np.array([r["t_cr"] for r in res], dtype=float)
        s = np.array([r["status"] for r in res], dtype=np.int8)
        return t, s

    return f
