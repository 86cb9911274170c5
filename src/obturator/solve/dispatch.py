"""Which integrator runs a case: the per-case choice behind the default method ``"auto"``.

``"auto"`` runs each case with the set-valued event-driven solver (``"set-valued"``:
the friction law with no regularisation width, :mod:`obturator.core.integrators.stick_slip`)
where that solver takes the case and its spin is below :data:`SET_VALUED_BELOW`, and with
the regularised law (``"regularised"``: DOP853, handed to Radau IIA when stiff) elsewhere.
Below the threshold the stick-slip phases are long: the regularised path is slow there and
its width leaves up to ~2e-4 in t_cr, while the set-valued solver is both faster and
within ~2e-7 of the width-free limit; above it the ball slides almost from release and the
regularised path is the faster at equal accuracy.

The choice is a function of the packed parameter vector and the spin alone
(:func:`dispatched_method`), so the one-trajectory path (:mod:`obturator.solve.one`) and
the lanes (:func:`obturator.solve.opening_times`) choose the same integrator for every
case and give the same t_cr to the bit. Every other method name runs that integrator
for every case.
"""

from __future__ import annotations

from dataclasses import asdict
from typing import Any

import numpy as np

from ..core.integrators.stick_slip_modes import check_set_valued_law
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
    "dispatched_method",
    "method_identity",
    "method_of",
    "set_valued_applies",
]

#: Spin rate [rad/s] below which ``"auto"`` runs a case the set-valued solver takes with
#: that solver, per friction law (the thesis law on the rig and in flight, the Coulomb
#: patch law); at and above it, and for every case it refuses, the regularised path.
#: Placeholder, measured below.
SET_VALUED_BELOW: dict[int, float] = {
    FRIC_THESIS_RIG: 150.0,
    FRIC_THESIS_FLIGHT: 150.0,
    FRIC_COULOMB: 150.0,
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


def dispatched_method(method: str, p: np.ndarray, spin_rate: float) -> str:
    """The integrator that runs a case packed as `p` with spin `spin_rate` [rad/s] under
    `method`: for ``"auto"`` ``"set-valued"`` or ``"regularised"`` (see the module), any
    other method itself."""
    if method != "auto":
        return method
    below = SET_VALUED_BELOW.get(int(p[P_FRIC]), 0.0)
    if abs(spin_rate) < below and set_valued_applies(p):
        return "set-valued"
    return "regularised"


def method_of(case: Case, options: SolverOptions) -> str:
    """:func:`dispatched_method` of `case` with `options` (the integrator that runs it)."""
    return dispatched_method(options.method, pack_parameters(case, options), case.spin_rate)


def core_method(method: str) -> str:
    """The name :func:`obturator.core.integrators.integrate` knows `method` by (its
    ``"auto"`` is the regularised switching; it has no case to choose on)."""
    if method == "auto":
        raise ValueError("dispatch 'auto' per case first (dispatched_method)")
    return "auto" if method == "regularised" else method


def method_identity(options: SolverOptions) -> dict[str, Any]:
    """`options` as a study digest names them: their fields, and for ``"auto"`` the
    thresholds of the choice, so a resume store written under another choice (or before
    ``"auto"`` chose per case) is not taken for this one."""
    fields: dict[str, Any] = asdict(options)
    if options.method == "auto":
        fields["set_valued_below_rad_s"] = {str(k): v for k, v in SET_VALUED_BELOW.items()}
    return fields
