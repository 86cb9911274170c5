"""What the thesis's studies share: solver settings as attributes, horizons, and the
linearised solution matching a rig case.
"""

from __future__ import annotations

import warnings
from typing import Any

from .._provenance import package_version
from ..approx import ApproximationWarning, rig_approximation
from ..model.case import Case
from ..solve import SolverOptions

__all__ = ["RIG_T_MAX", "STICK_T_END", "rig_approx", "solver_attrs"]

#: End time of histories that have not opened within their horizon [s].
STICK_T_END = 1.0
#: Horizon of rig opening-time searches [s]: the slowest thesis rig case
#: (40 rad/s, mu_s = 0.5473) opens at 42.7 s.
RIG_T_MAX = 300.0


def solver_attrs(options: SolverOptions | None = None) -> dict[str, Any]:
    """Solver settings as flat Dataset attributes (netCDF-safe scalars).

    Parameters
    ----------
    options : SolverOptions, optional
        Default :class:`~obturator.solve.SolverOptions`.
    """
    o = options or SolverOptions()
    return {
        "solver_method": o.method,
        "solver_rtol": o.rtol,
        "solver_atol": o.atol,
        "solver_friction_width": o.friction_width,
        "solver_formulation": o.formulation,
        "obturator_version": package_version(),
    }


def rig_approx(case: Case, mu_s: float):
    """Linearised solution matching a rig case (same ball, W, S, theta_0, theta_cr)."""
    fr = case.torque.friction
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ApproximationWarning)
        return rig_approximation(
            case.ball,
            mu_s=mu_s,
            spin_rate=case.spin_rate,
            theta0=case.theta0,
            viscous_coefficient=case.torque.viscous.coefficient,
            weight=fr.weight,
            theta_cr=case.opening_angle,
            check=False,
        )
