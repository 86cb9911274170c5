"""Global sensitivity of t_cr: Sobol indices with SALib.

Variance-based (Sobol) indices of the opening time with respect to independent
uncertain inputs: the first-order index S1_i = V[E(Y|X_i)]/V(Y) (the share of
the variance that X_i explains alone) and the total index
ST_i = E[V(Y|X_~i)]/V(Y) (alone and in interactions). The sampling and the
estimators are SALib's (Herman and Usher, JOSS 2, 2017; SALib 1.5+):
``SALib.sample.sobol.sample`` draws a scrambled Sobol sequence in Saltelli's
scheme, N (d + 2) model runs without second-order indices, and
``SALib.analyze.sobol.analyze`` applies the Saltelli (2010) / Jansen
estimators with bootstrap confidence intervals (``num_resamples`` resamples).

SALib samples the unit hypercube; each column is mapped to its input by the
inverse CDF of the input's distribution
(:func:`obturator.envelope.uncertain.points_from_uniform`), which leaves the
Sobol indices unchanged (they depend on the input distributions, not on how
they are parametrised).

Points that do not open by t_max have no t_cr; they are censored at the
largest t_cr seen (or t_max) and counted in the results' attributes.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from ..errors import InputError, check_range
from ..sweeps import Distribution
from .coupled import STATUS_OPENED, STATUS_UNCONVERGED
from .uncertain import points_from_uniform

__all__ = ["sobol_indices", "sobol_warnings"]

VectorFunction = Callable[[list[dict[str, float]]], tuple[np.ndarray, np.ndarray]]


def sobol_indices(
    func: VectorFunction,
    dists: Mapping[str, Distribution],
    n_base: int = 256,
    *,
    seed: int = 0,
    confidence: float = 0.95,
    resamples: int = 1000,
    censor: float | None = None,
) -> Any:
    """First-order and total Sobol indices of t_cr with bootstrap confidence intervals.

    Parameters
    ----------
    func : callable
        Vectorised model: list of input dicts -> (values, status) arrays;
        :func:`obturator.envelope.uncertain.performance` builds one from a
        point model, or any function for testing (status 1 = valid).
    dists : mapping of str to Distribution
        Independent uncertain inputs (at least two).
    n_base : int
        SALib's N, a power of two >= 8 (model runs: N (d + 2)).
    seed : int
        Seed of the scrambled Sobol sequence and of the bootstrap.
    confidence : float
        Level of the bootstrap intervals.
    resamples : int
        Bootstrap resamples.
    censor : float, optional
        Value given to points without t_cr [s]; default the largest t_cr seen.

    Returns
    -------
    xarray.Dataset
        Dimension ``input``: ``S1``, ``S1_conf``, ``ST``, ``ST_conf`` (the
        ``_conf`` variables are half-widths of the intervals); attributes
        ``n_base``, ``n_evaluations``, ``n_censored``, ``n_unconverged``,
        ``mean``, ``variance``, ``confidence``.
    """
    import xarray as xr
    from SALib.analyze import sobol as sobol_analyze
    from SALib.sample import sobol as sobol_sample

    names = list(dists)
    if len(names) < 2:
        raise InputError("vary", "Sobol indices need at least two uncertain inputs")
    n = int(check_range("n_base", n_base, 8, 2**20))
    if n & (n - 1):
        raise InputError("n_base", f"{n} is not a power of two (SALib's Sobol sequence)")
    check_range("confidence", confidence, 0.5, 1.0, hi_open=True)
    resamples = int(check_range("resamples", resamples, 10, 100_000))
    problem = {"num_vars": len(names), "names": names, "bounds": [[0.0, 1.0]] * len(names)}
    u = sobol_sample.sample(problem, n, calc_second_order=False, scramble=True, seed=int(seed))
    y, status = func(points_from_uniform(dists, u))
    y = np.asarray(y, dtype=float)
    ok = np.isin(status, (STATUS_OPENED, STATUS_UNCONVERGED)) & np.isfinite(y)
    n_censored = int((~ok).sum())
    if not ok.any():
        raise InputError("vary", "no sample opened: Sobol indices are undefined")
    fill = float(np.max(y[ok])) if censor is None else float(censor)
    y = np.where(ok, y, fill)
    si = sobol_analyze.analyze(
        problem,
        y,
        calc_second_order=False,
        num_resamples=resamples,
        conf_level=confidence,
        print_to_console=False,
        # SALib's analyze seeds its bootstrap only `if seed:`, so seed 0 would leave the
        # intervals unseeded (not reproducible, nor identical after a resume)
        seed=int(seed) + 1,
    )
    data = {
        key: ("input", np.asarray(si[key], dtype=float), {"units": "1", "long_name": text})
        for key, text in (
            ("S1", "first-order Sobol index"),
            ("S1_conf", "half-width of the bootstrap interval of S1"),
            ("ST", "total Sobol index"),
            ("ST_conf", "half-width of the bootstrap interval of ST"),
        )
    }
    attrs = {
        "title": "Sobol indices of t_cr",
        "n_base": n,
        "n_evaluations": int(y.size),
        "n_censored": n_censored,
        "censor_value": fill if n_censored else math.nan,
        "n_unconverged": int((np.asarray(status) == STATUS_UNCONVERGED).sum()),
        "mean": float(y.mean()),
        "variance": float(y.var()),
        "confidence": confidence,
        "resamples": resamples,
        "seed": int(seed),
        "sampler": "SALib.sample.sobol (Saltelli scheme, scrambled), no second order",
        "distributions": "; ".join(f"{k}={dists[k]}" for k in names),
    }
    return xr.Dataset(data, coords={"input": ("input", names)}, attrs=attrs)


#: Index and interval scale below which nothing is reported [-]: an input with no
#: influence estimates 0 +- a few 1e-3, which is a clear answer, not noise to warn of.
_SLACK = 0.01


def sobol_warnings(ds: Any) -> list[str]:
    """What a reader of the Sobol indices must be told: intervals wider than the indices,
    indices outside [0, 1].

    A Sobol index is a share of the variance, in [0, 1]; Saltelli's estimators are not
    bounded, and with too few base samples they leave that range or carry bootstrap
    intervals wider than the index itself (Saltelli et al. 2010, sec. 4). Either means
    the estimate is noise: more ``--samples`` (the base sample count N) are needed.

    Parameters
    ----------
    ds : xarray.Dataset
        The result of :func:`sobol_indices` (``S1``, ``S1_conf``, ``ST``, ``ST_conf``
        over ``input``; attribute ``n_base``).

    Returns
    -------
    list of str
        One line per problem (empty: none).
    """
    out: list[str] = []
    names = [str(x) for x in ds["input"].values]
    for key in ("S1", "ST"):
        value, conf = np.asarray(ds[key], dtype=float), np.asarray(ds[f"{key}_conf"], dtype=float)
        outside = [
            f"{n} {v:.3g}"
            for n, v in zip(names, value, strict=True)
            if not -_SLACK <= v <= 1.0 + _SLACK
        ]
        wide = [
            f"{n} {v:.3g} +- {c:.2g}"
            for n, v, c in zip(names, value, conf, strict=True)
            if c > abs(v) and c > _SLACK
        ]
        if outside:
            out.append(f"{key} outside [0, 1] (a variance share cannot be): {', '.join(outside)}")
        if wide:
            out.append(f"{key} interval wider than the index: {', '.join(wide)}")
    if out:
        n = ds.attrs.get("n_base", "N")
        out.append(f"the estimates are noise at --samples {n}: raise it (e.g. 4x)")
    return out
