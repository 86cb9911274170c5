"""The obturator integrated along the flight: trajectory-coupled load and spin.

The trajectory does not depend on the ball (one-way coupling: the ball's
reaction on the projectile's flight is neglected; its spin reaction is
neglected too, the projectile spin following the aerodynamic roll damping).
So the flight is integrated first (:func:`obturator.envelope.trajectory.fly`)
and the obturator is then integrated in segments of length Delta: on segment
[t_k, t_k + Delta] the thesis's flight case (Table 1 "aerodynamic model",
Eqs. 43-55, 63) is solved with the load F_p and the projectile spin omega_p
frozen at their mid-segment values,

    F_p = pi r_p^2 (P_2 - P_1)(M(t_k + Delta/2), P_1(t_k + Delta/2))  (Eqs. 1, 3, 43),
    omega_p = omega_p(t_k + Delta/2),

restarting from the previous segment's final state. Many points advance
together: segment k of every point still running is one call of the front door
:func:`obturator.solve.advance` (the SIMD lanes). The ball's own angular velocity is
continuous across segment boundaries; the spin is stored as the last state
component (``y[7]``) and replaced by the new projectile spin. The midpoint rule
makes the error second order in Delta; :func:`coupled_convergence` halves
Delta and reports the change together with the package's usual checks
(tolerances and friction width divided by 10, as in
:func:`obturator.solve.convergence_check`).

A cleaner route would pass F_p(t) and omega_p(t) into the compiled right-hand
side (a tabulated load in the parameter vector); that needs a change of the
numeric core and is not made here.

Where the flight Mach number falls to 1 before the bore opens, the
normal-shock load model of the thesis ends and the point gets status
:data:`STATUS_SUBSONIC`.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._docs import field_docs
from ..errors import InputError, check_range
from ..json_values import finite_or_none
from ..model.case import Case, initial_state
from ..solve import (
    SolverOptions,
    advance,
    refined_options,
    simulate,
)
from ..status import FLAGS, Status
from .design import ObturatorDesign, constant_case, constant_opening  # re-exported here
from .trajectory import Launch, Projectile, Trajectory, fly

__all__ = [
    "STATUS_OPENED",
    "STATUS_NOT_OPENED",
    "STATUS_FAILED",
    "STATUS_INVALID",
    "STATUS_UNCONVERGED",
    "STATUS_SUBSONIC",
    "STATUS_FLAGS",
    "ObturatorDesign",
    "CoupledOpening",
    "CoupledConvergence",
    "FlightPoints",
    "coupled_opening",
    "coupled_openings",
    "coupled_convergence",
    "coupled_convergences",
    "constant_case",
    "constant_opening",
    "cached_flight",
    "DEFAULT_SEGMENT",
]

#: Status codes of a coupled opening: members of :class:`obturator.status.Status`.
STATUS_OPENED = Status.OPENED
STATUS_NOT_OPENED = Status.T_MAX
STATUS_FAILED = Status.FAILED  # integrator failure or step limit
STATUS_INVALID = Status.INVALID_INPUT
STATUS_UNCONVERGED = Status.UNCONVERGED
STATUS_SUBSONIC = Status.SUBSONIC
#: Flag names (CF ``flag_meanings``) of the statuses a coupled opening can have.
STATUS_FLAGS = {
    s: FLAGS[s]
    for s in (
        STATUS_INVALID,
        STATUS_FAILED,
        STATUS_NOT_OPENED,
        STATUS_OPENED,
        STATUS_UNCONVERGED,
        STATUS_SUBSONIC,
    )
}

#: Stop angle of a segment whose Mach cannot start the tube [rad] (never reached).
_NEVER = 1e-12

#: Default segment length Delta [s] of the piecewise-constant load.
DEFAULT_SEGMENT = 2e-3


@functools.lru_cache(maxsize=64)
def cached_flight(projectile: Projectile, launch: Launch, t_end: float) -> Trajectory:
    """:func:`fly` with a per-process cache (the flight does not depend on the ball)."""
    return fly(projectile, launch, t_end)


@field_docs
@dataclass(frozen=True)
class CoupledOpening:
    """Result of one trajectory-coupled opening."""

    #: Opening time [s]; NaN if the bore did not open.
    t_cr: float
    #: Outcome: :data:`STATUS_OPENED`, :data:`STATUS_NOT_OPENED`, :data:`STATUS_SUBSONIC` or
    #: :data:`STATUS_FAILED`.
    status: int
    #: Segment length Delta [s].
    segment: float
    #: Segments integrated.
    n_segments: int
    #: Flight Mach number at t_cr (or at the end) [-].
    mach_end: float
    #: Load F_p at t_cr (or at the end) [N].
    force_end: float
    #: Spin at t_cr (or at the end) [rad/s].
    spin_end: float
    #: Right-hand-side evaluations of the obturator integrator.
    nfev: int
    #: Recorded history, with ``record=True`` (None otherwise): arrays ``t`` [s], ``theta``
    #: [rad], ``force`` [N], ``spin`` [rad/s] and ``mach`` [-] by name.
    history: dict[str, np.ndarray] | None = field(default=None, repr=False)

    @property
    def opened(self) -> bool:
        """True when theta reached theta_cr."""
        return math.isfinite(self.t_cr)


@dataclass(eq=False)
class _Segments:
    """One point's flight cut into segments, and where its integration stands."""

    design: ObturatorDesign
    trajectory: Trajectory
    t_end: float
    scale: float  #: muzzle spin / the trajectory's
    stop_angle: Callable[[float], float] | None
    starts: np.ndarray
    lengths: np.ndarray
    machs: np.ndarray
    forces: np.ndarray
    spins: np.ndarray
    y: np.ndarray  #: state at the start of the next segment
    k: int = 0  #: segments integrated
    status: int = STATUS_NOT_OPENED  #: STATUS_NOT_OPENED while running
    running: bool = True
    t_cr: float = math.nan
    mach: float = math.nan
    force: float = math.nan
    spin: float = math.nan
    nfev: int = 0
    slot: int = -1  #: position among the points


