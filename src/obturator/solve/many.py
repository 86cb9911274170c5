"""Opening times of many cases: the one front door every study goes through.

:func:`opening_times` takes a sequence of cases (an
:class:`~obturator.errors.InputError` in place of a case marks an invalid point) and
returns t_cr, a :class:`~obturator.status.Status` per case and work counters, with the
route each case took (:mod:`obturator.solve.plan`). Every case's route is planned from
that case and the options alone, so a case gives the same t_cr, status and counters
alone (:func:`~obturator.solve.opening_time`, which is a batch of one) and in any batch:

1. every case is packed (:func:`pack_points`, :class:`PackedPoints`) and its route
   planned (:func:`~obturator.solve.plan.plan_routes`);
2. the set-valued ones run one by one through the event-driven solver
   (:mod:`obturator.solve.one_by_one`; with ``shared_maps`` each reads the return map of
   its spin's fixed band, :mod:`obturator.core.integrators.stick_slip_family`);
3. the regularised ones run by right-hand-side kernel (:func:`_run_group`): DOP853
   stretches (in SIMD lanes where the group is large enough to pay,
   :func:`lanes_pay_from`, else one by one: the lanes run the scalar arithmetic per lane,
   so the bits are the same), a stiff stretch continued in Radau IIA from the last
   accepted state (in Radau IIA lanes with ``radau_lanes``, alone or in any batch,
   else the scalar Radau IIA), and back to DOP853 once the ball slides again
   (status ``NONSTIFF``; :func:`obturator.core.integrators.continue_auto`), in rounds
   until every point has ended.

This module is the only one above :mod:`obturator.core` besides
:mod:`obturator.solve.one` and :mod:`obturator.solve.one_by_one` that drives the
integrators.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np

from ..core.integrators import (
    AUTO_HAND_BACKS,
    Controls,
    HandOff,
    Problem,
    RawSolution,
    auto_radau_tolerances,
    continue_auto,
    method_module,
)
from ..core.integrators.lanes import DEFAULT_LANES, LANES, integrate_lanes, integrate_radau_lanes
from ..core.layout import KERNEL_GENERIC, N_PARAM, N_STATE, P_KERNEL
from ..errors import InputError, SolverError
from ..status import MESSAGES, Status
from .one import opening_time, simulate
from .one_by_one import failed_status, run_one_by_one
from .options import SolverOptions
from .plan import ROUTE_CODES, SET_VALUED_CODES, plan_routes, route_counts, route_of
from .setup import integration_controls, integration_setup

__all__ = [
    "BATCH_METHODS",
    "PACKED_WIDTHS",
    "POINT_STATUSES",
    "THESIS_LANES_MIN",
    "GENERIC_LANES_MIN",
    "Advanced",
    "PackedPoints",
    "advance",
    "batchable",
    "integrate_packed",
    "lanes_pay_from",
    "opening_times",
    "pack_points",
    "point_status",
]

#: Methods :func:`integrate_packed` takes (``regularised``: DOP853 stretches, stiff ones
#: continued in Radau IIA; ``auto``: its regularised cases so, its set-valued ones one by
#: one; ``set-valued``: every case one by one).
BATCH_METHODS = ("auto", "regularised", "set-valued")
#: Fewest thesis-kernel points of a batch whose DOP853 stretches run in SIMD lanes;
#: fewer run them one by one. The lanes run the scalar arithmetic lane by lane, so this
#: is an execution choice (speed), not a route: the bits are the same either way.
THESIS_LANES_MIN = 5
#: The same for the generic right-hand side (every kernel but the thesis's), whose lanes
#: evaluate the right-hand side lane by lane and so pay only for large batches.
GENERIC_LANES_MIN = 128


def batchable(options: SolverOptions) -> bool:
    """True when :func:`opening_times` runs cases with these options through the packed
    path (:func:`integrate_packed`: methods ``auto``, ``regularised``, ``set-valued``);
    the other methods run each case through :func:`~obturator.solve.opening_time`."""
    return options.method in BATCH_METHODS


#: The statuses a case of :func:`opening_times` can have (a study's ``status``
#: variable's flag values).
POINT_STATUSES: tuple[Status, ...] = (
    Status.INVALID_INPUT,
    Status.FAILED,
    Status.T_MAX,
    Status.OPENED,
    Status.STEP_LIMIT,
    Status.UNCONVERGED,
)


def point_status(status: int, t: float) -> tuple[float, int]:
    """(t_cr, status) of a case from an integration's status and t_event [s].

    ``FAILED`` or ``STEP_LIMIT`` when the integration failed (t_cr NaN; a hand-over
    signal, :class:`~obturator.core.integrators.HandOff`, that reached a point's end is
    a failure too), ``T_MAX`` when it did not open, else ``OPENED``. Shared by the
    one-by-one path and the lanes.
    """
    if status not in (Status.OPENED, Status.T_MAX, Status.UNCONVERGED):
        return math.nan, Status.STEP_LIMIT if status == Status.STEP_LIMIT else Status.FAILED
    return (t, Status.OPENED) if math.isfinite(t) else (math.nan, Status.T_MAX)


def opening_times(
    cases: Sequence[object],
    options: SolverOptions | None = None,
    *,
    check_convergence: bool = False,
    strict: bool = False,
    n_lanes: int = DEFAULT_LANES,
) -> tuple[np.ndarray, np.ndarray, dict[str, int]]:
    """t_cr [s] and status of many cases: the front door of every study.

    Parameters
    ----------
    cases : sequence of Case or InputError
        The cases; an :class:`~obturator.errors.InputError` in place of a case
        marks a point that is not a valid case (status ``INVALID_INPUT``).
    options : SolverOptions, optional
        Solver options (default :class:`SolverOptions`). With method ``"auto"`` or
        ``"regularised"`` the cases run in lanes (:func:`batchable`; under ``"auto"``
        those it gives to the set-valued solver one by one, as under
        ``"set-valued"``, the cases of equal parameters but the spin sharing the return
        maps of :mod:`obturator.core.integrators.stick_slip_family`), else one by one.
    check_convergence : bool
        Also check every opened case's convergence (:func:`~obturator.solve.convergence_checks`:
        the three reruns of all of them through this front door, in lanes where the
        options allow); status ``UNCONVERGED`` where it fails.
    strict : bool
        Raise, as :func:`~obturator.solve.opening_time` does, where a case is invalid
        or its integration failed (for studies that cannot use a partial answer).
    n_lanes : int
        Lanes advanced together (1 to 16).

    Returns
    -------
    t_cr : ndarray
        Opening times [s] (NaN where not opened).
    status : ndarray of int8
        :class:`~obturator.status.Status` per case: ``OPENED``, ``T_MAX`` (did not
        open by ``case.t_max``), ``STEP_LIMIT``, ``FAILED``, ``INVALID_INPUT``,
        ``UNCONVERGED``.
    stats : dict
        ``n_points``, ``nfev`` (right-hand sides, all points; lanes only),
        ``n_stiff`` (points handed to Radau IIA), ``n_hand_backs`` (Radau IIA lanes
        that went back to DOP853), ``n_set_valued`` (points run set-valued),
        ``nfev_shared`` (right-hand sides of the return-map grids this call built),
        ``route`` (int8 per case: its :data:`~obturator.solve.plan.ROUTES` code) and
        ``routes`` (cases per route name).

    Raises
    ------
    InputError
        With `strict`, the first invalid case's error.
    SolverError
        With `strict`, where an integration failed or reached the step limit.
    """
    options = options or SolverOptions()
    if batchable(options):
        out = integrate_packed(pack_points(cases, options), options, n_lanes=n_lanes)
    else:
        n = len(cases)
        t_cr = np.full(n, math.nan)
        status = np.full(n, Status.INVALID_INPUT, dtype=np.int8)
        for k, case in enumerate(cases):
            if not isinstance(case, InputError):
                t_cr[k], status[k] = _one_by_one(case, options)
        routes = np.zeros(n, dtype=np.int8)
        for k, case in enumerate(cases):
            if not isinstance(case, InputError):
                routes[k] = ROUTE_CODES[route_of(options.method, options)]
        out = t_cr, status, _stats(n, routes=routes)
    if check_convergence:
        from .convergence import mark_unconverged

        mark_unconverged(cases, options, out[0], out[1])
    if strict:
        _raise_failed(cases, out[1])
    return out


class Advanced(NamedTuple):
    """Where each case of :func:`advance` ended."""

    t_cr: np.ndarray  #: (n,) opening time [s] from the case's t = 0 (NaN if not opened)
    status: np.ndarray  #: (n,) int8 :class:`~obturator.status.Status`, as :func:`opening_times`
    state: np.ndarray  #: (n, 8) state at t_max (the event state if opened; NaN if invalid)
    nfev: np.ndarray  #: (n,) right-hand-side evaluations of each case
    stats: dict[str, int]  #: as :func:`opening_times`


def advance(
    cases: Sequence[object],
    states: np.ndarray,
    options: SolverOptions | None = None,
    *,
    n_lanes: int = DEFAULT_LANES,
) -> Advanced:
    """Integrate many cases from given states to the opening event or each ``case.t_max``.

    One segment of a piecewise-constant load for many points at once (the
    trajectory-coupled opening of :mod:`obturator.envelope.coupled`): the same
    lanes and ``auto`` switching as :func:`opening_times`, each case starting at its
    t = 0 from row i of `states` with the initial step of a fresh run.

    Parameters
    ----------
    cases : sequence of Case or InputError
    states : ndarray, shape (n, 8)
        Initial states in ``options.formulation`` (:meth:`Case.initial_state` layout).
    options : SolverOptions, optional
    n_lanes : int
        Lanes advanced together (1 to 16).

    Returns
    -------
    Advanced
        t_cr [s] relative to the segment start, status, end states and stats.
    """
    options = options or SolverOptions()
    n = len(cases)
    states = np.asarray(states, dtype=float)
    if states.shape != (n, N_STATE):
        raise InputError("states", f"expected shape ({n}, {N_STATE}), got {states.shape}")
    end = np.full((n, N_STATE), math.nan)
    nfev = np.zeros(n, dtype=np.int64)
    if batchable(options):
        packed = pack_points(cases, options, states)
        t_cr, status, stats = integrate_packed(
            packed, options, n_lanes=n_lanes, end_states=end, point_nfev=nfev
        )
        return Advanced(t_cr, status, end, nfev, stats)

    t_cr = np.full(n, math.nan)
    status = np.full(n, Status.INVALID_INPUT, dtype=np.int8)
    for k, case in enumerate(cases):
        if isinstance(case, InputError):
            continue
        res = simulate(case, options, y0=states[k], t_eval=np.array([case.t_max]))
        t_cr[k], status[k] = point_status(res.status, res.opening_time)
        nfev[k] = res.nfev
        if res.state.shape[0]:
            end[k] = res.state[-1]
    routes = np.array(
        [0 if isinstance(c, InputError) else ROUTE_CODES[route_of(options.method, options, False)]
         for c in cases], dtype=np.int8,
    )  # fmt: skip
    return Advanced(t_cr, status, end, nfev, _stats(n, int(nfev.sum()), routes))


def _stats(n: int, nfev: int = 0, routes: np.ndarray | None = None) -> dict[str, Any]:
    """The work counters of :func:`opening_times` for `n` points before any lane work,
    with the points' `routes` (codes of :data:`~obturator.solve.plan.ROUTES`)."""
    routes = np.zeros(n, dtype=np.int8) if routes is None else routes
    return {
        "n_points": n, "nfev": nfev, "nfev_shared": 0, "n_stiff": 0, "n_hand_backs": 0,
        "n_set_valued": 0, "route": routes, "routes": route_counts(routes),
    }  # fmt: skip


