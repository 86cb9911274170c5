"""The exact rig model as a function of its parameters: t_cr at given spin rates.

:func:`model_opening_times` is what the calibrations fit (and the bootstrap
tabulates): the integrated equations of motion of the spin-rig case
(:func:`obturator.model.cases.rig_case`) for given mu_s, theta_0, viscous
constant S and, for the validation study, the release transient, the
slip-speed law of mu and the contact patch.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..model.cases import rig_case
from ..reference import TABLE1
from ..solve import SolverOptions, opening_times

__all__ = ["S_TABLE1", "model_opening_times"]

#: Viscous constant S of Eq. (42) with the Table 1 inputs [N m s].
S_TABLE1: float = rig_case().torque.viscous.coefficient


def model_opening_times(
    spin_rates: NDArray[np.float64],
    *,
    mu_s: float,
    theta0_deg: float = TABLE1["theta0_deg"],
    shear_constant: float = S_TABLE1,
    weight: float = TABLE1["rig_weight"],
    torque_model: str = "thesis",
    t_max: float = 5.0,
    options: SolverOptions | None = None,
    theta_dot0: float = 0.0,
    speed_law: str = "constant",
    speed_ratio: float = 1.0,
    slip_speed: float = 0.05,
    release_phase: float = 0.0,
    patch_radius: float | None = None,
) -> NDArray[np.float64]:
    """Exact rig t_cr [s] at each spin rate [rad/s] (NaN where the ball does not open).

    All spins in one call of :func:`obturator.solve.opening_times` (lanes where the
    options allow).

    The viscous constant is set through the gap-fluid viscosity, to which the
    Eq. (42) constant S is proportional. `theta_dot0` [rad/s] and
    `release_phase` [rad] set the release state, `speed_law` with `speed_ratio`
    and `slip_speed` [m/s] the slip-speed dependence of mu
    (:class:`obturator.model.torques.SlipSpeedLaw`), `patch_radius` [m] the Coulomb
    contact patch.
    """
    from ..model.torques import SlipSpeedLaw

    law = None if speed_law == "constant" else SlipSpeedLaw(speed_law, speed_ratio, slip_speed)
    extra: dict[str, Any] = {
        "speed_law": law,
        "release_rate": (theta_dot0, 0.0, 0.0),
        "release_phase": release_phase,
    }
    if torque_model == "coulomb":
        extra["patch_radius"] = patch_radius
    visc = TABLE1["viscosity"] * shear_constant / S_TABLE1
    cases = [
        rig_case(
            float(w),
            mu_s,
            theta0_deg=theta0_deg,
            weight=weight,
            torque_model=torque_model,
            viscosity=visc,
            t_max=t_max,
            **extra,
        )
        for w in np.asarray(spin_rates, dtype=float).reshape(-1)
    ]
    return opening_times(cases, options, strict=True)[0]