def _segments(
    design: ObturatorDesign,
    trajectory: Trajectory,
    options: SolverOptions,
    dt: float,
    t_max: float | None,
    spin_rate: float | None,
    stop_angle: Callable[[float], float] | None,
) -> _Segments:
    t_end = trajectory.t_end if t_max is None else min(float(t_max), trajectory.t_end)
    check_range("t_max", t_end, 0.0, lo_open=True, unit="s")
    scale = 1.0
    if spin_rate is not None:
        scale = check_range("spin_rate", spin_rate, 0.0, lo_open=True, unit="rad/s") / float(
            trajectory.spin_rate(0.0)
        )
    loads = trajectory.segment_loads(dt, t_end, design.bore_radius, design.gamma)
    y = initial_state(
        math.radians(design.theta0_deg),
        scale * float(trajectory.spin_rate(0.0)),
        formulation=options.formulation,
    )
    return _Segments(design, trajectory, t_end, scale, stop_angle, *loads, y)


def _next_case(run: _Segments) -> Case | None:
    """The case of `run`'s next segment (None: the run has ended, its status set)."""
    if run.k >= run.starts.size:
        run.running = False
        return None
    run.mach = float(run.machs[run.k])
    if run.mach <= 1.0:
        run.status, run.running = STATUS_SUBSONIC, False
        return None
    run.force = float(run.forces[run.k])
    run.spin = run.scale * float(run.spins[run.k])
    run.y = run.y.copy()
    run.y[7] = run.spin
    stop = None if run.stop_angle is None else float(run.stop_angle(run.mach))
    if stop is not None and not math.isfinite(stop):
        stop = _NEVER
    return run.design.case(run.force, run.spin, float(run.lengths[run.k]), theta_cr=stop)


