"""The relative cost of the design study's phases, for its progress display.

The unit is one exact solve (one t_cr at one parameter set and setting), as for the
validation study (:mod:`obturator.validation.cost`). Each phase's weight counts its work
from the code:

* the posterior fits: one fit from the start values per candidate not given
  (:func:`obturator.validation.cost.fit_solves`);
* the surrogate solves: ``2 k + 1`` stencil points per candidate at every setting
  (:func:`.surrogate.stencil`); the release-angle slopes: one solve per candidate and
  setting;
* the plan search: the criterion evaluations of :func:`.criterion.greedy_exchange`
  (``n`` candidates per run placed or exchanged, at most :data:`.criterion.EXCHANGE_PASSES`
  passes), :data:`CRITERIA_PER_SOLVE` of them costing one solve;
* the simulated campaigns: one solve per draw and planned setting of each generating
  model;
* the decision rates: one log-evidence per plan, generating model, candidate and
  campaign (:func:`.campaigns.decision_rates`), :data:`EVIDENCES_PER_SOLVE` of them
  costing one solve.

The two conversion factors are bounds from the phase times of a measured run (the plan
search and the decision rates are short beside the exact solves), and the whole-run
estimate at the end of the first phase is checked against that run's elapsed time:
``docs/benchmarks.md`` (history, ``design/cost.py``).
"""

from __future__ import annotations

from collections.abc import Sequence

from ..validation.candidates import get_candidates
from ..validation.cost import fit_solves
from .criterion import EXCHANGE_PASSES

__all__ = ["CRITERIA_PER_SOLVE", "EVIDENCES_PER_SOLVE", "phase_weights"]

#: Criterion evaluations (a plan's Box-Hill value) in the time of one exact solve.
CRITERIA_PER_SOLVE = 100.0
#: Campaign log-evidences (one campaign, one candidate) in the time of one exact solve.
EVIDENCES_PER_SOLVE = 20.0

SURROGATE = "surrogate solves"
CAMPAIGNS = "simulated campaigns"


def phase_weights(
    fitted: Sequence[str],
    models: Sequence[str],
    n_data: int,
    n_settings: int,
    n_candidates: int,
    sizes: Sequence[int],
    n_plans: int,
    n_columns: int,
    campaigns: int,
) -> list[tuple[str, float]]:
    """The study's phases and their weights in exact solves.

    Parameters
    ----------
    fitted : sequence of str
        Candidates fitted here (not given).
    models : sequence of str
        Every candidate of the study.
    n_data : int
        Measured runs.
    n_settings, n_candidates : int
        Settings of the surrogates, and those a plan may use.
    sizes : sequence of int
        Campaign sizes planned.
    n_plans : int
        Plans whose decision rates are simulated (designed and naive).
    n_columns : int
        Settings of those plans (the campaigns' exact solves), or an upper bound.
    campaigns : int
        Simulated campaigns per generating model and plan.
    """
    cands = {c.name: c for c in get_candidates(list(models))}
    stencil = sum(2 * cands[m].n_params + 1 for m in models)
    n_models = len(models)
    criteria = sum(n * (1 + EXCHANGE_PASSES) * n_candidates for n in sizes)
    evidences = n_plans * n_models * n_models * campaigns
    return [
        (
            "posterior fits",
            sum(fit_solves(n_data, cands[m].n_params, started=False) for m in fitted),
        ),
        (SURROGATE, float(stencil * n_settings)),
        ("release-angle slopes", float(n_models * n_settings)),
        ("plan search", criteria / CRITERIA_PER_SOLVE),
        (CAMPAIGNS, float(n_models * campaigns * n_columns)),
        ("decision rates", evidences / EVIDENCES_PER_SOLVE),
    ]
