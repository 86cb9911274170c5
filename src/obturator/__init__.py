"""obturator: opening dynamics of the ball obturator of a spin-stabilised tubular projectile.

A reproduction and extension of J. W. Bloomer II, *Ball Obturation of a Spin
Stabilized Tubular Projectile*, M.S. thesis, Naval Postgraduate School, 1980.
The numeric core takes plain SI floats; units are converted at the edges
(:mod:`obturator.io`, the command line).

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
    "TABLE1": "reference",
    "couette_case": "model.cases",
    "flight_case": "model.cases",
    "rig_case": "model.cases",
    "table1_ball": "model.cases",
    "InputError": "errors",
    "SolverError": "errors",
    "BoredBall": "model.geometry",
    "Case": "model.case",
    "NutationResult": "result",
    "SolverOptions": "solve",
    "initial_state": "model.case",
    "opening_time": "solve",
    "simulate": "solve",
    "convergence_check": "solve",
    "CouetteViscous": "model.torques",
    "CoulombContactFriction": "model.torques",
    "NakabayashiViscous": "model.torques",
    "SlipSpeedLaw": "model.torques",
    "ThesisFlightFriction": "model.torques",
    "ThesisRigFriction": "model.torques",
    "TorqueModel": "model.torques",
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

__all__ = [
    "SlipSpeedLaw",
    "SolverError",
    "convergence_check",
    "TABLE1",
    "BoredBall",
    "Case",
    "CouetteViscous",
    "CoulombContactFriction",
    "InputError",
    "NakabayashiViscous",
    "NutationResult",
    "SolverOptions",
    "ThesisFlightFriction",
    "ThesisRigFriction",
    "TorqueModel",
    "__version__",
    "couette_case",
    "flight_case",
    "initial_state",
    "opening_time",
    "rig_case",
    "simulate",
    "table1_ball",
]
