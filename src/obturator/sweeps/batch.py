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
3. a lane that DOP853 finds stiff continues with Radau IIA from its last
   accepted state, as :func:`obturator.core.integrators.integrate` does for one
   trajectory: in Radau IIA lanes
   (:func:`obturator.core.integrators.radau_lanes.integrate_radau_lanes`) when
   the batch has at least :data:`RADAU_LANES_MIN` such points and the thesis
   kernel, else one by one.

Per lane the arithmetic is that of the one-trajectory DOP853, so t_cr agrees
with the scalar path to the last bit on the cases checked
(``tests/test_lanes.py``); points continued in Radau IIA lanes agree with the
scalar Radau IIA to rounding amplified by the near-stick dynamics (~1e-8
relative measured; ``OBTURATOR_RADAU_LANES=0`` continues them one by one).
Options the lanes do not cover (methods other than
``auto``, the convergence check) fall back to the per-point path.
"""

from __future__ import annotations

import math
import os
from collections.abc import Mapping, Sequence

import numpy as np

from ..core.integrators import RawSolution, _hand_over, auto_radau_tolerances
from ..core.integrators.lanes import DEFAULT_LANES, LANES, integrate_lanes
from ..core.integrators.radau_lanes import integrate_radau_lanes
from ..core.layout import KERNEL_THESIS, N_STATE, P_KERNEL
from ..errors import InputError
from ..solve import SolverOptions, integration_setup
from ..status import Status
from .points import point_status

__all__ = ["BATCH_METHODS", "RADAU_LANES_MIN", "batchable", "opening_times"]

#: Methods the lanes integrate (``auto``: DOP853, stiff lanes handed to Radau IIA).
BATCH_METHODS = ("auto",)
#: Fewest stiff points of a batch that continue in Radau IIA lanes; fewer go one by one
#: through the scalar Radau IIA. The lanes advance in lock step, so with few points the
#: tail (lanes idle while the last points finish) outweighs the vector speed: measured
#: on 10,000 rig points in strided chunks, ~11 stiff points per chunk took 9.2 s in
#: lanes against 7.0 s one by one, ~23 broke even, ~46 took 5.1 s against 6.4 s.
RADAU_LANES_MIN = 32


def env_switch(name: str) -> bool:
    """An on/off environment variable: unset or ``1`` is on, ``0`` off.

    Raises
    ------
    InputError
        Any other value (a typo must not silently select a path).
    """
    value = os.environ.get(name, "1")
    if value not in ("0", "1"):
        raise InputError(name, f"{value!r}; allowed: 0 (off), 1 (on)")
    return value == "1"


def batchable(options: SolverOptions, check_convergence: bool = False) -> bool:
    """True when points with these options run in lanes.

    ``OBTURATOR_LANES=0`` in the environment turns the lanes off (every point
    through :func:`~obturator.sweeps.points.evaluate_point`, the scalar path):
    for benchmarks and for cross-checks; results are the same.
    """
    if not env_switch("OBTURATOR_LANES"):
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
    stiff = np.flatnonzero(st == Status.STIFF)
    lanes_ok = stiff[np.all(np.isfinite(y_end[stiff]), axis=1) & (t_end[stiff] > 0.0)]
    if (
        lanes_ok.size < RADAU_LANES_MIN
        or _kernel_of(problems) != KERNEL_THESIS
        or not env_switch("OBTURATOR_RADAU_LANES")
    ):
        lanes_ok = lanes_ok[:0]
    if lanes_ok.size:
        rst, rt, rnfev = _radau_lanes(
            [problems[g] for g in lanes_ok], [controls[g] for g in lanes_ok], y_end[lanes_ok],
            t_end[lanes_ok], n_steps[lanes_ok], np.argsort(spin[lanes_ok], kind="stable"),
            options, n_lanes,
        )  # fmt: skip
        st[lanes_ok] = rst
        t_ev[lanes_ok] = rt
        stats["nfev"] += int(rnfev.sum())
        stats["n_stiff"] += int(lanes_ok.size)
    done = set(lanes_ok.tolist())
    for g, k in enumerate(idx):
        s = Status(int(st[g]))
        t = float(t_ev[g])
        if s == Status.STIFF and g not in done:
            stats["n_stiff"] += 1
            dop = RawSolution(
                s, t, np.full(N_STATE, math.nan), np.empty(0), np.empty((0, N_STATE)),
                int(nfev[g]), 0, int(n_steps[g]), int(n_rej[g]), float(t_end[g]), y_end[g],
            )  # fmt: skip
            out = _hand_over(dop, problems[g], controls[g])
            stats["nfev"] += int(out.nfev) - int(nfev[g])
            s, t = Status(out.status), float(out.t_event)
        t_cr[k], status[k] = point_status(s, t)


def _radau_lanes(problems, controls, y, t, steps_done, order, options, n_lanes):
    """Continue points from (t, y) in Radau IIA lanes, at ``auto``'s Radau tolerances
    (:func:`~obturator.core.integrators.auto_radau_tolerances`); (status, t_event, nfev)
    per point."""
    rtol, atol = auto_radau_tolerances(options.rtol, options.atol)
    st, t_ev, nfev, _, _ = integrate_radau_lanes(
        y, t, np.array([pr.p for pr in problems]), np.array([pr.scale for pr in problems]),
        np.array([c.t_max for c in controls]), np.array([c.h0 for c in controls]),
        np.array([c.h_max for c in controls]),
        np.array([max(c.max_steps - int(k), 1) for c, k in zip(controls, steps_done, strict=True)]),
        order, rtol, atol, options.event_tol, n_lanes, LANES,
    )  # fmt: skip
    return st, t_ev, nfev


def _kernel_of(problems) -> float:
    """The right-hand-side kernel of a group of problems (all share one)."""
    return float(problems[0].p[P_KERNEL])


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
