"""The exact rig model as a function of its parameters: t_cr at given spin rates.

:func:`model_opening_times` is what the calibrations fit (and the bootstrap
tabulates): the integrated equations of motion of the spin-rig case
(:func:`obturator.model.cases.rig_case`) for given mu_s, theta_0, viscous
constant S and, for the validation study, the release transient, the
slip-speed law of mu and the contact patch.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._docs import fill_doc
from ..errors import InputError
from ..model.case import Case
from ..model.cases import CASE_INPUTS_DOC, rig_case
from ..model.geometry import BoredBall
from ..reference import TABLE1
from ..solve import SolverOptions, opening_times

__all__ = [
    "S_TABLE1",
    "apply_run_settings",
    "model_opening_times",
    "model_opening_times_grid",
    "rig_model_case",
    "run_case_keywords",
]

#: Viscous constant S of Eq. (42) with the Table 1 inputs [N m s].
S_TABLE1: float = rig_case().torque.viscous.coefficient


def model_opening_times(
    spin_rates: NDArray[np.float64],
    *,
    mu_s: float,
    options: SolverOptions | None = None,
    **model: Any,
) -> NDArray[np.float64]:
    """Exact rig t_cr [s] at each spin rate [rad/s] (NaN where the ball does not open).

    All spins in one call of :func:`obturator.solve.opening_times` (lanes where the
    options allow).

    Parameters
    ----------
    spin_rates : ndarray
        omega_p [rad/s].
    mu_s : float
        Sliding friction coefficient [-].
    options : SolverOptions, optional
    **model
        The rig model's other inputs: keyword arguments of :func:`rig_model_case`.
    """
    return model_opening_times_grid(spin_rates, [mu_s], options=options, **model)[0]


def model_opening_times_grid(
    spin_rates: NDArray[np.float64],
    mu_values: Sequence[float] | NDArray[np.float64],
    *,
    options: SolverOptions | None = None,
    **model: Any,
) -> NDArray[np.float64]:
    """Exact rig t_cr [s], shape (len(mu_values), len(spin_rates)): every (mu_s, spin)
    pair in one call of :func:`obturator.solve.opening_times`, so the lanes stay full
    (a bootstrap table has ~90 mu_s rows of ~30 runs).

    Parameters
    ----------
    spin_rates : ndarray
        omega_p [rad/s].
    mu_values : sequence of float
        mu_s [-] of each row.
    options : SolverOptions, optional
    **model
        The rig model's other inputs: keyword arguments of :func:`rig_model_case`.
    """
    w = np.asarray(spin_rates, dtype=float).reshape(-1)
    runs = model.pop("run_settings", None)
    if runs is None:
        runs = [()] * w.size
    if len(runs) != w.size:
        raise InputError("run_settings", f"has {len(runs)} entries, expected {w.size}")
    cases = [
        apply_run_settings(rig_model_case, float(x), dict(r), mu_s=float(m), **model)
        for m in mu_values
        for x, r in zip(w, runs, strict=True)
    ]
    return opening_times(cases, options, strict=True)[0].reshape(-1, w.size)


def run_case_keywords(
    settings: Mapping[str, float], theta0_offset_deg: float = 0.0
) -> dict[str, Any]:
    """Keywords of :func:`~obturator.model.cases.rig_case` for one run's own settings.

    Parameters
    ----------
    settings : mapping
        The run's settings (:meth:`~.data.SpinRigData.run_settings`): ``theta0_deg``,
        ``hole_radius`` [m], ``density`` [kg/m^3], ``ball_mass`` [kg]; others ignored.
    theta0_offset_deg : float
        Added to the run's theta_0 [deg] (a fitted alignment offset).

    Notes
    -----
    A hole radius, density or mass makes a new ball (Table 1 radius): its inertia
    from the density (from the mass and the bored volume when only the mass is
    given), its load W = m g from the mass when given, else the ball's own weight
    rho V g (Table 1's measured 0.07987 N is for the Table 1 ball only).
    """
    from ..model.cases import table1_ball
    from ..model.geometry import STANDARD_GRAVITY

    kw: dict[str, Any] = {}
    if "theta0_deg" in settings:
        kw["theta0_deg"] = float(settings["theta0_deg"]) + theta0_offset_deg
    if {"hole_radius", "density", "ball_mass"} & set(settings):
        hole = settings.get("hole_radius")
        density = settings.get("density")
        if density is None and "ball_mass" in settings:
            unit = table1_ball(hole_radius=hole, density=1.0)
            density = float(settings["ball_mass"]) / unit.mass
        kw["ball"] = table1_ball(density=density, hole_radius=hole)
        mass = settings.get("ball_mass")
        kw["weight"] = None if mass is None else float(mass) * STANDARD_GRAVITY
    return kw


def apply_run_settings(
    factory: Any, spin_rate: float, settings: Mapping[str, float], **kw: Any
) -> Case:
    """``factory(spin_rate, **kw)`` with one run's settings laid over `kw`.

    A run's own theta_0 replaces ``kw["theta0_deg"]`` shifted by that value's offset
    from Table 1's 87.25 deg (so a fitted theta_0 acts as an alignment offset on
    runs that state theirs). ``theta_cr_deg`` in `settings` moves the terminal event
    to that angle (a time to an intermediate angle measured by the laser readout).
    """
    offset = float(kw.get("theta0_deg", TABLE1["theta0_deg"])) - TABLE1["theta0_deg"]
    kw = {**kw, **run_case_keywords(settings, offset)}
    case = factory(spin_rate, **kw)
    if "theta_cr_deg" in settings:
        case = replace(case, theta_cr=math.radians(float(settings["theta_cr_deg"])))
    return case


@fill_doc(case_inputs=CASE_INPUTS_DOC)
def rig_model_case(
    spin_rate: float,
    *,
    mu_s: float,
    theta0_deg: float = TABLE1["theta0_deg"],
    shear_constant: float = S_TABLE1,
    weight: float = TABLE1["rig_weight"],
    torque_model: str = "thesis",
    t_max: float = 5.0,
    theta_dot0: float = 0.0,
    speed_law: str = "constant",
    speed_ratio: float = 1.0,
    slip_speed: float = 0.05,
    release_phase: float = 0.0,
    patch_radius: float | None = None,
    ball: BoredBall | None = None,
) -> Case:
    """The spin-rig case (:func:`obturator.model.cases.rig_case`) of the rig model's inputs.

    The viscous constant is set through the gap-fluid viscosity, to which the
    Eq. (42) constant S is proportional.

    Parameters
    ----------
    {case_inputs}
    shear_constant : float
        Viscous constant S of Eq. (42) [N m s].
    weight : float
        Normal load W [N].
    torque_model : str
        ``"thesis"`` (Eqs. 56-61) or ``"coulomb"`` (contact patch of `patch_radius` [m]).
    t_max : float
        Horizon [s].
    theta_dot0 : float
        Release nutation rate [rad/s].
    speed_law, speed_ratio, slip_speed : str, float, float
        Slip-speed dependence of mu (:class:`obturator.model.torques.SlipSpeedLaw`;
        `slip_speed` [m/s]).
    release_phase : float
        Release phase [rad].
    patch_radius : float, optional
        Coulomb contact patch radius [m].
    ball : BoredBall, optional
        The ball (default Table 1's; a run's own hole radius or density).
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
    return rig_case(
        spin_rate,
        mu_s,
        theta0_deg=theta0_deg,
        weight=weight,
        torque_model=torque_model,
        viscosity=visc,
        t_max=t_max,
        ball=ball,
        **extra,
    )