def _raise_failed(cases: Sequence[object], status: np.ndarray) -> None:
    """Raise for the first case that is invalid or whose integration failed."""
    for case, s in zip(cases, status.tolist(), strict=True):
        if isinstance(case, InputError):
            raise case
        if s in (Status.FAILED, Status.STEP_LIMIT):
            name = getattr(case, "name", "") or "case"
            raise SolverError(f"{name}: {MESSAGES[Status(s)]}", status=Status(s))


def _one_by_one(case: Any, options: SolverOptions) -> tuple[float, int]:
    """(t_cr, status) of one case through the one-trajectory path (never raises for a
    failed integration)."""
    try:
        t = opening_time(case, options)
    except RuntimeError as exc:  # SolverError, or anything else the integrator raised
        return point_status(failed_status(exc), math.nan)
    return point_status(Status.OPENED, t)


class PackedPoints(NamedTuple):
    """Points ready for the lanes: what :func:`~obturator.solve.integration_setup` gives
    for each, as arrays with one row per point (rows of invalid points are zeros).

    Built in Python (case validation, parameter packing), so it can be built in another
    process than the one that integrates (:mod:`obturator.sweeps.ahead`); :meth:`take`
    selects points.
    """

    valid: np.ndarray  #: bool (n,): the point is a valid case
    y0: np.ndarray  #: (n, 8) initial states
    p: np.ndarray  #: (n, n_par) packed parameters
    scale: np.ndarray  #: (n, 8) error-weight scales
    t_max: np.ndarray  #: (n,) [s]
    h0: np.ndarray  #: (n,) initial steps [s]
    h_max: np.ndarray  #: (n,) largest steps [s]
    spin: np.ndarray  #: (n,) omega_p [rad/s]

    def take(self, rows: np.ndarray) -> PackedPoints:
        """The points at positions `rows`."""
        return PackedPoints(*(a[rows] for a in self))


