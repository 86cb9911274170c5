"""The relative cost of the validation study's phases, for its progress display.

The unit is one exact solve (one observation's t_cr at one parameter set). Each phase's
weight counts the solves its tasks make, from the code:

* a fit of ``k`` parameters to ``n`` observations: ``n`` solves per evaluation of the
  residuals, ``k + 1`` evaluations per trust-region iteration (the residuals and a
  forward-difference Jacobian, :mod:`.fit`), :data:`ITERATIONS_FROM_START` iterations
  from the start values or :data:`ITERATIONS_STARTED` from a nearby start (subset fits
  start from the all-run fit, profile probes from the best fit), then ``2 k``
  evaluations of the covariance's central Jacobian;
* a prediction: one solve per predicted observation;
* a curve with its convergence check: one solve per curve point, three per run
  (tolerances / 10, width / 10, the other family: :func:`obturator.solve.convergence_checks`);
* a profile side: ``max_probes`` refits with the profiled parameter held
  (:func:`.fit.profile_interval`), no covariance;
* the release-phase scatter: one solve per cluster centre and phase (:data:`.tasks.PHASES`).

The iteration counts are the basis of the weights: a first pass from the start values
converges in 9-26 evaluations of the residuals and the later passes start next to the
optimum; fits given a nearby start converge in a few iterations. The resulting ratio of
the second phase to the first against the measured wall times of the two phases, and
the whole-run estimate against the elapsed time: ``docs/benchmarks.md`` (history,
``validation/cost.py``).
"""

from __future__ import annotations

from collections.abc import Sequence

from .candidates import Candidate
from .tasks import PHASES

__all__ = ["ITERATIONS_FROM_START", "ITERATIONS_STARTED", "fit_solves", "phase_weights"]

#: Trust-region iterations of a fit from the candidate's start values (all passes).
ITERATIONS_FROM_START = 20
#: Trust-region iterations of a fit from a nearby start (subset fits, profile probes).
ITERATIONS_STARTED = 4
#: Refits per profile side (the default ``max_probes`` of :func:`.fit.profile_interval`).
PROFILE_PROBES = 3
#: Solves per run of the convergence check (tolerances, width, family).
CHECK_SOLVES = 3


def fit_solves(n: int, k: int, *, started: bool, covariance: bool = True) -> float:
    """Exact solves of one fit of `k` parameters to `n` observations (module notes)."""
    iterations = ITERATIONS_STARTED if started else ITERATIONS_FROM_START
    return float(n * (iterations * (k + 1) + (2 * k if covariance else 0)))


def profile_solves(n: int, k: int) -> float:
    """Exact solves of one profile side of a `k`-parameter fit to `n` observations."""
    return PROFILE_PROBES * fit_solves(n, k - 1, started=True, covariance=False)


def phase_weights(
    cands: Sequence[Candidate],
    n_obs: int,
    n_runs: int,
    subsets: Sequence[tuple[int, int]],
    curve_points: int,
    n_centres: int,
    profiled: Sequence[Candidate],
) -> list[tuple[str, float]]:
    """The study's two phases and their weights in exact solves.

    Parameters
    ----------
    cands : sequence of Candidate
        The candidates (each fitted to all observations, then to every subset).
    n_obs, n_runs : int
        Observations (runs' t_cr and times to intermediate angles) and runs.
    subsets : sequence of (int, int)
        Per subset fit, its fitted and its predicted observations.
    curve_points : int
        Points of each curve.
    n_centres : int
        Cluster centres of the release-phase scatter.
    profiled : sequence of Candidate
        The candidates whose parameters are profiled (both sides of each).
    """
    first = sum(fit_solves(n_obs, c.n_params, started=False) for c in cands)
    second = float(n_centres * PHASES)
    for c in cands:
        for n_fit, n_pred in subsets:
            second += fit_solves(n_fit, c.n_params, started=True) + n_pred
        second += curve_points + CHECK_SOLVES * n_runs
    for c in profiled:
        second += 2 * c.n_params * profile_solves(n_obs, c.n_params)
    return [("all-run fits", first), ("profiles, subset fits, curves", second)]
