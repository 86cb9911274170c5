"""Validation of the spin-rig model against all 54 runs of thesis Appendix B (issue 9).

One concern per module:

* :mod:`.floor` - replicate clusters and the pure-error floor;
* :mod:`.candidates` - the registry of candidate mechanisms and the parameters they
  fit (bounds and physical ranges: the fit registry, :data:`obturator.params.FIT_SPECS`);
* :mod:`.likelihood` - the censored Gaussian likelihood, one sigma per spin
  band (or pooled), with the spin error-in-variables term;
* :mod:`.goodness` - goodness of fit per band and per replicate cluster against
  the replicate floor;
* :mod:`.evaluate` - cached exact-model t_cr per (parameter vector, spin);
* :mod:`.fit` - maximum-likelihood fit, Wald and profile-likelihood intervals, through
  the fit engine :mod:`obturator.fitting`;
* :mod:`.predictive` - leave-one-cluster-out and leave-one-band-out predictive scores;
* :mod:`.valley` - flat directions of a fit and the bounded multi-start along them;
* :mod:`.results` - result objects (numbers, JSON);
* :mod:`.textreport` - text and Markdown tables;
* :mod:`.plotting` - the validation figure;
* :mod:`.study` - the whole study (``obturator validate``).
"""

from . import candidates as _candidates
from .candidates import CANDIDATES, DEFAULT_MODELS, PARAMETERS, Candidate, get_candidates
from .fit import fit_candidate, profile_interval
from .floor import BANDS, ReplicateFloor, cluster_runs, replicate_floor
from .goodness import band_goodness, cluster_goodness, goodness_summary
from .likelihood import SPIN_SD, nll_terms
from .results import CandidateFit, ModelResult, ValidationResult
from .study import recommend, run_validation
from .textreport import format_report

__all__ = [
    "BANDS",
    "CANDIDATES",
    "DEFAULT_MODELS",
    "PARAMETERS",
    "SPIN_SD",
    "band_goodness",
    "cluster_goodness",
    "goodness_summary",
    "Candidate",
    "CandidateFit",
    "ModelResult",
    "ReplicateFloor",
    "ValidationResult",
    "cluster_runs",
    "fit_candidate",
    "format_report",
    "get_candidates",
    "nll_terms",
    "profile_interval",
    "recommend",
    "replicate_floor",
    "run_validation",
]


def __getattr__(name: str) -> object:
    if name == "Parameter":  # deprecated: obturator.fitting.FitParameter
        return _candidates.__getattr__(name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
