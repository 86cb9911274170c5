"""Parameter sweeps and Monte Carlo studies of the opening time t_cr.

Numerics and orchestration only (no plotting). Every grid point or sample is
one independent call of :func:`obturator.solve.opening_time`, so a study is
embarrassingly parallel. One concern per module:

* :mod:`.grid`: parsing axes (``START:STOP:COUNT``, ``a,b,c``, with units);
* :mod:`.spec`: :class:`SweepSpec`, the study and its identity (hash);
* :mod:`.points`: one point's t_cr and :class:`~obturator.status.Status`;
* :mod:`.job`: a study's chunks as a job of :class:`obturator.runs.Runner` (which
  runs them here, on a pool or Dask, resumably) and their results;
* :mod:`.sweep`: running a study (:func:`run_sweep`, :func:`execute_sweep`);
* :mod:`.table`: a study's results as arrays (:class:`StudyTable`) and its NetCDF file;
* :mod:`.export`: the study's table, CSV, and the files written atomically;
* :mod:`.distributions`, :mod:`.stats`, :mod:`.montecarlo`: Monte Carlo.

Status values stored in the ``status`` variable are those of
:class:`obturator.status.Status` (:data:`~.points.POINT_STATUSES`): 1 opened,
0 not opened by t_max, -1 solver failure, 2 step limit, -2 invalid input,
4 opened but not converged (``check_convergence``).
"""

from ..params import SWEEP_PARAMS as PARAMETERS
from ..runs.pools import default_workers
from ..runs.store import sidecar_path
from ..status import Status
from .distributions import Distribution, parse_distribution, sample_inputs
from .export import write_csv, write_netcdf
from .grid import parse_axis
from .montecarlo import MAX_SAMPLES, monte_carlo, monte_carlo_summary, monte_carlo_table
from .points import POINT_STATUSES
from .spec import SweepSpec
from .stats import MonteCarloSummary, QuantileEstimate, summarize_monte_carlo
from .sweep import SweepRun, execute_sweep, run_sweep, sweep_summary
from .table import StudyTable

__all__ = [
    "PARAMETERS",
    "POINT_STATUSES",
    "Status",
    "SweepSpec",
    "SweepRun",
    "StudyTable",
    "Distribution",
    "QuantileEstimate",
    "MonteCarloSummary",
    "parse_axis",
    "parse_distribution",
    "run_sweep",
    "execute_sweep",
    "sweep_summary",
    "monte_carlo",
    "monte_carlo_table",
    "MAX_SAMPLES",
    "summarize_monte_carlo",
    "monte_carlo_summary",
    "sample_inputs",
    "write_netcdf",
    "write_csv",
    "sidecar_path",
    "default_workers",
]