@dataclass(frozen=True)
class FlightPoints:
    """The points of a coupled study: per point a design, its flight and, optionally,
    the muzzle spin replacing the flight's [rad/s] and the stop angle theta_stop(M)
    (the `spin_rate` and `stop_angle` of :func:`coupled_opening`)."""

    designs: Sequence[ObturatorDesign]
    trajectories: Sequence[Trajectory]
    spin_rates: Sequence[float | None] | None = None
    stop_angles: Sequence[Callable[[float], float] | None] | None = None

    def rows(self) -> list[tuple[Any, ...]]:
        """(design, trajectory, spin_rate, stop_angle) of every point."""
        n = len(self.designs)
        spins = [None] * n if self.spin_rates is None else list(self.spin_rates)
        stops = [None] * n if self.stop_angles is None else list(self.stop_angles)
        return list(zip(self.designs, self.trajectories, spins, stops, strict=True))

    def take(self, rows: Sequence[int]) -> FlightPoints:
        """The points at positions `rows`."""
        every = self.rows()
        pick = [every[i] for i in rows]
        return FlightPoints(*(list(col) for col in zip(*pick, strict=True)))  # type: ignore[arg-type]


def coupled_openings(
    points: FlightPoints,
    options: SolverOptions | None = None,
    *,
    segment: float = DEFAULT_SEGMENT,
    t_max: float | None = None,
    record: bool = False,
) -> list[CoupledOpening | InputError]:
    """:func:`coupled_opening` of many points, segment by segment in lanes.

    Segment k of every point still running is one call of the front door
    :func:`obturator.solve.advance` (lanes, ``auto`` switching), each point from
    its own state; a point's answer does not depend on the others beyond the
    Radau IIA lanes' rounding (the same as :func:`obturator.solve.opening_times`).

    Parameters
    ----------
    points : FlightPoints
        The n points.
    options, segment, t_max, record
        As for :func:`coupled_opening`, shared by all points.

    Returns
    -------
    list of CoupledOpening or InputError
        One per point; an :class:`~obturator.errors.InputError` where that point's
        inputs are invalid.
    """
    options = options or SolverOptions()
    n = len(points.designs)
    dt = check_range("segment", segment, 0.0, 0.1, lo_open=True, unit="s")
    runs: list[_Segments | InputError] = []
    for design, tr, spin, stop in points.rows():
        try:
            runs.append(_segments(design, tr, options, dt, t_max, spin, stop))
            runs[-1].slot = len(runs) - 1  # type: ignore[union-attr]
        except InputError as exc:
            runs.append(exc)
    hist: list[dict[str, list[np.ndarray]]] = [
        {k: [] for k in ("t", "theta", "force", "spin", "mach")} for _ in range(n)
    ]
    live = [r for r in runs if isinstance(r, _Segments)]
    while live:
        cases, now = [], []
        for run in live:
            try:
                case = _next_case(run)
            except InputError as exc:
                runs[run.slot] = exc
                continue
            if case is not None:
                cases.append(case)
                now.append(run)
        if not cases:
            break
        out = advance(cases, np.array([r.y for r in now]), options)
        statuses, nfevs = out.status.tolist(), out.nfev.tolist()  # Python ints, once
        for j, run in enumerate(now):
            if record:
                _record(hist[run.slot], run, cases[j], options)
            run.k += 1
            run.nfev += nfevs[j]
            if statuses[j] == STATUS_OPENED:
                run.t_cr = float(run.starts[run.k - 1]) + float(out.t_cr[j])
                run.status, run.running = STATUS_OPENED, False
            elif statuses[j] == STATUS_NOT_OPENED:
                run.y = out.state[j]
            else:
                run.status, run.running = STATUS_FAILED, False
        live = [r for r in now if r.running]
    return [
        r if isinstance(r, InputError) else _opening(r, dt, hist[i], record)
        for i, r in enumerate(runs)
    ]


