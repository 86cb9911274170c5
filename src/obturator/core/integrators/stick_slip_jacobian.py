"""Jacobian of the zero-width law for the Radau IIA steps of a slip phase.

Near a breakaway or a stick the slip omega_r = R w - omega_p Z is a small difference
of rates of size omega_p (1e-8 omega_p after a kick), and the law varies on the scale
of |omega_r| itself. Forward differences must therefore move omega_r by a small
fraction of |omega_r|, yet stay far above the rounding of the rates and the attitude:
increments of :data:`SLIP_INCREMENT` |omega_r| on the body rates and
:data:`SLIP_INCREMENT` |omega_r| / omega_p on the quaternion (which moves omega_r by
about omega_p per unit), capped at sqrt(eps) of the component as in
:func:`.common.jacobian`. The law at zero width is differenced directly: no
regularised copy is needed, since the increments never cross omega_r = 0.

The regularised-copy Jacobian used before (width 1e-3 |omega_r|, increments capped at
1e-4 widths by :func:`.common.jacobian`) moved the attitude by ~1e-15 after a kick,
near the rounding of a unit quaternion: its entries erred by more than the
non-stiff ones they stand for (``docs/stick_slip.md`` section 8).
"""

from __future__ import annotations

import math

from numba import njit

from ..dynamics import rhs
from ..jit_flags import NO_REFCOUNT
from ..layout import N_STATE
from .stick_slip_modes import slip

__all__ = ["SLIP_INCREMENT", "slip_jacobian"]

#: Forward-difference increment on omega_r, in units of |omega_r|.
SLIP_INCREMENT = 1e-3
_SQRT_EPS = math.sqrt(2.220446049250313e-16)


@njit(cache=True, fastmath=False, **NO_REFCOUNT, error_model="python")
def slip_jacobian(t, y, f0, p, scale, jac, work, fwork, floor) -> None:
    """Forward-difference Jacobian `jac` of the right-hand side at (t, y), f0 = f(t, y).

    `floor` [rad/s] bounds |omega_r| from below in the increments (the slip after a
    kick is never smaller); `work`, `fwork` are (N_STATE,) scratch.
    """
    r = max(slip(y)[3], floor)
    spin = abs(y[7]) if y[7] != 0.0 else 1.0
    for j in range(N_STATE):
        for i in range(N_STATE):
            work[i] = y[i]
        dj = _SQRT_EPS * max(abs(y[j]), scale[j])
        if j < 4:  # quaternion: omega_r moves by ~ omega_p per unit
            dj = min(dj, SLIP_INCREMENT * r / spin)
        elif j < 7:
            dj = min(dj, SLIP_INCREMENT * r)
        work[j] = y[j] + dj
        dj = work[j] - y[j]
        rhs(t, work, p, fwork)
        for i in range(N_STATE):
            jac[i, j] = (fwork[i] - f0[i]) / dj
