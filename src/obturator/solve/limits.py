"""The regularisation widths each regularised path carries, refused outside them.

The regularised friction law turns stick into slip within a slip speed of
``friction_width * omega_p``; the narrower the width, the stiffer the stick phases.
The methods that integrate those phases with Radau IIA (``"regularised"``: DOP853, then
Radau IIA where stiff; ``"radau"``) do not carry every width of the allowed range:
below :data:`MIN_FRICTION_WIDTH` their t_cr jumps away from the width-free limit, far
above the trend of the width's own error, in every friction family and at every
tolerance measured (``python -m benchmarks.regularised_limits``, against the
set-valued solver at rtol 1e-12). There the width-free limit itself is the answer:
``method="set-valued"``. The default ``"auto"`` runs such cases set-valued.
"""

from __future__ import annotations

from typing import Any

from ..errors import InputError

__all__ = ["MIN_FRICTION_WIDTH", "check_regularised_limits"]

#: Smallest ``friction_width`` [1/omega_p] each method carries (methods not named: any
#: width of the allowed range).
MIN_FRICTION_WIDTH: dict[str, float] = {"regularised": 1e-10, "radau": 1e-10}


def check_regularised_limits(options: Any) -> None:
    """Raise InputError naming ``friction_width`` where `options`'s method cannot carry it.

    Parameters
    ----------
    options : SolverOptions
        Its ``method`` and ``friction_width`` (relative to the spin omega_p).
    """
    lo = MIN_FRICTION_WIDTH.get(options.method)
    if lo is not None and options.friction_width < lo:
        raise InputError(
            "friction_width",
            f"{options.friction_width:g} is outside the range method {options.method!r} "
            f"carries: [{lo:g}, 1] (relative to omega_p; its Radau IIA stick phases lose "
            "t_cr below it; method 'set-valued' is the width-free limit)",
        )