def _record(
    hist: dict[str, list[np.ndarray]], run: _Segments, case: Case, options: SolverOptions
) -> None:
    """theta(t) over the segment, 20 samples (a second, recording run of the segment)."""
    h = float(run.lengths[run.k])
    res = simulate(case, options, y0=run.y, t_eval=np.linspace(0.0, h, 21)[1:])
    t0 = float(run.starts[run.k])
    for name, val in (
        ("t", t0 + res.t),
        ("theta", res.theta),
        ("force", np.full(res.t.size, run.force)),
        ("spin", np.full(res.t.size, run.spin)),
        ("mach", np.full(res.t.size, run.mach)),
    ):
        hist[name].append(np.asarray(val))


def _opening(
    run: _Segments, dt: float, hist: dict[str, list[np.ndarray]], record: bool
) -> CoupledOpening:
    status = run.status
    tr = run.trajectory
    if status == STATUS_NOT_OPENED and tr.subsonic and run.t_end >= tr.t_end:
        status = STATUS_SUBSONIC
    history = {name: np.concatenate(v) if v else np.empty(0) for name, v in hist.items()}
    return CoupledOpening(
        run.t_cr, status, dt, run.k, run.mach, run.force, run.spin, run.nfev,
        history if record else None,
    )  # fmt: skip


def coupled_opening(
    design: ObturatorDesign,
    trajectory: Trajectory,
    options: SolverOptions | None = None,
    *,
    segment: float = DEFAULT_SEGMENT,
    t_max: float | None = None,
    spin_rate: float | None = None,
    record: bool = False,
    stop_angle: Callable[[float], float] | None = None,
) -> CoupledOpening:
    """Integrate the obturator along a flight with piecewise-constant load and spin.

    Parameters
    ----------
    design : ObturatorDesign
    trajectory : Trajectory
        The flight (:func:`obturator.envelope.trajectory.fly`).
    options : SolverOptions, optional
        Obturator integrator settings.
    segment : float
        Segment length Delta [s], in (0, 0.1].
    t_max : float, optional
        Give up at this time [s]; default the trajectory's end.
    spin_rate : float, optional
        Muzzle spin [rad/s] replacing the trajectory's; omega_p(t) is scaled
        (exact: the roll-damping equation is linear in omega_p and the
        translational motion does not depend on it).
    record : bool
        Keep theta(t), F_p(t), omega_p(t), M(t) (20 samples per segment).
    stop_angle : callable, optional
        theta_stop(M) [rad] per segment instead of first light: with
        :meth:`ObturatorDesign.start_angle` the run ends when the tube starts
        (t_start, the closed-bore load kept past first light); NaN (cannot
        start at that Mach) runs the segment without a stop.

    Returns
    -------
    CoupledOpening

    Raises
    ------
    InputError
        Invalid segment, t_max, spin rate or design.
    """
    one = FlightPoints([design], [trajectory], [spin_rate], [stop_angle])
    (res,) = coupled_openings(one, options, segment=segment, t_max=t_max, record=record)
    if isinstance(res, InputError):
        raise res
    return res


