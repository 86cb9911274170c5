"""Which integrator runs a case: the per-case choice behind the default method ``"auto"``.

``"auto"`` runs each case with the set-valued event-driven solver (``"set-valued"``:
the friction law with no regularisation width, :mod:`obturator.core.integrators.stick_slip`)
where that solver takes the case and its stick ratio (:func:`stick_ratio`) is below
:data:`SET_VALUED_BELOW`, and with the regularised law (``"regularised"``: DOP853, handed
to Radau IIA when stiff) elsewhere: for every case the set-valued solver refuses
(slip-speed laws, the thesis's energy spin mode, Euler angles, Coulomb point contacts,
no friction) and above the threshold. Below it the ball sticks and slips for many
revolutions: the regularised law's width leaves 1e-6..1e-2 in t_cr there and the
set-valued solver is within ~2e-7 of the width-free limit (``docs/stick_slip.md``),
at lower or similar cost; above it the ball slides from release on, both paths agree
to ~5e-9 and the regularised one is the faster.

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
#: Measured 2026-11-27 on an idle 2-vCPU AMD EPYC (Zen 4), rig mu_s 0.5473 unless said,
#: ``python -m benchmarks.dispatch_crossover`` (errors against ``"set-valued"`` at rtol
#: 1e-12, the width-free limit of ``docs/stick_slip.md``; default rtol 1e-8; ms per point,
#: set-valued one by one / regularised one by one / regularised in lanes, a band of 32
#: points over +-5 rad/s in ``opening_times``):
#:
#: ====== ======= ====================== =============== ===============
#: spin   kappa   ms sv / 1x1 / lanes    error sv        error reg.
#: ====== ======= ====================== =============== ===============
#: 40     0.020   6.5 / 310 / 150        5e-8            1.3e-3
#: 60     0.045   6.4 / 44 / 20.5        4e-8            2.9e-4
#: 70     0.062   10.0 / 22.5 / 10.2     1.6e-7          2.7e-4
#: 100    0.126   4.0 / 7.1 / 3.2        6e-8            1.3e-4
#: 140    0.247   1.16 / 1.51 / 0.61     2e-7            3.6e-5
#: 150    0.284   0.97 / 1.19 / 0.49     1.3e-7          2.9e-5
#: 200    0.505   0.52 / 0.47 / 0.18     8e-9            2.7e-6
#: 250    0.79    0.36 / 0.24 / 0.079    4e-9            6e-9
#: ====== ======= ====================== =============== ===============
#:
#: So on speed alone the set-valued solver wins below ~190 rad/s (kappa 0.46) one by one
#: and below ~72 rad/s (kappa 0.066) against the lanes, which are 1-4.6x cheaper per point;
#: but up to kappa 0.536 (206 rad/s) the regularised t_cr is 1.8e-6..1.3e-3 off (the
#: ball sticks and slips, and the width converges slowly there), and from 0.546 on
#: within 1e-8: no stick after release. That edge is the same at mu_s 0.35, 0.5473 and
#: 0.8 (spins 165, 207, 251 rad/s: errors 1.8e-6 at kappa 0.536 and <= 8e-9 at 0.546
#: for all three), which is why the threshold is on kappa and not on the spin. Thesis
#: law: 0.6 (218 rad/s at Table 1), a 10 % margin; between 0.546 and 0.6 the
#: set-valued solver costs 1.1-1.3x (one by one) to 3-4x (lanes) for equal accuracy.
#: Flight (Mach 3-4, mu_s 0.35-0.5473, spin scaled): below kappa = cos(beta) = 0.8 the
#: ball never leaves stick (set-valued 0.05 ms, closed form; regularised 20-67 ms to
#: t_max, both NaN); regularised errors 4.1e-5, 1.6e-6, 6.9e-7, 3.6e-7, 2.4e-7 at kappa
#: 0.9, 1.0, 1.1, 1.2, 1.3 (the same at both Mach numbers), set-valued <= 5e-8 at
#: 0.37 ms against 0.15: 1.2 (Table 1 flight: kappa 1.5-28, regularised). Coulomb patch
#: law (rig): the set-valued solver costs 1.07-1.15x the regularised path one by one and
#: 1.1-1.4x its lanes at 80-250 rad/s (the generic right-hand side, no vectorised gain),
#: its errors 1e-8..8e-7 to 180 rad/s against the regularised 3.3e-4 (45 rad/s), 2.9e-6
#: (65), 1.3e-2 (70: one slip window more), 7.6e-7 (80), 3.7e-6 (100), 2.1e-6 (140),
#: 6.0e-7 (150) (45-70 rad/s: 2026-11-26): 0.28 (149 rad/s); above it both are ~1e-6
#: off (set-valued 5.9e-6 at 200 rad/s).
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

    Why: at rtol 1e-8 one rig point of 2,000 over 40-1000 rad/s (77.46 rad/s, mu_s
    0.5473) was 1.1e-5 from the width-free limit, and every other within 2.1e-7; at
    rtol 3e-9 the worst of the 2,000 is 1.4e-7, for 1.5-1.7x the time
    (``python -m benchmarks.dense_accuracy --limit``, docs/stick_slip.md section 11).
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