#: Columns of one point's row when :class:`PackedPoints` travel as one 2-D array
#: (valid, y0, p, scale, t_max, h0, h_max, spin), e.g. through shared memory.
PACKED_WIDTHS: tuple[int, ...] = (1, N_STATE, N_PARAM, N_STATE, 1, 1, 1, 1)


def pack_points(
    cases: Sequence[object], options: SolverOptions, states: np.ndarray | None = None
) -> PackedPoints:
    """:class:`PackedPoints` of `cases` (an :class:`~obturator.errors.InputError` in
    place of a case marks an invalid point), from row i of `states` (n, 8) where given,
    else from each case's release state."""
    n = len(cases)
    valid = np.array([not isinstance(c, InputError) for c in cases], dtype=bool)
    setups = [
        integration_setup(c, options, None if states is None else states[i])
        for i, (c, ok) in enumerate(zip(cases, valid, strict=True))
        if ok
    ]
    out = PackedPoints(
        valid, np.zeros((n, N_STATE)), np.zeros((n, N_PARAM)), np.ones((n, N_STATE)),
        *(np.zeros(n) for _ in range(4)),
    )  # fmt: skip
    k = np.flatnonzero(valid)
    if k.size:
        out.y0[k] = [pr.y0 for pr, _ in setups]
        out.p[k] = [pr.p for pr, _ in setups]
        out.scale[k] = [pr.scale for pr, _ in setups]
        out.t_max[k] = [c.t_max for _, c in setups]
        out.h0[k] = [c.h0 for _, c in setups]
        out.h_max[k] = [c.h_max for _, c in setups]
        out.spin[k] = [cases[i].spin_rate for i in k]
    return out


