"""Which route computes each point's t_cr: decided once, from the point and the options.

A *route* names the strategy that computes one t_cr: the integrator chosen for the point
(:func:`~obturator.solve.dispatch.dispatched_method`: the set-valued solver at low stick
ratio under ``"auto"``, else the regularised law) and the speed strategies of
:class:`~obturator.solve.SolverOptions` that change its arithmetic
(``shared_maps`` and ``slip_lanes`` for the set-valued solver, ``radau_lanes`` for the
regularised law's stiff stretches). The route is a function of the point's packed
parameters, its start state and the options alone, never of the other points of a batch,
so a point takes the same route, and gives the same bits, alone
(:func:`~obturator.solve.opening_time`) and in any batch, chunk or worker of
:func:`~obturator.solve.opening_times`.

Execution details that cannot change a bit are not part of a route: whether a
regularised point's DOP853 stretches run in SIMD lanes or one by one (``lanes``; the
lanes run the scalar arithmetic per lane) is recorded in the work counters instead.

>>> ROUTES[:3]
('invalid', 'set-valued', 'set-valued, shared map')
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .dispatch import dispatched_method
from .options import SolverOptions

__all__ = ["ROUTES", "ROUTE_CODES", "SET_VALUED_CODES", "plan_routes", "route_counts", "route_of"]

#: Every route a point can take (the ``route`` variable of a study: its index here).
ROUTES: tuple[str, ...] = (
    "invalid",
    "set-valued",
    "set-valued, shared map",
    "set-valued, cycle by cycle",
    "regularised",
    "regularised, Radau IIA lanes",
    "radau",
    "rosenbrock",
    "moreau-jean",
    "set-valued, last slip in lanes",
    "set-valued, shared map, last slip in lanes",
)
#: Route name -> code (int8).
ROUTE_CODES: dict[str, int] = {name: k for k, name in enumerate(ROUTES)}


def route_of(method: str, options: SolverOptions, t_cr_only: bool = True) -> str:
    """The route of a point that :func:`dispatched_method` gives to `method`, under
    `options`; `t_cr_only`: only the opening time is wanted (a time history is always
    integrated cycle by cycle, with the scalar Radau IIA). The set-valued solver's
    ``"set-valued"`` route iterates its own one-spin return map where that applies
    (:mod:`obturator.core.integrators.stick_slip_map`)."""
    if method == "set-valued":
        if not t_cr_only:
            return "set-valued, cycle by cycle"
        route = "set-valued, shared map" if options.shared_maps else "set-valued"
        return f"{route}, last slip in lanes" if options.slip_lanes else route
    if method == "regularised":
        return "regularised, Radau IIA lanes" if options.radau_lanes and t_cr_only else method
    return method


def plan_routes(
    valid: np.ndarray,
    p: np.ndarray,
    y0: np.ndarray,
    options: SolverOptions,
    t_cr_only: bool = True,
) -> np.ndarray:
    """Route code (:data:`ROUTE_CODES`) of each packed point: rows `p` (parameters) and
    `y0` (start states), ``invalid`` where not `valid`; `t_cr_only` as in
    :func:`route_of`."""
    out = np.zeros(valid.size, dtype=np.int8)
    for k in np.flatnonzero(valid):
        method = dispatched_method(options.method, p[k], y0[k])
        out[k] = ROUTE_CODES[route_of(method, options, t_cr_only)]
    return out


#: The codes of the routes that run the set-valued solver.
SET_VALUED_CODES: tuple[int, ...] = tuple(
    code for name, code in ROUTE_CODES.items() if name.startswith("set-valued")
)


def route_counts(routes: Sequence[int] | np.ndarray) -> dict[str, int]:
    """Points per route name (routes with none left out)."""
    codes, counts = np.unique(np.asarray(routes, dtype=np.int8), return_counts=True)
    return {ROUTES[int(c)]: int(n) for c, n in zip(codes, counts, strict=True)}
