"""Opening times of many points at once: batched DOP853 lanes, stiff lanes handed to Radau.

:func:`opening_times` is what a sweep or Monte Carlo chunk computes. It gives the
same t_cr and status per point as :func:`obturator.sweeps.points.evaluate_point`
(one :func:`obturator.solve.opening_time` call per point), but integrates the
points together in the lanes of :func:`obturator.core.integrators.lanes.integrate_lanes`:

1. every point's case is built and packed (a point that is not a valid case
   gets ``INVALID_INPUT``), and points are grouped by right-hand-side kernel;
2. each group runs in lanes, highest spin rate first (spin sets the steps per
   second of simulated time, so the costliest enter first and the tail of the
   batch is short);
3. a lane that DOP853 finds stiff continues with Radau IIA
   from its last accepted state, exactly as
   :func:`obturator.core.integrators.integrate` does for one trajectory.

Per lane the arithmetic is that of the one-trajectory DOP853, so t_cr agrees
with the scalar path to the last bit on the cases checked
(``tests/test_lanes.py``). Options the lanes do not cover (methods other than
``auto``, the convergence check) fall back to the per-point path.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence

import numpy as np

from ..core.integrators import RawSolution, _hand_over
from ..core.integrators.lanes import DEFAULT_LANES, integrate_lanes
from ..core.layout import N_STATE, P_KERNEL
from ..errors import InputError
from ..solve import SolverOptions, integration_setup
from ..status import Status
from .points import point_status

__all__ = ["BATCH_METHODS", "batchable", "opening_times"]

#: Methods the lanes integrate (``auto``: DOP853, stiff lanes handed to Radau IIA).
BATCH_METHODS = ("auto",)


def batchable(options: SolverOptions, check_convergence: bool = False) -> bool:
    """True when points with these options run in lanes.

    ``OBTURATOR_LANES=0`` in the environment turns the lanes off (every point
    through :func:`~obturator.sweeps.points.evaluate_point`, the scalar path):
    for benchmarks and for cross-checks; results are the same.
    """
    if os.environ.get("OBTURATOR_LANES", "1") == "0":
        return False
    return options.method in BATCH_METHODS and not check_convergence


def opening_times(
    cases: Sequence[object], options: SolverOptions, *, n_lanes: int = DEFAULT_LANES
) -> tuple[np.ndarray, np.ndarray, dict[str, int]]:
    """t_cr [s] and status of many cases, integrated in lanes.

    Parameters
    ----------
    cases : sequence of Case or InputError
        The points; an :class:`~obturator.errors.InputError` in place of a case
        marks a point that is not a valid case (status ``INVALID_INPUT``).
    options : SolverOptions
        Solver options (method ``"auto"``).
    n_lanes : int
        Lanes advanced together (1 to 16).

    Returns
    -------
    t_cr : ndarray
        Opening times [s] (NaN where not opened).
    status : ndarray of int8
        :class:`~obturator.status.Status` per point, as
        :func:`~obturator.sweeps.points.evaluate_point` gives it.
    stats : dict
        ``n_points``, ``nfev`` (right-hand sides, all points), ``n_stiff``
        (lanes handed to Radau IIA).
    """
    if options.method not in BATCH_METHODS:
        raise InputError("method", f"{options.method!r}: the lanes integrate {BATCH_METHODS}")
    n = len(cases)
    t_cr = np.full(n, math.nan)
    status = np.full(n, Status.INVALID_INPUT, dtype=np.int8)
    stats = {"n_points": n, "nfev": 0, "n_stiff": 0}
    valid = [k for k, c in enumerate(cases) if not isinstance(c, InputError)]
    if not valid:
        return t_cr, status, stats
    packed = [(*integration_setup(cases[k], options), cases[k]) for k in valid]
    kernels = np.array([pk[0].p[P_KERNEL] for pk in packed])
    for kernel in np.unique(kernels):
        sel = [i for i in range(len(valid)) if kernels[i] == kernel]
        _run_group([valid[i] for i in sel], [packed[i] for i in sel], options, n_lanes,
                   t_cr, status, stats)  # fmt: skip
    return t_cr, status, stats


def _run_group(idx, packed, options, n_lanes, t_cr, status, stats) -> None:
    problems = [pk[0] for pk in packed]
    controls = [pk[1] for pk in packed]
    spin = np.array([c.spin_rate for c in (pk[2] for pk in packed)])
    st, t_ev, t_end, y_end, nfev, n_steps, n_rej = integrate_lanes(
        np.array([pr.y0 for pr in problems]), np.array([pr.p for pr in problems]),
        np.array([pr.scale for pr in problems]), np.array([c.t_max for c in controls]),
        np.array([c.h0 for c in controls]), np.array([c.h_max for c in controls]),
        np.argsort(-spin, kind="stable"), options.rtol, options.atol,
        int(options.max_steps), options.event_tol, n_lanes,
    )  # fmt: skip
    stats["nfev"] += int(nfev.sum())
    for g, k in enumerate(idx):
        s = Status(int(st[g]))
        t = float(t_ev[g])
        if s == Status.STIFF:
            stats["n_stiff"] += 1
            dop = RawSolution(
                s, t, np.full(N_STATE, math.nan), np.empty(0), np.empty((0, N_STATE)),
                int(nfev[g]), 0, int(n_steps[g]), int(n_rej[g]), float(t_end[g]), y_end[g],
            )  # fmt: skip
            out = _hand_over(dop, problems[g], controls[g])
            stats["nfev"] += int(out.nfev) - int(nfev[g])
            s, t = Status(out.status), float(out.t_event)
        t_cr[k], status[k] = point_status(s, t)


def run_rows(spec, names: tuple[str, ...], rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`opening_times` of the rows of one sweep chunk (values in `names` order)."""
    cases: list[object] = []
    for row in rows:
        values: Mapping[str, float] = dict(zip(names, row.tolist(), strict=True))
        try:
            cases.append(spec.build_case(values))
        except InputError as exc:
            cases.append(exc)
    t, s, _ = opening_times(cases, spec.options)
    return t, s
