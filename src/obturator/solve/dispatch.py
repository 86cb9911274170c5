"""Which integrator runs a case: the per-case choice behind the default method ``"auto"``.

``"auto"`` runs each case with the set-valued event-driven solver (``"set-valued"``:
the friction law with no regularisation width, :mod:`obturator.core.integrators.stick_slip`)
where that solver takes the case and its stick ratio (:func:`stick_ratio`) is below
:data:`SET_VALUED_BELOW`, and with the regularised law (``"regularised"``: DOP853, handed
to Radau IIA when stiff) elsewhere: for every case the set-valued solver refuses
(slip-speed laws, the thesis's energy spin mode, Euler angles, Coulomb point contacts,
no friction) and above the threshold. Below it the ball sticks and slips for many
revolutions, where the regularised law's width error is largest and the set-valued
solver has none; above it the ball slides from release on, both paths agree and the
regularised one is the faster (``docs/benchmarks.md``, ``python -m
benchmarks.dispatch_crossover``).

The choice is a function of the packed parameter vector and the start state alone
(:func:`dispatched_method`), so the one-trajectory path (:mod:`obturator.solve.one`) and
the lanes (:func:`obturator.solve.opening_times`) choose the same integrator for every
case and give the same t_cr to the bit, but for the set-valued cases of
:func:`~obturator.solve.opening_times` that share return maps across spins (to the
maps' tolerance). Every other method name runs that integrator for every case.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core.integrators import Controls, auto_radau_tolerances
from ..core.integrators.stick_slip_modes import check_set_valued_law
from ..core.integrators.stick_slip_modes import stick_ratio as core_stick_ratio
from ..core.layout import (
    FORM_QUATERNION,
    FRIC_COULOMB,
    FRIC_THESIS_FLIGHT,
    FRIC_THESIS_RIG,
    P_FORM,
    P_FRIC,
    P_SPIN_MODE,
    SPIN_THESIS_ENERGY,
)
from ..errors import InputError
from ..model.case import Case
from .options import SolverOptions
from .setup import pack_parameters

__all__ = [
    "SET_VALUED_BELOW",
    "core_method",
    "dispatched_controls",
    "dispatched_method",
    "dispatch_identity",
    "method_of",
    "set_valued_applies",
    "stick_ratio",
]

#: Stick ratio kappa at the start (:func:`stick_ratio`) below which ``"auto"`` runs a case
#: the set-valued solver takes with that solver, per friction law; at and above it, the
#: regularised path. Set by accuracy, where the regularised law's width error at the
#: default width (1e-7 omega_p) falls below 1e-6; cost only decides above that.
#: The threshold is on kappa, not on the spin, because the edge where the regularised
#: t_cr stops being within 1e-6 of the width-free limit (no stick after release) falls at
#: the same kappa for every mu_s; each value keeps a margin below that edge. Measured by
#: ``python -m benchmarks.dispatch_crossover`` (tables in ``docs/benchmarks.md``).
SET_VALUED_BELOW: dict[int, float] = {
    FRIC_THESIS_RIG: 0.6,
    FRIC_THESIS_FLIGHT: 1.2,
    FRIC_COULOMB: 0.28,
}


def set_valued_applies(p: np.ndarray) -> bool:
    """Whether the set-valued solver takes the case packed as `p`: quaternion form, a
    constant or free spin, and a law with a set-valued form (the thesis law, the Coulomb
    patch law with a patch, constant mu_s: what
    :func:`obturator.core.integrators.stick_slip.integrate` accepts)."""
    if p[P_FORM] != FORM_QUATERNION or p[P_SPIN_MODE] == SPIN_THESIS_ENERGY:
        return False
    try:
        check_set_valued_law(p, "the set-valued solver")
    except InputError:
        return False
    return True


def stick_ratio(p: np.ndarray, y: np.ndarray) -> float:
    """kappa = |G_req| / M [-] at the quaternion state `y` of a case packed as `p`: the
    friction moment that would keep the ball turning rigidly with the socket,
    G_req = omega_p^2 (C - A) z_Z (Z x z) (Eqs. 5a-5c at omega_r = 0), over the law's
    moment scale M (thesis Eq. 61: mu_s W R_s on the rig; n mu N_k R_s for Coulomb
    contacts). At release on the rig kappa = omega_p^2 |C - A| cos(theta_0)
    sin(theta_0) / (mu_s W R_s): 0.077 at 78 rad/s, mu_s = 0.5473 (Table 1),
    growing as omega_p^2 / mu_s. t_cr, in spin periods, and the stick-slip it goes
    through depend on kappa, not on omega_p and mu_s apart (the dimensionless form of
    Eqs. 5a-5c; see :data:`SET_VALUED_BELOW`)."""
    return core_stick_ratio(y, p)


def dispatched_method(method: str, p: np.ndarray, y0: np.ndarray) -> str:
    """The integrator that runs a case packed as `p` from state `y0` under `method`: for
    ``"auto"`` ``"set-valued"`` or ``"regularised"`` (see the module), any other method
    itself."""
    if method != "auto":
        return method
    below = SET_VALUED_BELOW.get(int(p[P_FRIC]))
    if below is not None and set_valued_applies(p) and stick_ratio(p, y0) < below:
        return "set-valued"
    return "regularised"


def method_of(case: Case, options: SolverOptions) -> str:
    """:func:`dispatched_method` of `case` from its release state with `options` (the
    integrator that runs it)."""
    y0 = case.initial_state(options.formulation)
    return dispatched_method(options.method, pack_parameters(case, options, y0), y0)


def dispatched_controls(method: str, chosen: str, controls: Controls) -> Controls:
    """`controls` for the integrator `chosen` under `method`: a case ``"auto"`` gives to
    the set-valued solver runs at
    :data:`~obturator.core.integrators.AUTO_RADAU_TOL_FACTOR` (a third) of the
    tolerances, as the regularised path's Radau IIA stretches do near stick.

    Why: at the full tolerances single near-stick points missed the 1e-6 accuracy
    contract of the default (``python -m benchmarks.dense_accuracy --limit``,
    ``docs/benchmarks.md``).
    """
    if method != "auto" or chosen != "set-valued":
        return controls
    rtol, atol = auto_radau_tolerances(controls.rtol, controls.atol)
    return controls._replace(rtol=rtol, atol=atol)


def core_method(method: str) -> str:
    """The name :func:`obturator.core.integrators.integrate` knows `method` by (its
    ``"auto"`` is the regularised switching; it has no case to choose on)."""
    if method == "auto":
        raise ValueError("dispatch 'auto' per case first (dispatched_method)")
    return "auto" if method == "regularised" else method


def dispatch_identity(options: SolverOptions) -> dict[str, Any]:
    """What a study digest adds to the fields of `options`: for ``"auto"`` the thresholds
    of its choice (``{}`` for any other method), so that a resume store written under
    another choice, or before ``"auto"`` chose per case (when it was today's
    ``"regularised"``), is not taken for this one."""
    if options.method != "auto":
        return {}
    below = {str(k): v for k, v in sorted(SET_VALUED_BELOW.items())}
    return {"auto": {"set_valued_below_stick_ratio": below}}
