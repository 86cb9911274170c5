"""Experiment design: which rig runs decide between the candidate mechanisms (issue 29).

One concern per module:

* :mod:`.settings` - what the rig can set (spin, release angle, hole radius, density),
  the candidate grid, the naive plan, and a setting as a case of each candidate;
* :mod:`.feasibility` - the holding moment a setting needs against the rig's bound, and
  where it leaves the validated runs;
* :mod:`.posterior` - each candidate's Laplace posterior from its validation fit (a new
  ball's own copy of the ball-specific parameters);
* :mod:`.surrogate` - t_cr over (setting, parameters) from exact front-door solves;
* :mod:`.criterion` - the Box-Hill criterion (symmetric KL of predictive Gaussians) and
  the greedy/exchange plan search;
* :mod:`.campaigns` - simulated campaigns and their Bayes-factor decisions;
* :mod:`.results`, :mod:`.textreport`, :mod:`.plotting` - numbers, text, figure;
* :mod:`.report` - the section of the reproduction report;
* :mod:`.study` - the whole study (:func:`design_experiment`, ``obturator design-experiment``).
"""

from .campaigns import DECISIVE_BAYES_FACTOR, Rates
from .criterion import box_hill, gaussian_kl, greedy_exchange, jeffreys
from .noise import ReplicateNoise
from .posterior import Posterior
from .results import DesignResult, PlanResult
from .settings import Setting, SettingRanges, design_case, naive_plan
from .study import DEFAULT_DESIGN_MODELS, DEFAULT_RUNS, design_experiment
from .surrogate import Surrogate
from .textreport import format_design

__all__ = [
    "DECISIVE_BAYES_FACTOR",
    "DEFAULT_DESIGN_MODELS",
    "DEFAULT_RUNS",
    "DesignResult",
    "PlanResult",
    "Posterior",
    "Rates",
    "ReplicateNoise",
    "Setting",
    "SettingRanges",
    "Surrogate",
    "box_hill",
    "design_case",
    "design_experiment",
    "format_design",
    "gaussian_kl",
    "greedy_exchange",
    "jeffreys",
    "naive_plan",
]
