"""Friction calibration against spin-rig opening times (thesis chapter IV and beyond).

* :mod:`.data`: the runs (:class:`SpinRigData`): Appendix B or a user's CSV;
* :mod:`.thesis_fit`: the thesis's least squares of t = T2 omega_p (Eqs. 95-96)
  and its printed sums;
* :mod:`.rig_model`: the exact rig model, t_cr as a function of its parameters;
* :mod:`.exact`: the exact-model fit (:func:`fit_exact`) through the fit engine
  :mod:`obturator.fitting` (named parameters :class:`~obturator.fitting.FitParameter`);
* :mod:`.result`: its result (:class:`ExactFit`);
* :mod:`.bootstrap`: bootstrap of mu_s on an interpolated t_cr table;
* :mod:`.report`: the fit as JSON and as a text report.
"""

from ..fitting import FitParameter
from ..params import FIT_PARAMS as PARAMETERS
from .bootstrap import BootstrapResult, OpeningTimeTable, TableSettings, bootstrap_mu_s
from .data import SpinRigData, load_spin_rig_csv, load_thesis_data, readout_to_spin_rate
from .exact import ExactFit, calibrate_csv, fit_exact, select_runs
from .report import format_fit
from .rig_model import model_opening_times
from .thesis_fit import (
    EQ95_COEFFICIENT,
    PRINTED_SUMS_OMITTED_RUNS,
    THESIS_FIT_MIN_SPIN,
    THESIS_THETA0,
    SubsetMatch,
    ThesisComparison,
    ThesisLeastSquares,
    compare_with_thesis,
    format_comparison,
    printed_subset,
    printed_thesis_sums,
    search_printed_sums_subsets,
    thesis_fit,
    thesis_least_squares,
)

__all__ = [
    "EQ95_COEFFICIENT",
    "PARAMETERS",
    "PRINTED_SUMS_OMITTED_RUNS",
    "THESIS_FIT_MIN_SPIN",
    "THESIS_THETA0",
    "BootstrapResult",
    "ExactFit",
    "FitParameter",
    "OpeningTimeTable",
    "SpinRigData",
    "SubsetMatch",
    "TableSettings",
    "ThesisComparison",
    "ThesisLeastSquares",
    "bootstrap_mu_s",
    "calibrate_csv",
    "compare_with_thesis",
    "fit_exact",
    "format_comparison",
    "format_fit",
    "load_spin_rig_csv",
    "load_thesis_data",
    "model_opening_times",
    "printed_subset",
    "printed_thesis_sums",
    "readout_to_spin_rate",
    "search_printed_sums_subsets",
    "select_runs",
    "thesis_fit",
    "thesis_least_squares",
]
