"""obturator: opening dynamics of the ball obturator of a spin-stabilised tubular projectile.

A reproduction and extension of J. W. Bloomer II, *Ball Obturation of a Spin
Stabilized Tubular Projectile*, M.S. thesis, Naval Postgraduate School, 1980.
The numeric core takes plain SI floats; units are converted at the edges
(:mod:`obturator.units`, :mod:`obturator.io`, the command line). The
package's layout, from configuration to report, is described in
``docs/architecture.md``; this namespace is its curated public API.

Quick use::

    >>> from obturator import rig_case, simulate
    >>> res = simulate(rig_case(spin_rate=300.0, mu_s=0.5473))
    >>> round(res.opening_time, 3)
    0.276
"""

import importlib
from importlib.metadata import PackageNotFoundError, version

# Public names and the module that defines each: imported on first use (PEP 562),
# so ``import obturator`` and the command line start without loading numba,
# scipy, xarray or pint until a computation needs them.
_LAZY = {
    # errors and outcomes
    "InputError": "errors",
    "SolverError": "errors",
    "ClusterError": "errors",
    "Status": "status",
    # the model: ball, torques, cases
    "BoredBall": "model.geometry",
    "Case": "model.case",
    "initial_state": "model.case",
    "TorqueModel": "model.torques",
    "CouetteViscous": "model.torques",
    "NakabayashiViscous": "model.torques",
    "ThesisRigFriction": "model.torques",
    "ThesisFlightFriction": "model.torques",
    "CoulombContactFriction": "model.torques",
    "SlipSpeedLaw": "model.torques",
    "TABLE1": "reference",
    "table1_ball": "model.cases",
    "rig_case": "model.cases",
    "flight_case": "model.cases",
    "couette_case": "model.cases",
    "case_from_settings": "model.cases",
    # solving
    "SolverOptions": "solve",
    "simulate": "solve",
    "opening_time": "solve",
    "opening_times": "solve",
    "convergence_check": "solve",
    "ConvergenceCheck": "solve",
    "NutationResult": "result",
    "rig_approximation": "approx",
    "ApproximateSolution": "approx",
    # flow
    "normal_shock": "flow",
    "standard_atmosphere": "flow",
    # calibration
    "SpinRigData": "calibration",
    "load_thesis_data": "calibration",
    "load_spin_rig_csv": "calibration",
    "fit_exact": "calibration",
    "ExactFit": "calibration",
    "FitParameter": "fitting",
    # studies and the thesis report (their many tasks run on a Runner)
    "Runner": "runs",
    "SweepSpec": "sweeps",
    "run_sweep": "sweeps",
    "monte_carlo": "sweeps",
    "Distribution": "sweeps",
    "reproduce": "thesis",
    "design_experiment": "design",
    # input at the edge
    "parse_quantity": "units",
    "load_config": "io",
}


def __getattr__(name: str) -> object:
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'obturator' has no attribute {name!r}")
    value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(__all__)


try:
    __version__ = version("obturator")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"

__all__ = sorted([*_LAZY, "__version__"])
