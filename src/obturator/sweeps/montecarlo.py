"""Monte Carlo studies of t_cr under uncertain inputs.

:func:`monte_carlo` draws the inputs (:mod:`.distributions`), computes every
sample like a sweep point (on the same :class:`~obturator.runs.Runner`, :mod:`.sweep`) and
summarises t_cr by order statistics (:mod:`.stats`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import InputError
from ..runs import Runner, study_digest
from ..solve import SolverOptions
from .distributions import (
    Distribution,
    check_sample_cases,
    check_samples,
    distributions,
    sample_inputs,
)
from .export import (
    T_CR_ATTRS,
    check_distinct_outputs,
    common_attrs,
    coord_attrs,
    route_attrs,
    status_attrs,
    write_outputs,
)
from .spec import SweepSpec
from .stats import CI_METHOD, MonteCarloSummary, summarize_monte_carlo
from .sweep import run_points
from .table import StudyTable

if TYPE_CHECKING:  # pragma: no cover
    import xarray

#: Largest Monte Carlo sample. At 10^5 the order-statistic interval of a 5 %
#: quantile is +-0.14 percentage points wide (1.96 sqrt(p (1 - p) / n)), finer than
#: the model's own accuracy. Drawing the inputs (one seeded generator per sample, so
#: results do not depend on chunking) is Python work per sample: at this bound the
#: drawing and the run take seconds, with a progress bar and an estimate; ten times
#: more would hold the first point back by most of a minute (``docs/benchmarks.md``,
#: history). Rare-event probabilities: ``obturator probability`` (importance sampling).
MAX_SAMPLES = 100_000

__all__ = ["monte_carlo", "monte_carlo_table", "monte_carlo_summary", "MAX_SAMPLES"]


def monte_carlo(
    case: str | SweepSpec = "spin-rig",
    vary: Mapping[str, Distribution | str] | Sequence[str] = (),
    *,
    samples: int,
    seed: int,
    quantiles: Sequence[float] = (0.05, 0.5, 0.95),
    confidence: float = 0.95,
    runner: Runner | None = None,
    csv: str | os.PathLike[str] | None = None,
    **model: Any,
) -> xarray.Dataset:
    """Monte Carlo study of t_cr under uncertain inputs.

    Every opened sample is checked for convergence by default (tolerances / 10,
    friction width / 10, another regularisation family; four times the cost):
    a sample whose t_cr moves by more than 1e-3 gets status ``UNCONVERGED``
    (4, ``opened_not_converged``), stays in the dataset, and is excluded from the
    quantiles and the mean (counted in ``n_unconverged``).

    Parameters
    ----------
    case : {"spin-rig", "flight"} or SweepSpec
        The case, with the model settings in `model`; or the whole study without
        axes as a :class:`SweepSpec` (then no `model` settings).
    vary : mapping of str to Distribution or str, or sequence of str
        Uncertain inputs: ``{"mu_s": Distribution("normal", (0.5473, 0.03))}``,
        ``{"mu_s": "normal:0.5473,0.03"}`` or ``["mu_s=normal:0.5473,0.03"]``
        (see :func:`~.distributions.parse_distribution`); any name in
        :data:`~obturator.params.SWEEP_PARAMS`.
    samples : int
        Number of samples n >= 1.
    seed : int
        Root seed (>= 0); sample i uses ``SeedSequence(seed).spawn(n)[i]``.
    quantiles : sequence of float
        Probabilities reported, default 5, 50 and 95 %.
    confidence : float
        Confidence level of the intervals.
    runner : Runner, optional
        Where and how the samples run, as in :func:`~.sweep.run_sweep` (its store is
        the NetCDF output, and its resume store holds the samples' results).
    csv : path, optional
        Flat CSV table of the samples, written after the NetCDF file.
    **model
        The fields of :class:`SweepSpec` other than case and axes: ``fixed`` (inputs
        held fixed, e.g. ``{"spin_rate": 300.0}``), ``torque_model``, ``spin_mode``,
        ``options``, ``t_max``, ``check_convergence`` (default True here).

    Returns
    -------
    xarray.Dataset
        Along ``sample``: the sampled inputs (with units), ``t_cr`` [s] and
        ``status``; along ``quantile``: ``t_cr_quantile``, ``t_cr_quantile_lower``,
        ``t_cr_quantile_upper`` [s] (inf = beyond t_max) and ``ci_coverage``;
        attributes with the distributions, seed, counts, fraction not opened
        and its interval, and the solver settings.
    """
    return monte_carlo_table(
        case, vary, samples=samples, seed=seed, quantiles=quantiles, confidence=confidence,
        runner=runner, csv=csv, **model,
    ).to_dataset()  # fmt: skip


def monte_carlo_table(
    case: str | SweepSpec = "spin-rig",
    vary: Mapping[str, Distribution | str] | Sequence[str] = (),
    *,
    samples: int,
    seed: int,
    quantiles: Sequence[float] = (0.05, 0.5, 0.95),
    confidence: float = 0.95,
    runner: Runner | None = None,
    csv: str | os.PathLike[str] | None = None,
    **model: Any,
) -> StudyTable:
    """:func:`monte_carlo`, its results as arrays (:class:`~.table.StudyTable`, the form
    the command line writes its files from without xarray); arguments as there."""
    dists = distributions(vary)
    n = _whole("samples", samples, 1, MAX_SAMPLES)
    seed_i = _whole("seed", seed, 0, None)
    runner = runner or Runner()
    check_distinct_outputs(runner.store, csv)
    spec = _study(case, dists, model)
    values = sample_inputs(dists, n, seed_i)
    check_samples(values)
    check_sample_cases(spec, values)
    names = tuple(values)
    table = np.column_stack([values[k] for k in names]) if names else np.empty((n, 0))
    ident = {
        "spec": spec.identity(),
        "vary": {k: str(d) for k, d in dists.items()},
        "seed": seed_i,
        "samples": n,
    }
    digest = study_digest(ident)
    out = run_points(
        spec,
        names,
        lambda idx: table[idx],
        n,
        digest,
        runner,
        label="monte carlo",
        unit="samples",
        extra_outputs=() if csv is None else (str(csv),),
    )
    t_max_used = spec.t_max if spec.t_max is not None else spec.build_case({}).t_max
    summ = summarize_monte_carlo(
        out.t_cr, out.status, t_max=t_max_used, quantiles=quantiles, confidence=confidence
    )
    data: dict[str, Any] = {k: ("sample", values[k], coord_attrs(k)) for k in names}
    data["t_cr"] = ("sample", out.t_cr, T_CR_ATTRS)
    data["status"] = ("sample", out.status, status_attrs())
    data["route"] = ("sample", out.route, route_attrs())
    data |= _quantile_variables(summ)
    coords: dict[str, Any] = {
        "sample": ("sample", np.arange(n), {"long_name": "sample number"}),
        "quantile": ("quantile", [q.probability for q in summ.quantiles], {"units": "1"}),
    }
    for name, value in spec.resolved().items():
        if name not in names and value is not None:
            coords[name] = ((), value, coord_attrs(name))
    attrs: dict[str, Any] = {
        "title": "obturator Monte Carlo study of t_cr",
        "distributions": "; ".join(f"{k}={d}" for k, d in dists.items()) or "none",
        "seed": seed_i,
        "samples": n,
        "seeding": "numpy.random.SeedSequence(seed).spawn(samples), one child per sample",
        **_summary_attrs(summ),
        **common_attrs(spec),
        "study_hash": digest,
        # what lies outside the Appendix B runs ("" if nothing; obturator.model.validity)
        "outside_validated_data": out.outside_validated_data or "",
    }
    result = StudyTable(data, coords, attrs)
    write_outputs(result, runner, csv)
    return result


def _whole(field: str, value: Any, lo: int, hi: int | None) -> int:
    """`value` as a whole number in [lo, hi] (no upper bound if hi is None)."""
    try:
        n = int(value)
    except (TypeError, ValueError):
        raise InputError(field, f"expected a whole number, got {value!r}") from None
    if n < lo or (hi is not None and n > hi):
        allowed = f">= {lo}" if hi is None else f"[{lo}, {hi}] (obturator.sweeps.MAX_SAMPLES)"
        raise InputError(field, f"{n} is outside the allowed range {allowed}")
    return n


def _study(case: str | SweepSpec, dists: Mapping[str, Distribution], model: dict) -> SweepSpec:
    """The study the samples vary: `case` with the `model` settings (or the SweepSpec
    given), checked against the varied names."""
    if isinstance(case, SweepSpec):
        if model or case.axes:
            raise InputError("case", "a SweepSpec without axes, and no further settings")
        spec = case
    else:
        model = {"check_convergence": True, **model}
        model["check_convergence"] = bool(model["check_convergence"])
        model["options"] = model.get("options") or SolverOptions()
        spec = SweepSpec(case, {}, dict(model.pop("fixed", None) or {}), **model)
    for name in dists:
        if name in spec.fixed:
            raise InputError(name, "is both varied and fixed")
        spec._check_name(name)
    return spec


def _quantile_variables(summ: MonteCarloSummary) -> dict[str, Any]:
    """The t_cr quantiles with their intervals and coverage, along ``quantile``."""
    q_attrs = {"units": "s", "comment": "inf: the order statistic did not open by t_max"}
    qs = summ.quantiles
    return {
        "t_cr_quantile": ("quantile", [q.value for q in qs], q_attrs),
        "t_cr_quantile_lower": ("quantile", [q.lower for q in qs], q_attrs),
        "t_cr_quantile_upper": ("quantile", [q.upper for q in qs], q_attrs),
        "ci_coverage": ("quantile", [q.coverage for q in qs], {"units": "1"}),
    }


def _summary_attrs(summ: MonteCarloSummary) -> dict[str, Any]:
    """The counts, the fraction not opened with its interval, mean and SD of t_cr."""
    return {
        "confidence": summ.confidence,
        "ci_method": CI_METHOD,
        "n_opened": summ.n_opened,
        "n_not_opened": summ.n_not_opened,
        "n_failed": summ.n_failed,
        "n_invalid": summ.n_invalid,
        "n_unconverged": summ.n_unconverged,
        "fraction_not_opened": summ.fraction_not_opened,
        "fraction_not_opened_ci": np.array(summ.fraction_not_opened_ci),
        "mean_t_cr_s": summ.mean_s,
        "std_t_cr_s": summ.std_s,
    }


def monte_carlo_summary(ds: xarray.Dataset | StudyTable) -> MonteCarloSummary:
    """Recompute the :class:`MonteCarloSummary` of a :func:`monte_carlo` study (its
    Dataset, or :func:`monte_carlo_table`'s arrays)."""
    table = StudyTable.of(ds)
    return summarize_monte_carlo(
        table.values("t_cr"),
        table.values("status"),
        t_max=float(table.attrs["t_max_s"]),
        quantiles=[float(q) for q in table.values("quantile")],
        confidence=float(table.attrs["confidence"]),
    )