def integrate_packed(
    packed: PackedPoints,
    options: SolverOptions,
    *,
    n_lanes: int = DEFAULT_LANES,
    end_states: np.ndarray | None = None,
    point_nfev: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
    """:func:`opening_times` of points already packed (:func:`pack_points`); where
    given, row i of `end_states` (n, 8) receives point i's last state and entry i of
    `point_nfev` its right-hand-side evaluations.

    Each point's route is planned once from its own inputs
    (:func:`~obturator.solve.plan.plan_routes`): the set-valued ones run one by one
    (:func:`~obturator.solve.one_by_one.run_one_by_one`), the regularised ones by kernel
    through :func:`_run_group`. Nothing a point computes depends on the other points."""
    if options.method not in BATCH_METHODS:
        raise InputError("method", f"{options.method!r}: packed points take {BATCH_METHODS}")
    n = packed.valid.size
    t_cr = np.full(n, math.nan)
    status = np.full(n, Status.INVALID_INPUT, dtype=np.int8)
    to_t_max = end_states is not None
    routes = plan_routes(packed.valid, packed.p, packed.y0, options, t_cr_only=not to_t_max)
    stats = _stats(n, routes=routes)
    valid = np.flatnonzero(packed.valid)
    set_valued = np.isin(routes[valid], SET_VALUED_CODES)
    exact, valid = valid[set_valued], valid[~set_valued]
    outs, nfev = run_one_by_one(packed, exact, options, to_t_max, n_lanes)
    stats["nfev_shared"] += nfev
    for k, out in zip(exact, outs, strict=True):
        t_cr[k], status[k] = point_status(int(out.status), float(out.t_event))
        stats["nfev"] += int(out.nfev)
        stats["n_set_valued"] += 1
        if end_states is not None:
            end_states[k] = out.y[-1] if out.y.shape[0] else out.y_end
        if point_nfev is not None:
            point_nfev[k] = out.nfev
    kernels = packed.p[valid, P_KERNEL]
    for kernel in np.unique(kernels):
        idx = valid[kernels == kernel]
        y_end, nfev = _run_group(idx, packed.take(idx), options, n_lanes, t_cr, status, stats)
        if end_states is not None:
            end_states[idx] = y_end
        if point_nfev is not None:
            point_nfev[idx] = nfev
    return t_cr, status, stats


def lanes_pay_from(kernel: float) -> int:
    """Fewest points of one right-hand-side `kernel` whose DOP853 stretches
    :func:`_run_group` runs in lanes; fewer run them one by one, to the same bits (the
    lanes run the scalar arithmetic per lane). The thesis kernel's lanes evaluate the
    right-hand side as vectors and pay from a handful of points; the generic kernel's
    evaluate it lane by lane and pay only in large batches (``python -m
    benchmarks.small_groups``; docs/benchmarks.md)."""
    return GENERIC_LANES_MIN if kernel == KERNEL_GENERIC else THESIS_LANES_MIN


def _run_group(idx, packed, options, n_lanes, t_cr, status, stats) -> tuple[np.ndarray, np.ndarray]:
    """Points of one kernel under the regularised law: DOP853 stretches, stiff points on
    in Radau IIA (in lanes with ``options.radau_lanes``, else the scalar Radau IIA of
    :func:`continue_auto`), the points where sliding resumed back to DOP853, and so on, as
    :func:`continue_auto` does for one point. Every decision is per point; the DOP853
    stretches run in lanes or one by one (:func:`lanes_pay_from`) to the same bits."""
    n = idx.size
    p, scale, spin = packed.p, packed.scale, packed.spin
    t_max, h0, h_max = packed.t_max, packed.h0, packed.h_max
    max_steps = np.full(n, int(options.max_steps), dtype=np.int64)
    y = packed.y0.copy()  # where each point's next stretch starts
    t = np.zeros(n)  # integration_setup starts every run at release, t = 0
    cnt = np.zeros((3, n), dtype=np.int64)  # nfev, accepted steps, rejected steps so far
    hand_backs = np.zeros(n, dtype=np.int64)
    end_status = np.zeros(n, dtype=np.int8)
    t_event = np.full(n, math.nan)
    went_stiff = np.zeros(n, dtype=bool)
    in_lanes = options.lanes and n >= lanes_pay_from(float(p[0, P_KERNEL]))
    dop853 = integrate_lanes if in_lanes else _dop853_one_by_one
    pending = np.arange(n)
    while pending.size:
        sel = pending
        st, t_ev = _advance(
            dop853, sel, y, t, cnt, p, scale, t_max, h0, h_max, max_steps,
            np.argsort(-spin[sel], kind="stable"), options.rtol, options.atol,
            options.event_tol, n_lanes, np.zeros(sel.size),
        )  # fmt: skip
        _settle(sel, st, t_ev, st != HandOff.STIFF, end_status, t_event)
        stiff = sel[st == HandOff.STIFF]
        went_stiff[stiff] = True
        radau = stiff[np.all(np.isfinite(y[stiff]), axis=1) & (t[stiff] > 0.0)]
        if not options.radau_lanes:
            radau = radau[:0]
        for g in np.setdiff1d(stiff, radau):
            problem = Problem(packed.y0[g], p[g], scale[g])
            controls = integration_controls(options, float(t_max[g]), float(h0[g]), float(h_max[g]))
            dop = RawSolution(
                HandOff.STIFF, math.nan, np.full(N_STATE, math.nan), np.empty(0),
                np.empty((0, N_STATE)), int(cnt[0, g]), 0, int(cnt[1, g]), int(cnt[2, g]),
                float(t[g]), y[g].copy(),
            )  # fmt: skip
            out = continue_auto(dop, problem, controls, int(hand_backs[g]))
            cnt[0, g] = out.nfev
            y[g] = out.y_end
            end_status[g], t_event[g] = out.status, out.t_event
        pending = radau
        if radau.size:
            rtol, atol = auto_radau_tolerances(options.rtol, options.atol)
            st, t_ev = _advance(
                integrate_radau_lanes, radau, y, t, cnt, p, scale, t_max, h0, h_max,
                max_steps, hand_backs[radau] < AUTO_HAND_BACKS,
                np.argsort(spin[radau], kind="stable"), rtol, atol, options.event_tol,
                n_lanes, LANES,
            )  # fmt: skip
            back = st == HandOff.NONSTIFF
            _settle(radau, st, t_ev, ~back, end_status, t_event)
            pending = radau[back]
            hand_backs[pending] += 1
    stats["nfev"] += int(cnt[0].sum())
    stats["n_stiff"] += int(went_stiff.sum())
    stats["n_hand_backs"] += int(hand_backs.sum())
    for g, k in enumerate(idx):
        t_cr[k], status[k] = point_status(Status(int(end_status[g])), float(t_event[g]))
    return y, cnt[0]


def _dop853_one_by_one(
    y0, t0, p, scale, t_max, h0, h_max, max_steps, order, rtol, atol, event_tol, n_lanes,
    slip_floor,
):  # fmt: skip
    """:func:`integrate_lanes`'s contract, point by point through the scalar DOP853 (the
    same arithmetic: the lanes run it per lane); `order` and `n_lanes` are the lanes'
    and unused, `slip_floor` is zero (the regularised law's points)."""
    run = method_module("dop853").integrate
    n = y0.shape[0]
    st = np.zeros(n, dtype=np.int8)
    t_ev, t_end = np.full(n, math.nan), np.zeros(n)
    y_end = np.empty_like(y0)
    counts = np.zeros((3, n), dtype=np.int64)
    for i in range(n):
        controls = Controls(
            float(t_max[i]), rtol, atol, float(h0[i]), float(h_max[i]), int(max_steps[i]),
            np.empty(0), False, True, event_tol,
        )  # fmt: skip
        out = run(Problem(y0[i], p[i], scale[i], float(t0[i])), controls)
        st[i], t_ev[i], t_end[i], y_end[i] = out.status, out.t_event, out.t_end, out.y_end
        counts[:, i] = out.nfev, out.n_steps, out.n_rejected
    return st, t_ev, t_end, y_end, counts[0], counts[1], counts[2]


def _advance(lanes, sel, y, t, cnt, p, scale, t_max, h0, h_max, max_steps, *rest):
    """One stretch of the points `sel` in `lanes` (:func:`integrate_lanes` or
    :func:`integrate_radau_lanes`) from (t, y), with the steps they have left; (t, y)
    and the counters move on to where each stopped. Returns (status, t_event)."""
    left = np.maximum(max_steps[sel] - cnt[1, sel], 1)
    st, t_ev, t_end, y_end, nfev, n_steps, n_rej = lanes(
        y[sel], t[sel], p[sel], scale[sel], t_max[sel], h0[sel], h_max[sel], left, *rest
    )
    y[sel] = y_end
    t[sel] = t_end
    cnt[:, sel] += np.stack((nfev, n_steps, n_rej))
    return st, t_ev


def _settle(sel, st, t_ev, final, end_status, t_event) -> None:
    """Record the outcome of the points of `sel` whose run ended (`final`)."""
    end_status[sel[final]] = st[final]
    t_event[sel[final]] = t_ev[final]
