"""A surrogate of each candidate's t_cr over (setting, parameters), from exact solves.

Every t_cr here is an exact solve through the front door
:func:`obturator.solve.opening_times` (with the validation's solver settings). At every
candidate setting s the surrogate of model m is the second-order expansion in the
whitened parameters z (x = x_hat + L z, L the Cholesky factor of the Laplace posterior,
so z ~ N(0, I)) with a diagonal curvature:

    t(s, z) ~ t0(s) + sum_j g_j(s) z_j + 1/2 sum_j c_j(s) z_j^2,

g_j and c_j from central differences one posterior SD along each column of L
(2k + 1 solves per setting and model). Over the posterior its mean and covariance are,
exactly for this quadratic form,

    E t(s) = t0 + 1/2 sum_j c_j,   Cov(t(s), t(s')) = sum_j g_j g_j' + 1/2 sum_j c_j c_j'.

The campaigns of :mod:`.campaigns` draw their data from exact solves and compare them
with this surrogate at the same draws: its error over the posterior is measured, not
assumed (:attr:`DesignResult.surrogate_error`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._docs import field_docs
from ..solve import opening_times
from ..validation.candidates import get_candidates
from ..validation.evaluate import VALIDATION_OPTIONS
from .posterior import Posterior
from .settings import NEW_BALL, Setting, design_case, settings_of

__all__ = ["Surrogate", "assemble", "opening_time_table", "stencil", "surrogate_tasks"]


def opening_time_table(task: Mapping[str, Any]) -> list[list[float | None]]:
    """Exact t_cr [s] of parameter points x settings (a runner task; None: not opened).

    `task`: ``model``, ``values`` (list of parameter dicts), ``settings`` (list of
    :meth:`Setting.to_dict`), ``t_max`` [s]. One call of
    :func:`obturator.solve.opening_times` for all of them (full lanes).
    """
    (cand,) = get_candidates([str(task["model"])])
    settings = settings_of(task["settings"])
    t_max = float(task["t_max"])
    # points that differ only in the parameter copy a ball does not use (the new ball's
    # on the as-built ball, the as-built ball's on a new one) give one case: solved once
    keys: dict[tuple[Any, ...], int] = {}
    cases, where = [], []
    for v in task["values"]:
        for s in settings:
            used = {k: x for k, x in v.items() if NEW_BALL not in k}
            if not s.is_as_built_ball:
                used.update({k.removesuffix(NEW_BALL): x for k, x in v.items() if NEW_BALL in k})
            key = (tuple(sorted(used.items())), s)
            if key not in keys:
                keys[key] = len(cases)
                cases.append(design_case(cand, s, v, t_max))
            where.append(keys[key])
    t, _, _ = opening_times(cases, VALIDATION_OPTIONS)
    table = t[np.array(where, dtype=np.intp)].reshape(len(task["values"]), len(settings))
    return [[float(x) if np.isfinite(x) else None for x in row] for row in table]


def stencil(post: Posterior) -> NDArray[np.float64]:
    """The 2k + 1 points (rows, optimiser variables): x_hat, then x_hat +- L e_j."""
    lcol = post.cholesky.T  # row j: column j of L
    pts = [post.mean]
    for j in range(len(post.params)):
        pts += [post.mean + lcol[j], post.mean - lcol[j]]
    return np.array(pts)


@field_docs
@dataclass(frozen=True)
class Surrogate:
    """The expansion of one model's t_cr at every candidate setting (module notes)."""

    #: Name of the candidate expanded.
    model: str
    #: t_cr at x_hat at each of the S settings [s], shape (S,).
    t0: NDArray[np.float64]
    #: First-order coefficients g_j at each setting [s per posterior SD], shape (S, k) for the
    #: k parameters.
    grad: NDArray[np.float64]
    #: Curvatures c_j at each setting [s per posterior SD^2], shape (S, k).
    curv: NDArray[np.float64]

    @classmethod
    def from_table(cls, model: str, table: NDArray[np.float64]) -> Surrogate:
        """From the exact t_cr at the :func:`stencil` points (rows) x settings (columns)."""
        t0 = table[0]
        plus, minus = table[1::2], table[2::2]
        grad = (0.5 * (plus - minus)).T
        curv = (plus + minus - 2.0 * t0).T
        return cls(model, t0, grad, curv)

    @property
    def valid(self) -> NDArray[np.bool_]:
        """Settings where every stencil point opened (others are not design candidates)."""
        return np.isfinite(self.t0) & np.all(np.isfinite(self.grad), axis=1)

    def mean(self, idx: Sequence[int] | NDArray[np.intp]) -> NDArray[np.float64]:
        """Posterior mean of t_cr at the settings `idx` [s] (an index array of any shape:
        one mean per index)."""
        i = np.asarray(idx, dtype=np.intp)
        return self.t0[i] + 0.5 * self.curv[i].sum(axis=-1)

    def covariance(self, idx: Sequence[int] | NDArray[np.intp]) -> NDArray[np.float64]:
        """Posterior covariance of t_cr between the settings `idx` [s^2]; `idx` of shape
        (..., N) gives one N x N covariance per leading index (stacked plans)."""
        i = np.asarray(idx, dtype=np.intp)
        g, c = self.grad[i], self.curv[i]
        return g @ g.swapaxes(-1, -2) + 0.5 * (c @ c.swapaxes(-1, -2))

    def sd(self) -> NDArray[np.float64]:
        """Posterior SD of t_cr at every setting [s]."""
        return np.sqrt(np.sum(self.grad**2, axis=1) + 0.5 * np.sum(self.curv**2, axis=1))

    def at(self, idx: Sequence[int] | NDArray[np.intp], z: NDArray[np.float64]) -> NDArray:
        """t_cr [s] at whitened draws z (rows) and settings `idx` (columns)."""
        i = np.asarray(idx, dtype=np.intp)
        z = np.atleast_2d(z)
        return self.t0[i] + z @ self.grad[i].T + 0.5 * (z * z) @ self.curv[i].T


def surrogate_tasks(
    post: Posterior, settings: Sequence[Setting], t_max: float, chunk: int
) -> list[dict[str, Any]]:
    """Runner tasks of the exact solves behind one model's surrogate (settings in chunks)."""
    values = [post.to_values(x) for x in stencil(post)]
    rows = [s.to_dict() for s in settings]
    return [
        {"model": post.model, "values": values, "settings": rows[i : i + chunk], "t_max": t_max}
        for i in range(0, len(rows), chunk)
    ]


def assemble(model: str, results: Sequence[list[list[float | None]]]) -> Surrogate:
    """The surrogate from the results of :func:`surrogate_tasks` (in task order)."""
    table = np.concatenate(
        [np.array([[np.nan if v is None else v for v in row] for row in r]) for r in results],
        axis=1,
    )
    return Surrogate.from_table(model, table)
