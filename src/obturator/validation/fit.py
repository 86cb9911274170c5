"""Maximum-likelihood fit of a candidate to measured opening times (issue 9, item 3).

Algorithm (effective-variance iteration, see :mod:`.likelihood`):

1. start from the candidate's default (or given) values, slopes g = 0;
2. with the effective SDs s_i fixed, minimise sum ((m_i - y_i)/s_i)^2 over the
   physical parameters by :func:`obturator.fitting.minimize_least_squares` (trust-region
   reflective, bounds, forward differences with a relative step of 1e-3 on
   the optimiser scale: large enough to step over the tiny ripple of t_cr in
   the parameters, small against their uncertainties);
3. recompute the secant slopes g_i at the new optimum and the ML sigmas, one per
   noise group (:func:`.likelihood.profile_noise`: per spin band, or pooled);
4. repeat 2-3 until -log L changes by less than 1e-3 (at most ``max_outer``
   passes). Without a spin error (``spin_sd = 0``) one pass is exact.

At fixed s_i, step 2 is the exact ML step; the outer loop is Orear's
effective-variance method for errors in variables (it neglects d s_i/d theta
in the gradient, a second-order effect at the optimum).

The optimiser, the Jacobian and the intervals are the fit engine's
(:mod:`obturator.fitting`); parameters, bounds and transforms are the fit
registry's (:data:`obturator.params.FIT_SPECS`). Uncertainties: standard
errors from the Gauss-Newton information J^T J of the scaled residuals at
the optimum (central differences), on the optimiser scale (log10 for
``slip_speed``), transformed by the delta method; Wald 95 % intervals with
the Student-t quantile for n - k degrees of freedom, clipped to the fit
bounds (an interval that reaches a bound: the parameter is not identified on
that side). For chosen parameters :func:`profile_interval` gives
profile-likelihood intervals instead (each probe a refit of the other
parameters with the slopes held at the best fit's).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from functools import partial
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._docs import field_docs
from ..errors import InputError, check_range
from ..fitting import (
    CHI2_95,
    LeastSquaresSettings,
    ParameterSet,
    central_jacobian,
    covariance_internal,
    minimize_least_squares,
    profile_limit,
    wald,
)
from ..solve import SolverOptions
from .candidates import PARAMETERS, Candidate
from .evaluate import DEFAULT_T_MAX, ModelEvaluator
from .floor import band_of
from .likelihood import (
    SPIN_SD,
    effective_sd,
    nll_terms,
    noise_groups,
    profile_noise,
    scaled_residuals,
)
from .results import CandidateFit

__all__ = [
    "CHI2_95",
    "COVARIANCE_STEP",
    "FitControls",
    "RunModels",
    "fit_candidate",
    "predict",
    "profile_interval",
]

# optimiser stopping (relative step of the parameters): tight in the first pass,
# whose valley (mu_s against v_s) is long and curved, looser in the later
# passes, which start next to the optimum; the parameters' standard errors are
# 1e-2 relative or more
_XTOL = 1e-6
_XTOL_LATER = 1e-4
_FTOL = 1e-8
#: Forward differences, relative step 1e-3 on the optimiser's scale (also the
#: central step of the covariance's Jacobian), unit variable scaling.
_SETTINGS = LeastSquaresSettings("2-point", 1e-3, 1.0, _XTOL, _FTOL, 1e-3)
#: The first pass (from the start values, far from the optimum) scales the variables
#: by the Jacobian's column norms: with unit scaling its trust region ignores that the
#: variables differ in leverage by orders of magnitude (one candidate's first pass
#: crawled along its valley unscaled and converged quickly scaled). The later passes,
#: which start next to the optimum, keep unit scaling: scaled there too, some
#: candidates stopped at a worse optimum; so do the fits given a start (subset fits
#: from the all-run fit, profile probes).
#:
#: Neither scaling suits every likelihood, so the first pass, scaled or not, has a
#: budget of :data:`_FIRST_PASS_EVALUATIONS`; one that uses it up is crawling, and a pass
#: with the other scaling from the same start follows, the lower cost of the two going
#: on. On the thesis data a converging first pass needs fewer evaluations than this
#: budget, and each scaling crawls for some candidate where the other converges (the
#: cases, from ``obturator validate``: ``docs/benchmarks.md``, history).
_FIRST_PASS_EVALUATIONS = 50
_SETTINGS_FIRST = replace(_SETTINGS, x_scale="jac", max_nfev=_FIRST_PASS_EVALUATIONS)
#: Central-difference step of the covariance's Jacobian (optimiser scale, relative).
COVARIANCE_STEP = _SETTINGS.covariance_step
_SETTINGS_STARTED = replace(_SETTINGS, max_nfev=_FIRST_PASS_EVALUATIONS)


def _parameters(cand: Candidate) -> ParameterSet:
    return ParameterSet(tuple(PARAMETERS[k] for k in cand.params))


@field_docs
@dataclass(frozen=True)
class FitControls:
    """How :func:`fit_candidate` iterates: a full fit by default; a profile probe
    holds the slopes, skips the covariance and stops earlier.
    """

    #: Fixed dt_cr/domega_p per run [s^2]: no outer iteration (profile probes).
    slopes: ArrayLike | None = None
    #: Effective-variance passes.
    max_outer: int = 4
    #: Compute the Wald covariance.
    covariance: bool = True
    #: Relative parameter step at which the first pass stops.
    xtol: float = _XTOL
    #: Run-to-run sigma per run [s] of the first pass (profile probes: the best fit's); default the
    #: rms residual of the start for every run.
    sigma: ArrayLike | None = None


Conditions = tuple[tuple[str, float], ...]


@dataclass
class RunModels:
    """A candidate's model at runs that may have their own settings (a data file's
    theta0, hole radius, density, mass, measured angle): one cached
    :class:`~.evaluate.ModelEvaluator` per distinct setting, the given one for the
    runs at Table 1 (all the thesis's runs: then this is that evaluator alone).

    Parameters
    ----------
    base : ModelEvaluator
        The candidate's evaluator at Table 1 settings.
    conditions : sequence of tuple, optional
        Per run, its settings as (name, value) pairs (empty: Table 1).
    """

    base: ModelEvaluator
    conditions: Sequence[Conditions] | None = None
    _by_setting: dict[Conditions, ModelEvaluator] = field(default_factory=dict, repr=False)

    def _groups(self, n: int) -> list[tuple[ModelEvaluator, NDArray[np.bool_] | None]]:
        cond = self.conditions
        if cond is None or not any(cond):
            return [(self.base, None)]
        if len(cond) != n:
            raise InputError("conditions", f"has {len(cond)} entries, expected {n}")
        out = []
        for c in dict.fromkeys(cond):
            if c not in self._by_setting:
                base = self.base
                self._by_setting[c] = (
                    base
                    if not c
                    else ModelEvaluator(
                        replace(base.candidate, conditions=c), base.t_max, base.options
                    )
                )
            out.append((self._by_setting[c], np.array([x == c for x in cond])))
        return out

    def _each(self, method: str, values: Sequence[float], w: NDArray[np.float64]) -> NDArray:
        out = np.empty(w.size)
        for ev, sel in self._groups(w.size):
            if sel is None:
                return getattr(ev, method)(values, w)
            out[sel] = getattr(ev, method)(values, w[sel])
        return out

    def opening_times(self, values: Sequence[float], w: NDArray[np.float64]) -> NDArray:
        """t_cr [s] of each run (NaN: censored)."""
        return self._each("opening_times", values, w)

    def slopes(self, values: Sequence[float], w: NDArray[np.float64]) -> NDArray:
        """Secant dt_cr/domega_p [s^2] of each run."""
        return self._each("slopes", values, w)

    def prefetch(self, many: Sequence[Sequence[float]], w: NDArray[np.float64]) -> None:
        """t_cr of each run at many parameter vectors, one batched solve per setting,
        into the evaluators' caches."""
        for ev, sel in self._groups(w.size):
            ev.opening_times_of(many, w if sel is None else w[sel])

    @property
    def counts(self) -> tuple[int, int]:
        """Integrations and failures over every evaluator."""
        evs = {id(e): e for e in (self.base, *self._by_setting.values())}.values()
        return sum(e.n_integrations for e in evs), sum(e.n_failed for e in evs)


@dataclass
class _Objective:
    """The model t_cr of one candidate at the runs, in the optimiser's variables."""

    params: ParameterSet
    evaluator: RunModels
    spin_rate: NDArray[np.float64]
    measured: NDArray[np.float64]
    t_max: float
    nfev: int = 0

    def model(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """Model t_cr [s] per run (NaN: censored)."""
        self.nfev += 1
        return self.evaluator.opening_times(self.params.from_internal(x), self.spin_rate)

    def prefetch(self, xs: Sequence[NDArray[np.float64]]) -> None:
        """Model t_cr at many points x in one batched solve, into the evaluator's cache."""
        self.evaluator.prefetch([self.params.from_internal(x) for x in xs], self.spin_rate)

    def residuals(self, sd: NDArray[np.float64]) -> Callable[[NDArray[np.float64]], NDArray]:
        """x -> (m_i - y_i) / s_i at fixed effective SDs (Gauss-Newton residuals)."""
        return lambda x: scaled_residuals(self.measured, self.model(x), sd, self.t_max)


class _Optimum(NamedTuple):
    x: NDArray[np.float64]
    model: NDArray[np.float64]
    slope: NDArray[np.float64]
    sigma: NDArray[np.float64]  # per run
    sigma_by_group: dict[str, float]
    success: bool
    message: str


def _effective_variance(
    obj: _Objective,
    x: NDArray[np.float64],
    spin_sd: float,
    controls: FitControls,
    groups: NDArray[np.str_],
    first: LeastSquaresSettings = _SETTINGS,
) -> _Optimum:
    """Steps 1-4 of the module notes: least squares at fixed s_i, then slopes and sigma;
    `first` is the first pass's settings."""
    y, t_max, w = obj.measured, obj.t_max, obj.spin_rate
    eiv = spin_sd > 0.0
    held = controls.slopes is not None
    g = np.asarray(controls.slopes, dtype=float).copy() if held else np.zeros(w.size)
    success, message = True, "no free parameters"
    m = obj.model(x)
    if controls.sigma is not None:
        sigma = np.asarray(controls.sigma, dtype=float).reshape(-1)
    else:
        # each group's rms residual at the start (the ML sigma without spin error)
        sigma = np.maximum(profile_noise(y, m, np.zeros(w.size), t_max, groups, 0.0)[0], 1e-3)
    nll_prev = math.inf
    # one pass is exact without spin error and with one sigma (the weights are equal)
    reweight = eiv or np.unique(groups).size > 1
    outer = 1 if (held or not reweight) else max(1, int(controls.max_outer))
    for it in range(outer):
        sd = effective_sd(sigma, np.where(np.isfinite(m), g, 0.0), spin_sd if eiv else 0.0)
        if len(obj.params):
            settings = first if it == 0 else _SETTINGS
            fit = partial(
                minimize_least_squares,
                obj.residuals(sd),
                x,
                obj.params.internal_bounds(),
                xtol=controls.xtol if it == 0 else _XTOL_LATER,
                prefetch=obj.prefetch,
            )
            best = fit(settings)
            if best.exhausted and it == 0:  # crawling: the other scaling, no budget
                other = "jac" if settings.x_scale == _SETTINGS.x_scale else _SETTINGS.x_scale
                best = min(best, fit(replace(_SETTINGS, x_scale=other)), key=lambda b: b.cost)
            x, success, message = best.x, best.success, best.message
            m = obj.model(x)
        if eiv and not held:
            g = obj.evaluator.slopes(obj.params.from_internal(x), w)
        sigma, by_group, nll = profile_noise(
            y, m, np.where(np.isfinite(m), g, 0.0), t_max, groups, spin_sd if eiv else 0.0
        )
        if abs(nll_prev - nll) < 1e-3:
            break
        nll_prev = nll
    return _Optimum(x, m, g, sigma, by_group, success, message)


def _runs(
    candidate: Candidate,
    spin_rate: ArrayLike,
    measured: ArrayLike,
    band: ArrayLike | None,
    run: ArrayLike | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.str_], NDArray[np.int64]]:
    """Spins, measured t_cr, bands and run numbers, checked."""
    w = np.asarray(spin_rate, dtype=float).reshape(-1)
    y = np.asarray(measured, dtype=float).reshape(-1)
    if w.size != y.size:
        raise InputError("measured", f"has {y.size} entries, expected {w.size}")
    if w.size < candidate.n_params + 2:
        raise InputError(
            "runs", f"{w.size} runs for {candidate.n_params} parameters and sigma; need more"
        )
    bands = band_of(w) if band is None else np.asarray(band).astype(str)
    runs = np.arange(1, w.size + 1) if run is None else np.asarray(run, dtype=np.int64)
    return w, y, bands, runs


def _start_values(
    candidate: Candidate, start: Sequence[float] | Mapping[str, float] | None
) -> list[float]:
    if start is None:
        return list(candidate.start())
    if isinstance(start, Mapping):
        return [float(start.get(k, PARAMETERS[k].start)) for k in candidate.params]
    return [float(v) for v in start]


def fit_candidate(
    candidate: Candidate,
    spin_rate: ArrayLike,
    measured: ArrayLike,
    *,
    band: ArrayLike | None = None,
    run: ArrayLike | None = None,
    selection: str = "all",
    start: Sequence[float] | Mapping[str, float] | None = None,
    spin_sd: float = SPIN_SD,
    t_max: float = DEFAULT_T_MAX,
    options: SolverOptions | None = None,
    evaluator: ModelEvaluator | None = None,
    controls: FitControls | None = None,
    noise: str = "band",
    conditions: Sequence[Conditions] | None = None,
) -> CandidateFit:
    """Fit one candidate to runs by maximum likelihood (censored Gaussian with spin EIV).

    Parameters
    ----------
    candidate : Candidate
    spin_rate : array_like
        omega_p per run [rad/s].
    measured : array_like
        Measured t_cr per run [s].
    band : array_like of str, optional
        Band label per run (default: by the run's own spin).
    run : array_like of int, optional
        Run numbers (default 1..n).
    selection : str
        Label of the run selection.
    start : sequence or mapping, optional
        Starting values of ``candidate.params`` (default: their ``start``).
    spin_sd : float
        Spin error SD sigma_w [rad/s]; 0 switches the error-in-variables term off.
    t_max : float
        Horizon [s].
    options : SolverOptions, optional
    evaluator : ModelEvaluator, optional
        Reused (with its cache) if it belongs to this candidate and horizon.
    controls : FitControls, optional
        Iteration settings (default: a full fit with its covariance).
    noise : {"band", "pooled"}
        Run-to-run noise: one sigma per spin band of `band` (small bands merged,
        :func:`.likelihood.noise_groups`) or one for all runs
        (see :mod:`.likelihood`).
    conditions : sequence of tuple, optional
        Each run's own settings (:meth:`~obturator.calibration.data.SpinRigData.run_settings`;
        default: every run at Table 1).

    Returns
    -------
    CandidateFit
    """
    t_start = time.perf_counter()
    w, y, bands, runs = _runs(candidate, spin_rate, measured, band, run)
    check_range("spin_sd", spin_sd, 0.0, math.inf, hi_open=True, unit="rad/s")
    check_range("t_max", t_max, 0.0, math.inf, lo_open=True, hi_open=True, unit="s")
    if (
        evaluator is None
        or evaluator.candidate != candidate
        or evaluator.t_max != t_max
        or evaluator.options != options
    ):
        evaluator = ModelEvaluator(candidate, t_max, options)
    models = RunModels(evaluator, conditions)
    n_int0, n_fail0 = models.counts
    controls = controls or FitControls()
    groups = noise_groups(bands, noise)
    obj = _Objective(_parameters(candidate), models, w, y, t_max)
    x0 = obj.params.start(_start_values(candidate, start))
    # from the default start, far from the optimum, the first pass scales by the Jacobian
    first = _SETTINGS_FIRST if start is None and controls.slopes is None else _SETTINGS_STARTED
    opt = _effective_variance(obj, x0, spin_sd, controls, groups, first)
    m, g, sigma = opt.model, opt.slope, opt.sigma
    sd = effective_sd(sigma, np.where(np.isfinite(m), g, 0.0), spin_sd)
    sd = np.where(np.isfinite(m), sd, sigma)
    nll = float(np.sum(nll_terms(y, m, sd, t_max)))
    values = obj.params.values(opt.x)
    p = len(obj.params)
    cov = np.full((p, p), math.nan)
    stderr = {k: math.nan for k in candidate.params}
    ci95 = {k: (math.nan, math.nan) for k in candidate.params}
    if p and controls.covariance:
        box = obj.params.internal_bounds()
        jac = central_jacobian(
            obj.residuals(sd), opt.x, box, _SETTINGS.covariance_step, prefetch=obj.prefetch
        )
        # the sigmas are fitted too: n - (p + n_sigma) degrees of freedom
        dof = max(w.size - (p + len(opt.sigma_by_group)), 1)
        est = wald(obj.params, opt.x, covariance_internal(jac), dof)
        cov, stderr, ci95 = est.covariance, est.stderr, est.ci95
        flat = [par.name for j, par in enumerate(obj.params) if not np.any(jac[:, j] != 0.0)]
        if flat:  # no run's t_cr moves with it: not identified, never a success
            opt = opt._replace(
                success=False,
                message=f"not identified: no run's t_cr changes with {', '.join(flat)}",
            )
    if not np.any(np.isfinite(m)):
        opt = opt._replace(
            success=False,
            message=f"not identified: the model opens none of the {w.size} runs by "
            f"t_max = {t_max:g} s (every run censored)",
        )
    return CandidateFit(
        name=candidate.name,
        selection=selection,
        params=candidate.params,
        values=values,
        stderr=stderr,
        ci95=ci95,
        ci_method={k: "wald" for k in candidate.params},
        plausible=candidate.plausibility(values),
        sigma=float(np.sqrt(np.mean(sigma**2))),
        nll=nll,
        k=p + len(opt.sigma_by_group),
        spin_rate=w,
        measured=y,
        model=m,
        slope=g,
        sd=sd,
        band=bands,
        run=runs,
        t_max=float(t_max),
        covariance=cov,
        success=opt.success,
        message=opt.message,
        nfev=obj.nfev,
        n_integrations=models.counts[0] - n_int0,
        n_failed=models.counts[1] - n_fail0,
        elapsed_s=time.perf_counter() - t_start,
        noise=noise,
        sigma_by_group=dict(opt.sigma_by_group),
        noise_group=groups,
        conditions=None if conditions is None else tuple(conditions),
    )


def predict(
    candidate: Candidate,
    values: Mapping[str, float],
    spin_rate: ArrayLike,
    *,
    t_max: float = DEFAULT_T_MAX,
    options: SolverOptions | None = None,
    evaluator: ModelEvaluator | None = None,
    conditions: Sequence[Conditions] | None = None,
) -> NDArray[np.float64]:
    """Model t_cr [s] at the given spins [rad/s] for fitted `values` (NaN: censored),
    at each run's own settings if `conditions` are given (see :class:`RunModels`)."""
    ev = evaluator or ModelEvaluator(candidate, t_max, options)
    w = np.asarray(spin_rate, dtype=float).reshape(-1)
    return RunModels(ev, conditions).opening_times([values[k] for k in candidate.params], w)


def profile_interval(
    best: CandidateFit,
    candidate: Candidate,
    name: str,
    *,
    spin_sd: float = SPIN_SD,
    options: SolverOptions | None = None,
    max_probes: int = 3,
    sides: tuple[int, ...] = (-1, 1),
) -> tuple[float, float]:
    """Profile-likelihood 95 % interval of one parameter of a fit.

    The interval is {v : 2 (nll_prof(v) - nll_best) <= 3.84}, nll_prof(v) the
    minimum of -log L over the other parameters (and sigma) with `name` held
    at v and the slopes held at the best fit's. Each side is found by the
    secant method on the signed root r(v) = sqrt(2 delta nll) (about linear in
    v), starting from the Wald bound; a side that reaches the fit bound
    without crossing the threshold returns the bound.

    Parameters
    ----------
    best : CandidateFit
        The fit (all its runs are reused).
    candidate : Candidate
        Its candidate.
    name : str
        Parameter to profile.
    max_probes : int
        Refits per side.
    sides : tuple of int
        -1 (lower), 1 (upper) or both; a side not computed is NaN (lets a
        pool compute the two sides in parallel).

    Returns
    -------
    (float, float)
        Lower and upper limit (physical units).
    """
    if name not in candidate.params:
        raise InputError("name", f"{name!r} is not fitted by {candidate.name!r}")
    par = PARAMETERS[name]
    others = tuple(k for k in candidate.params if k != name)
    x_best = par.to_internal(best.values[name])
    wald_limits = [par.to_internal(v) for v in best.ci95[name]]

    def signed_root(xv: float) -> float:
        sub = replace(
            candidate,
            params=others,
            fixed={**candidate.fixed, name: par.from_internal(xv)},
        )
        f = fit_candidate(
            sub,
            best.spin_rate,
            best.measured,
            band=best.band,
            run=best.run,
            start={k: best.values[k] for k in others},
            spin_sd=spin_sd,
            t_max=best.t_max,
            options=options,
            controls=FitControls(
                best.slope, covariance=False, xtol=_XTOL_LATER, sigma=best.sigma_per_run
            ),
            noise=best.noise,
            conditions=best.conditions,
        )
        d = max(2.0 * (f.nll - best.nll), 0.0)
        return math.copysign(math.sqrt(d), xv - x_best)

    out = {-1: math.nan, 1: math.nan}
    for side, guess in ((-1, wald_limits[0]), (1, wald_limits[1])):
        if side in sides:
            x_lim = profile_limit(
                signed_root, x_best, side, par.internal_bounds(), guess, max_probes
            )
            out[side] = par.from_internal(x_lim)
    if par.log or par.scale > 0:  # monotone increasing transform
        return (out[-1], out[1])
    return (out[1], out[-1])  # pragma: no cover - no decreasing transforms
