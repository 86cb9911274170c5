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

from importlib.metadata import PackageNotFoundError, version

from .cases import TABLE1, couette_case, flight_case, rig_case, table1_ball
from .errors import InputError
from .geometry import BoredBall
from .solve import Case, NutationResult, SolverOptions, initial_state, opening_time, simulate
from .torques import (
    CouetteViscous,
    CoulombContactFriction,
    NakabayashiViscous,
    ThesisFlightFriction,
    ThesisRigFriction,
    TorqueModel,
)

try:
    __version__ = version("obturator")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0+unknown"

__all__ = [
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
