"""Opening times of many cases: the one front door every study goes through.

:func:`opening_times` takes a sequence of cases (an
:class:`~obturator.errors.InputError` in place of a case marks an invalid point) and
returns t_cr, a :class:`~obturator.status.Status` per case and work counters. Where
the options allow (method ``auto`` or ``regularised``; with a convergence check, its
reruns too) the cases are integrated together in the SIMD lanes of
:func:`obturator.core.integrators.lanes.integrate_lanes`, else one by one through
:func:`obturator.solve.opening_time`; same status and t_cr (bit for bit, but see item 1):

1. every case is packed (:func:`pack_points`, :class:`PackedPoints`); under ``auto``
   the cases :func:`~obturator.solve.dispatch.dispatched_method` gives to the
   set-valued solver (low spin) run one by one through it, as
   :func:`~obturator.solve.opening_time` runs them, but cases differing in spin alone
   share their cycles' return maps (:mod:`obturator.core.integrators.stick_slip_family`:
   t_cr within 5.3e-7 of :func:`~obturator.solve.opening_time` on 1,855 points of a
   40-1000 rad/s sweep, closer to the width-free limit;
   :mod:`obturator.solve.one_by_one`), and the rest in lanes with the
   regularised law; those are grouped by right-hand-side kernel, and a group too
   small for lanes to pay (:func:`lanes_pay_from`: under five thesis-kernel points,
   under :data:`RADAU_LANES_MIN_GENERIC` of the generic kernel, whose lanes do not
   vectorise the right-hand side) runs one by one as well;
2. each group runs in lanes, highest spin rate first (spin sets the steps per
   second of simulated time, so the costliest enter first and the tail of the
   batch is short);
3. a lane that DOP853 finds stiff continues with Radau IIA from its last
   accepted state, as :func:`obturator.core.integrators.integrate` does for one
   trajectory: in Radau IIA lanes
   (:func:`obturator.core.integrators.lanes.integrate_radau_lanes`) when
   the batch has at least :data:`RADAU_LANES_MIN` such points
   (:data:`RADAU_LANES_MIN_GENERIC` for the generic right-hand side), else one by one;
4. a Radau IIA lane whose ball slides again (status ``NONSTIFF``, the end of the
   stick-slip phase; :func:`obturator.core.integrators.continue_auto`) goes back
   to the DOP853 lanes, in rounds until every point has ended.

Per lane the arithmetic is that of the one-trajectory DOP853, so t_cr agrees
with the scalar path to the last bit on the cases checked
(``tests/core/test_lanes.py``); points continued in Radau IIA lanes agree with the
scalar Radau IIA to rounding amplified by the near-stick dynamics (~1e-8
relative measured; ``OBTURATOR_RADAU_LANES=0`` continues them one by one,
``OBTURATOR_SHARED_MAPS=0`` has each set-valued case build its own return map).
This module is the only one above :mod:`obturator.core` besides
:mod:`obturator.solve.one` that drives the integrators.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, NamedTuple

import numpy as np

from ..core.integrators import (
    AUTO_HAND_BACKS,
    Problem,
    RawSolution,
    auto_radau_tolerances,
    continue_auto,
)
from ..core.integrators.lanes import DEFAULT_LANES, LANES, integrate_lanes, integrate_radau_lanes
from ..core.layout import KERNEL_GENERIC, N_PARAM, N_STATE, P_KERNEL
from ..errors import InputError, SolverError
from ..status import MESSAGES, Status
from .dispatch import dispatched_method
from .one import opening_time, simulate
from .one_by_one import env_switch, failed_status, run_one_by_one
from .options import SolverOptions
from .setup import integration_controls, integration_setup

__all__ = [
    "BATCH_METHODS",
    "PACKED_WIDTHS",
    "POINT_STATUSES",
    "RADAU_LANES_MIN",
    "RADAU_LANES_MIN_GENERIC",
    "THESIS_LANES_MIN",
    "GENERIC_LANES_MIN",
    "Advanced",
    "PackedPoints",
    "advance",
    "batchable",
    "env_switch",
    "integrate_packed",
    "lanes_pay_from",
    "opening_times",
    "pack_points",
    "point_status",
]

#: Methods :func:`integrate_packed` takes (``regularised``: DOP853 lanes, stiff lanes
#: handed to Radau IIA; ``auto``: its regularised cases so, its set-valued ones one by
#: one; ``set-valued``: every case one by one). The set-valued cases that differ in spin
#: alone share return maps (:mod:`obturator.core.integrators.stick_slip_family`).
BATCH_METHODS = ("auto", "regularised", "set-valued")
#: Fewest stiff points of a batch that continue in Radau IIA lanes; fewer go one by one
#: through the scalar Radau IIA. The lanes advance in lock step, so with few points the
#: tail (lanes idle while the last points finish) outweighs the vector speed: measured
#: on 10,000 rig points in strided chunks, ~11 stiff points per chunk took 9.2 s in
#: lanes against 7.0 s one by one, ~23 broke even, ~46 took 5.1 s against 6.4 s.
RADAU_LANES_MIN = 32
#: The same for the generic right-hand side (every kernel but the thesis's). Its lanes
#: evaluate the right-hand side lane by lane (as the scalar code does), so they save only
#: the vectorised LU: measured on a loaded 2-core Zen 4, Radau IIA alone from release on
#: 64 coulomb-patch rig points 1.21-1.26x faster than one by one, 1.05x on 8; in
#: opening_times with its hand-back rounds (64 points) and in validate's coulomb-patch
#: fits (32-56 stiff points a batch: 60-62 s against 57-59 s CPU) no gain. Only large
#: batches (sweeps) take them.
RADAU_LANES_MIN_GENERIC = 128
#: Fewest thesis-kernel points that run in DOP853 lanes (:func:`lanes_pay_from`).
THESIS_LANES_MIN = 5
#: Fewest generic-kernel points that run in lanes (:func:`lanes_pay_from`).
GENERIC_LANES_MIN = RADAU_LANES_MIN_GENERIC


def batchable(options: SolverOptions) -> bool:
    """True when cases with these options run in lanes (with or without convergence
    checks: :func:`opening_times` batches those too).

    ``OBTURATOR_LANES=0`` in the environment turns the lanes off (every case
    through :func:`~obturator.solve.opening_time`, the scalar path): for
    benchmarks and for cross-checks; results are the same.
    """
    if not env_switch("OBTURATOR_LANES"):
        return False
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


def point_status(status: Status, t: float) -> tuple[float, int]:
    """(t_cr, status) of a case from an integration's status and t_event [s].

    ``FAILED`` or ``STEP_LIMIT`` when the integration failed (t_cr NaN), ``T_MAX``
    when it did not open, else ``OPENED``. Shared by the one-by-one path and the lanes.
    """
    if not status.success:
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
        that went back to DOP853 lanes), ``n_set_valued`` (points ``auto`` gave to the
        set-valued solver; lanes only).

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
        out = t_cr, status, _stats(n)
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
    return Advanced(t_cr, status, end, nfev, _stats(n, int(nfev.sum())))


def _stats(n: int, nfev: int = 0) -> dict[str, int]:
    """The work counters of :func:`opening_times` for `n` points before any lane work."""
    return {"n_points": n, "nfev": nfev, "n_stiff": 0, "n_hand_backs": 0, "n_set_valued": 0}


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

    Built in Python (case validation, parameter packing: ~30 us per point), so it can
    be built in another process than the one that integrates
    (:mod:`obturator.sweeps.ahead`); :meth:`take` selects points.
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
) -> tuple[np.ndarray, np.ndarray, dict[str, int]]:
    """:func:`opening_times` of points already packed (:func:`pack_points`); where
    given, row i of `end_states` (n, 8) receives point i's last state and entry i of
    `point_nfev` its right-hand-side evaluations. Under ``auto`` the points
    :func:`~obturator.solve.dispatch.dispatched_method` gives to the set-valued solver
    run one by one through it (``stats["n_set_valued"]``), the rest in lanes, except
    kernels with fewer points than the lanes need to pay (:func:`lanes_pay_from`),
    which run one by one too, to the same t_cr."""
    if options.method not in BATCH_METHODS:
        raise InputError("method", f"{options.method!r}: packed points take {BATCH_METHODS}")
    n = packed.valid.size
    t_cr = np.full(n, math.nan)
    status = np.full(n, Status.INVALID_INPUT, dtype=np.int8)
    stats = _stats(n)
    valid = np.flatnonzero(packed.valid)
    one_by_one = []
    if options.method == "set-valued":
        one_by_one.append((valid, "set-valued"))
        valid = valid[:0]
    elif options.method == "auto":
        chosen = [dispatched_method("auto", packed.p[k], packed.y0[k]) for k in valid]
        exact = np.array([m == "set-valued" for m in chosen], dtype=bool)
        one_by_one.append((valid[exact], "set-valued"))
        valid = valid[~exact]
    kernels = packed.p[valid, P_KERNEL]
    groups = []
    for kernel in np.unique(kernels):
        idx = valid[kernels == kernel]
        if end_states is None and idx.size < lanes_pay_from(kernel):
            one_by_one.append((idx, "regularised"))
        else:
            groups.append(idx)
    to_t_max = end_states is not None
    for idx, chosen_method in one_by_one:
        outs, nfev = run_one_by_one(packed, idx, options, chosen_method, to_t_max, n_lanes)
        stats["nfev"] += nfev
        for k, out in zip(idx, outs, strict=True):
            t_cr[k], status[k] = point_status(Status(out.status), float(out.t_event))
            stats["nfev"] += int(out.nfev)
            if chosen_method == "set-valued":
                stats["n_set_valued"] += 1
            else:  # Radau IIA ran if it evaluated a Jacobian
                stats["n_stiff"] += int(out.njev > 0)
            if end_states is not None:
                end_states[k] = out.y[-1] if out.y.shape[0] else out.y_end
            if point_nfev is not None:
                point_nfev[k] = out.nfev
    for idx in groups:
        y_end, nfev = _run_group(idx, packed.take(idx), options, n_lanes, t_cr, status, stats)
        if end_states is not None:
            end_states[idx] = y_end
        if point_nfev is not None:
            point_nfev[idx] = nfev
    return t_cr, status, stats


def lanes_pay_from(kernel: float) -> int:
    """Fewest points of one right-hand-side `kernel` that :func:`integrate_packed` runs in
    lanes; fewer run one by one (the same t_cr: the DOP853 lanes are bit-equal to the
    scalar DOP853, and so few stiff points would go one by one anyway).

    The thesis kernel's lanes evaluate the right-hand side as vectors: measured on a
    2-vCPU Zen 4 (``python -m benchmarks.small_groups``: rig, 250-440 rad/s, rtol 1e-9),
    one point in lanes took 3.3x its time one by one, two 2.3x, three 1.55x, four 1.2x,
    six 0.82x, eight 0.66x; its strengthening variant alike (one 3.2x, eight 0.63x). The
    generic kernel's lanes evaluate it lane by lane, so its DOP853 lanes never paid
    (a slip-speed law, measured before it had a variant: one point 2.5x, eight 1.2x, 28
    1.04x; the tanh family now: one point 2.6-2.7x, eight 1.24-1.27x); only
    the Radau IIA lanes of :data:`RADAU_LANES_MIN_GENERIC` points do
    (:data:`GENERIC_LANES_MIN`). With the rule, one to four points cost 1.03-1.2x the
    loop over :func:`~obturator.solve.opening_time`.
    """
    return GENERIC_LANES_MIN if kernel == KERNEL_GENERIC else THESIS_LANES_MIN


def _run_group(idx, packed, options, n_lanes, t_cr, status, stats) -> tuple[np.ndarray, np.ndarray]:
    """Points of one kernel: DOP853 lanes, stiff points on in Radau IIA lanes, the points
    where sliding resumed back in DOP853 lanes, and so on, as :func:`continue_auto` does
    for one point; stiff points too few for Radau IIA lanes finish one by one through
    :func:`continue_auto` itself."""
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
    radau_lanes = env_switch("OBTURATOR_RADAU_LANES")
    thesis = p[0, P_KERNEL] != KERNEL_GENERIC
    fewest = RADAU_LANES_MIN if thesis else RADAU_LANES_MIN_GENERIC
    pending = np.arange(n)
    while pending.size:
        sel = pending
        st, t_ev = _advance(
            integrate_lanes, sel, y, t, cnt, p, scale, t_max, h0, h_max, max_steps,
            np.argsort(-spin[sel], kind="stable"), options.rtol, options.atol,
            options.event_tol, n_lanes,
        )  # fmt: skip
        _settle(sel, st, t_ev, st != Status.STIFF, end_status, t_event)
        stiff = sel[st == Status.STIFF]
        went_stiff[stiff] = True
        in_lanes = stiff[np.all(np.isfinite(y[stiff]), axis=1) & (t[stiff] > 0.0)]
        if in_lanes.size < fewest or not radau_lanes:
            in_lanes = in_lanes[:0]
        for g in np.setdiff1d(stiff, in_lanes):
            problem = Problem(packed.y0[g], p[g], scale[g])
            controls = integration_controls(options, float(t_max[g]), float(h0[g]), float(h_max[g]))
            dop = RawSolution(
                Status.STIFF, math.nan, np.full(N_STATE, math.nan), np.empty(0),
                np.empty((0, N_STATE)), int(cnt[0, g]), 0, int(cnt[1, g]), int(cnt[2, g]),
                float(t[g]), y[g].copy(),
            )  # fmt: skip
            out = continue_auto(dop, problem, controls, int(hand_backs[g]))
            cnt[0, g] = out.nfev
            y[g] = out.y_end
            end_status[g], t_event[g] = out.status, out.t_event
        pending = in_lanes
        if in_lanes.size:
            rtol, atol = auto_radau_tolerances(options.rtol, options.atol)
            st, t_ev = _advance(
                integrate_radau_lanes, in_lanes, y, t, cnt, p, scale, t_max, h0, h_max,
                max_steps, hand_backs[in_lanes] < AUTO_HAND_BACKS,
                np.argsort(spin[in_lanes], kind="stable"), rtol, atol, options.event_tol,
                n_lanes, LANES,
            )  # fmt: skip
            back = st == Status.NONSTIFF
            _settle(in_lanes, st, t_ev, ~back, end_status, t_event)
            pending = in_lanes[back]
            hand_backs[pending] += 1
    stats["nfev"] += int(cnt[0].sum())
    stats["n_stiff"] += int(went_stiff.sum())
    stats["n_hand_backs"] += int(hand_backs.sum())
    for g, k in enumerate(idx):
        t_cr[k], status[k] = point_status(Status(int(end_status[g])), float(t_event[g]))
    return y, cnt[0]


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