@field_docs
@dataclass(frozen=True)
class CoupledConvergence:
    """Change of coupled t_cr under refinement (cf. :class:`obturator.solve.ConvergenceCheck`)."""

    #: t_cr with the given options and segment [s].
    t_cr: float
    #: t_cr [s] of each refined rerun, by name: ``"tighter_tolerance"`` (rtol, atol / factor),
    #: ``"narrower_width"`` (friction width / factor), ``"other_family"`` and ``"half_segment"``
    #: (Delta / 2).
    variants: dict[str, float]
    #: Largest relative change accepted as converged.
    threshold: float = 1e-3

    def change(self, name: str) -> float:
        """|t_variant - t_cr| / t_cr (0 if neither opened, inf if only one did)."""
        a, b = self.t_cr, self.variants[name]
        if math.isnan(a) and math.isnan(b):
            return 0.0
        if math.isnan(a) or math.isnan(b):
            return math.inf
        return abs(b - a) / abs(a)

    @property
    def max_change(self) -> float:
        """Largest relative change over the variants."""
        return max((self.change(k) for k in self.variants), default=0.0)

    @property
    def converged(self) -> bool:
        """Every relative change below the threshold."""
        return self.max_change < self.threshold

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (None for NaN / inf)."""

        out: dict[str, Any] = {"converged": self.converged, "threshold": self.threshold}
        for k in self.variants:
            out[f"t_cr_{k}_s"] = finite_or_none(self.variants[k])
            out[f"{k}_rel_change"] = finite_or_none(self.change(k))
        return out


def coupled_convergences(
    points: FlightPoints,
    options: SolverOptions | None = None,
    *,
    segment: float = DEFAULT_SEGMENT,
    t_max: float | None = None,
    factor: float = 10.0,
    threshold: float = 1e-3,
    t_cr: Sequence[float] | None = None,
    variants: Mapping[str, SolverOptions] | None = None,
) -> list[CoupledConvergence | InputError]:
    """:func:`coupled_convergence` of many points, each rerun batched as in
    :func:`coupled_openings`."""
    options = options or SolverOptions()

    def times(opts: SolverOptions, dt: float = segment) -> list[float | InputError]:
        res = coupled_openings(points, opts, segment=dt, t_max=t_max)
        return [r if isinstance(r, InputError) else r.t_cr for r in res]

    base = times(options) if t_cr is None else [float(t) for t in t_cr]
    if variants is None:
        names = ("tighter_tolerance", "narrower_width", "other_family")
        variants = dict(zip(names, refined_options(options, factor), strict=True))
    reruns = {name: times(opts) for name, opts in variants.items()}
    reruns["half_segment"] = times(options, 0.5 * segment)
    out: list[CoupledConvergence | InputError] = []
    for i, t in enumerate(base):
        bad = [x for x in (t, *(r[i] for r in reruns.values())) if isinstance(x, InputError)]
        out.append(
            bad[0]
            if bad
            else CoupledConvergence(float(t), {k: r[i] for k, r in reruns.items()}, threshold)  # type: ignore[misc]
        )
    return out


def coupled_convergence(
    design: ObturatorDesign,
    trajectory: Trajectory,
    options: SolverOptions | None = None,
    *,
    segment: float = DEFAULT_SEGMENT,
    t_max: float | None = None,
    spin_rate: float | None = None,
    factor: float = 10.0,
    threshold: float = 1e-3,
    t_cr: float | None = None,
    variants: Mapping[str, SolverOptions] | None = None,
    stop_angle: Callable[[float], float] | None = None,
) -> CoupledConvergence:
    """Recompute the coupled t_cr with refined tolerances, friction width and segment.

    Parameters
    ----------
    design, trajectory, options, segment, t_max, spin_rate
        As for :func:`coupled_opening`.
    factor : float
        Refinement factor of the tolerances and the friction width.
    threshold : float
        Relative change accepted as converged.
    t_cr : float, optional
        The unrefined t_cr if already computed [s].
    variants : mapping of str to SolverOptions, optional
        Solver variants to rerun; default the three of
        :func:`obturator.solve.convergence_check` (:func:`obturator.solve.refined_options`):
        tolerances divided by `factor`, friction width divided by `factor` (tolerances
        too, so slip speeds of order the width stay resolved), and the other
        regularisation family, since a width study alone cannot show convergence to the
        wrong limit. The half-segment rerun is always added.
    stop_angle : callable, optional
        As for :func:`coupled_opening` (the check of t_start).
    """
    (res,) = coupled_convergences(
        FlightPoints([design], [trajectory], [spin_rate], [stop_angle]), options,
        segment=segment, t_max=t_max, factor=factor, threshold=threshold,
        t_cr=None if t_cr is None else [t_cr], variants=variants,
    )  # fmt: skip
    if isinstance(res, InputError):
        raise res
    return res
