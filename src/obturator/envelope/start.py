"""t_start along one flight: the started tube beside first light (thesis ch. I, Eq. 2)."""

from __future__ import annotations

import math
from typing import Any

from ..json_values import finite_or_none
from ..model.start import start_condition
from ..solve import start_times
from .coupled import STATUS_FLAGS, constant_case, coupled_convergence, coupled_opening
from .model import FlightModel
from .trajectory import Trajectory

__all__ = ["trajectory_start"]


def trajectory_start(model: FlightModel, flight: Trajectory, spin0: float) -> dict[str, Any]:
    """t_start along one flight with both loads, JSON-ready.

    Coupled: :func:`~.coupled.coupled_opening` stopping in each segment at
    theta_start(M) of the segment's Mach (:meth:`~.coupled.ObturatorDesign.start_angle`),
    with its convergence check when the model asks for one. Constant muzzle
    load: :func:`obturator.solve.start_times` (restart at first light, with the
    spill load bracket).

    Parameters
    ----------
    model : FlightModel
        Design, launch, solver settings.
    flight : Trajectory
        The computed flight (:func:`~.coupled.cached_flight`).
    spin0 : float
        Muzzle spin [rad/s].

    Returns
    -------
    dict
        ``t_start_coupled_s``, ``status_start_coupled``, ``convergence_start_coupled``,
        ``theta_start_at_start_deg`` and ``mach_at_start`` (coupled),
        ``t_start_constant_s``, ``theta_start_muzzle_deg``,
        ``t_start_constant_high_load_s``, ``t_start_constant_low_load_s``,
        ``inlet_at_muzzle`` (``starts``, ``unstartable``, ``choked``), ``choke_mach``;
        the bracket at the muzzle Mach with the constant load:
        ``theta_start_early_deg``, ``t_start_constant_early_s`` (the flow turned through
        the hole), ``theta_start_late_deg``, ``t_start_constant_late_s`` (wall friction
        and the lowest discharge coefficient; None where it never starts),
        ``late_at_muzzle`` (``starts`` or why not), ``friction_fld_late`` and
        ``discharge_coefficient_late``.
    """

    design, launch = model.design, model.launch
    angle = design.start_angle(launch.altitude_m)
    kw = {"segment": model.segment, "t_max": model.t_max, "spin_rate": spin0, "stop_angle": angle}
    res = coupled_opening(design, flight, model.options, **kw)
    conv = None
    if model.check_convergence and res.opened:
        conv = coupled_convergence(design, flight, model.options, t_cr=res.t_cr, **kw)
    cond = start_condition(
        launch.mach,
        design.ball(),
        design.bore_radius,
        gamma=design.gamma,
        altitude_m=launch.altitude_m,
    )
    const = start_times(constant_case(design, launch, model.t_max), cond, model.options)
    theta_end = angle(res.mach_end) if math.isfinite(res.mach_end) else math.nan

    return {
        "t_start_coupled_s": finite_or_none(res.t_cr),
        "status_start_coupled": STATUS_FLAGS[res.status],
        "convergence_start_coupled": None if conv is None else conv.to_dict(),
        "theta_start_at_start_deg": finite_or_none(math.degrees(theta_end)),
        "mach_at_start": finite_or_none(res.mach_end),
        "t_start_constant_s": finite_or_none(const.t_start),
        "theta_start_muzzle_deg": finite_or_none(math.degrees(cond.theta_start)),
        "t_start_constant_high_load_s": finite_or_none(const.t_start_high_load),
        "t_start_constant_low_load_s": finite_or_none(const.t_start_low_load),
        "inlet_at_muzzle": cond.verdict,
        "choke_mach": cond.choke_mach,
        "theta_start_early_deg": finite_or_none(math.degrees(cond.theta_start_early)),
        "t_start_constant_early_s": finite_or_none(const.t_start_early),
        "theta_start_late_deg": finite_or_none(math.degrees(cond.theta_start_late)),
        "t_start_constant_late_s": finite_or_none(const.t_start_late),
        "late_at_muzzle": cond.late_verdict,
        "friction_fld_late": cond.friction_fld,
        "discharge_coefficient_late": cond.discharge_coefficients[0],
    }
