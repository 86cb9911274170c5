"""Return map of stick-slip cycles at constant spin: hundreds of windows, a few integrated.

At constant spin the rig's ball goes through two slip windows per revolution (its stick
set is left where |cos psi| < kappa, ``docs/stick_slip.md``); at 40 rad/s that is 549
cycles before it opens, each integrated through its stiff slip window by
:mod:`.stick_slip`. The cycles are all one map of a single variable:

* the equations of motion (thesis Eqs. 5a-5c with the law of Eqs. 56-64, Appendix A) are
  invariant under turning the ball about its own axis z (axisymmetric, A = B; the torque
  depends on omega_r and z only) and, at constant spin, under turning everything by pi
  about the spin axis Z (ARM depends on u_X^2, u_Y^2, u_Z^2 only; Z x (I Z) turns along);
  they are autonomous;
* a breakaway state is stick (omega_r = 0) with z at the closed-form exit azimuth of
  :func:`~obturator.core.friction_sets.breakaway_angle`, so it is
  q = Z(k pi) B(theta) z(phi): B(theta) the canonical breakaway attitude at nutation
  theta, k an integer, phi the turn about the hole axis.

So the state at the next breakaway (a Poincare section at the exits of the stick set)
is Z((k + k') pi) B(theta + D(theta)) z(phi + Phi(theta)), reached after T(theta):
three smooth functions of theta alone and an integer k'. They are computed by
integrating one cycle from B(theta_j) (at :data:`NODE_TOL_FACTOR` of the tolerances) at
Chebyshev-Lobatto nodes in the variable :func:`abscissa` between theta_1 (the second
breakaway) and max(theta_cr, :data:`THETA_LOW`), interpolated (log(-D), T, Phi), and
the map is iterated over the cycles; the last :data:`LAST_CYCLES` cycles of the
interval, and those below it, are integrated again, with the opening event, from the
state the map gives. The interpolation error is estimated by the last two Chebyshev
coefficients of 9, 17 or 33 nodes (nested); a map whose estimate does not reach
:data:`MAP_TOL` times rtol by :data:`MAX_NODES` nodes (nor stops falling there, within
:data:`PLATEAU_TOL`: the nodes' own noise), whose nodes' cycles differ in kind (k', or
the number of half periods), or where a cycle does not decrease theta, is not used: the
cycles are then integrated one by one, as without the map. So is a map that would leave
fewer cycles than its next nodes. Where the nodes keep one kind from the top down to
some node only (below it the cycles no longer stick again, or change kind), the map is
built again down to that node and ends there, above theta_cr. Only runs that need the opening time
alone use it (no recorded steps, no output times, a terminal event, constant spin).
The map is a Poincare (first-return) map; its use to skip nearly periodic cycles is
the idea of envelope following (Petzold, SIAM J. Sci. Stat. Comput. 2, 1981), here
exact up to interpolation because the cycles depend on theta alone.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import numpy as np
from numba import njit

from ..._docs import field_docs
from ..friction_sets import breakaway_angle, hold_stick, turn_rigidly
from ..jit_flags import NO_REFCOUNT, REFCOUNT
from ..layout import FRIC_COULOMB, P_FRIC, P_SPIN_MODE, P_THETA_CR, SPIN_CONSTANT
from .contract import Controls, Problem, RawSolution, Status

__all__ = [
    "CycleMap",
    "MAP_TOL",
    "MAX_NODES",
    "MAP_MIN_CYCLES",
    "MIN_KIND_NODES",
    "NODE_TOL_FACTOR",
    "PLATEAU_TOL",
    "applies",
    "cycles_ahead",
    "integrate",
    "node_thetas",
]

#: Largest estimated interpolation error accepted (the last two Chebyshev coefficients),
#: in units of the requested rtol: of log(-D) (relative error of the change of theta per
#: cycle) and of T in units of half a spin period (at rtol 1e-8: 5e-7).
MAP_TOL = 50.0
#: Most nodes (Chebyshev-Lobatto levels 9, 17, 33).
MAX_NODES = 33
#: The nodes' cycles run at this fraction of the requested tolerances: an error of the
#: map is made in every cycle alike, where the cycles integrated one by one vary.
NODE_TOL_FACTOR = 0.1
#: Fewest cycles (:func:`cycles_ahead`) for which the map is built: a node costs about
#: two cycles integrated one by one, and 17 nodes are the usual need.
MAP_MIN_CYCLES = 60.0
#: Cycles left to the opening that are integrated one by one again.
LAST_CYCLES = 3
#: Largest estimate accepted at :data:`MAX_NODES` nodes where more nodes no longer lower
#: it (:func:`_at_noise_floor`), absolute in log(-D) and T / half period: the t_cr of
#: mapped cycles errs by about as much, relative, a tenth of the 1e-6 contract of the
#: default; the cycles integrated one by one instead err by more over thousands of
#: cycles (``docs/stick_slip.md``). :data:`MAP_TOL` accepts as much at rtol 2e-9 and
#: above, so it changes only runs at tighter tolerances (the validation's).
PLATEAU_TOL = 1e-7
#: Fewest of the 9 nodes (from the top) whose cycles are of one kind for the map to be
#: built again down to the last of them (:func:`_build_map`): a map over fewer would
#: save few cycles for its nodes' cost.
MIN_KIND_NODES = 4
#: Lowest nutation angle [rad] of the map's interval (the cycles below it, a handful
#: with the largest changes of theta, are integrated one by one).
THETA_LOW = math.radians(50.0)
#: Turn [rad] back into stick from which a node's cycle starts (the breakaway then
#: goes through the mode loop's own stick exit).
_BACK = 1e-3

RunCycles = Callable[[Problem, Controls, float], RawSolution]


@field_docs
class CycleMap(NamedTuple):
    """One spin's return map: Chebyshev series in :func:`abscissa` over [lo, hi]."""

    #: :func:`abscissa` of the map's lowest nutation angle, `theta_stop`.
    lo: float
    #: :func:`abscissa` of its highest nutation angle.
    hi: float
    #: Coefficients of log(-D) [log rad], D the change of theta over one cycle.
    c_logd: np.ndarray
    #: Coefficients of the cycle's duration T [s].
    c_time: np.ndarray
    #: Coefficients of the cycle's turn Phi about the hole axis [rad].
    c_phi: np.ndarray
    #: Half turns k' about the spin axis per cycle (0 or 1).
    k_step: int
    #: Nutation angle [rad] at which the iteration stops (that of `lo`).
    theta_stop: float
    #: Cycles before `theta_stop` that the case integrates itself: :data:`LAST_CYCLES`
    #: where the opening may follow, 1 where the map ends above theta_cr.
    last_cycles: int

    def covers(self, theta: float) -> bool:
        """Whether the nutation `theta` [rad] lies in the map's interval."""
        x = abscissa(theta)
        return min(self.lo, self.hi) <= x <= max(self.lo, self.hi)


def applies(problem: Problem, controls: Controls) -> bool:
    """Whether the run may use the map: constant spin, only the opening time wanted, and
    the thesis law (under the Coulomb patch law the slip also passes through zero
    without sticking, twice a revolution on the rig: its "cycles" are not the map's;
    with it the map's t_cr was 2.4e-5 off at 300 rad/s, the cycle-by-cycle run 6e-10)."""
    return (
        problem.p[P_SPIN_MODE] == SPIN_CONSTANT
        and problem.p[P_FRIC] != FRIC_COULOMB
        and controls.terminal
        and not controls.record
        and controls.t_eval.shape[0] == 0
        and problem.y0[7] != 0.0
    )


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _canonical(theta: float, p: np.ndarray, wp: float, back: float, out: np.ndarray) -> float:
    """`out` = stick state at nutation `theta`, turned `back` [rad] before its breakaway,
    phi = 0 (z at azimuth 0 first, where stick holds longest); returns the breakaway
    angle from azimuth 0 [rad] (not finite or <= `back`: no exit window)."""
    c, s = math.cos(0.5 * theta), math.sin(0.5 * theta)
    r = math.sqrt(0.5)  # q_Z(pi / 2) q_X(theta): z = (sin theta, 0, cos theta)
    out[0], out[1], out[2], out[3] = r * c, r * s, r * s, r * c
    for i in range(4, out.shape[0]):
        out[i] = 0.0
    out[7] = wp
    hold_stick(out, wp)
    angle = breakaway_angle(out, p, wp)
    if math.isfinite(angle) and angle > back:
        turn_rigidly(out, math.copysign(angle - back, wp), out)  # in place: reads q first
    return angle


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _body_turn(y: np.ndarray, phi: float) -> None:
    """q <- q z(phi) in place (turn about the body's hole axis), rates for stick."""
    c, s = math.cos(0.5 * phi), math.sin(0.5 * phi)
    q0, q1, q2, q3 = y[0], y[1], y[2], y[3]
    y[0] = q0 * c - q3 * s
    y[1] = q1 * c + q2 * s
    y[2] = q2 * c - q1 * s
    y[3] = q3 * c + q0 * s


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def compose(theta: float, k: int, phi: float, p: np.ndarray, wp: float, out: np.ndarray) -> bool:
    """`out` = the breakaway state Z(k pi) B(theta) z(phi) in stick; False if none."""
    angle = _canonical(theta, p, wp, 0.0, out)
    if not (math.isfinite(angle) and angle > 0.0):
        return False
    _body_turn(out, phi)
    turn_rigidly(out, k * math.pi, out)
    hold_stick(out, wp)
    return True


@njit(cache=True, **REFCOUNT, fastmath=False, error_model="python")
def decompose(y: np.ndarray, p: np.ndarray, wp: float) -> tuple[bool, float, int, float]:
    """(ok, theta, k, phi) of a breakaway state y = Z(k pi) B(theta) z(phi) (k in 0, 1)."""
    n = math.sqrt(y[0] ** 2 + y[1] ** 2 + y[2] ** 2 + y[3] ** 2)
    q0, q1, q2, q3 = y[0] / n, y[1] / n, y[2] / n, y[3] / n
    theta = math.acos(min(1.0, max(-1.0, 1.0 - 2.0 * (q1 * q1 + q2 * q2))))
    b = np.empty(y.shape[0])
    best, k_best, phi = math.inf, 0, 0.0
    for k in range(2):
        if not compose(theta, k, 0.0, p, wp, b):
            return False, theta, 0, 0.0
        # r = conj(b) q must be a turn about z: (cos phi/2, 0, 0, sin phi/2)
        r0 = b[0] * q0 + b[1] * q1 + b[2] * q2 + b[3] * q3
        r1 = b[0] * q1 - b[1] * q0 - b[2] * q3 + b[3] * q2
        r2 = b[0] * q2 - b[2] * q0 - b[3] * q1 + b[1] * q3
        r3 = b[0] * q3 - b[3] * q0 - b[1] * q2 + b[2] * q1
        off = abs(r1) + abs(r2)
        if off < best:
            best, k_best, phi = off, k, 2.0 * math.atan2(r3, r0)
    return best < 1e-6, theta, k_best, phi


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def _clenshaw(c: np.ndarray, x: float) -> float:
    """Chebyshev series sum_j c_j T_j(x), x in [-1, 1]."""
    b1 = 0.0
    b2 = 0.0
    for j in range(c.shape[0] - 1, 0, -1):
        b1, b2 = 2.0 * x * b1 - b2 + c[j], b1
    return x * b1 - b2 + c[0]


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def abscissa(theta: float) -> float:
    """The map's variable log(cot theta) (theta in (0, pi/2)): the exit windows'
    half-width kappa is proportional to sin theta cos theta, and D ~ kappa^3 near
    theta = pi/2; in this variable log(-D) has Chebyshev coefficients falling ~100x
    every 4 degrees (40 rad/s), against ~10x in theta itself."""
    return math.log(math.cos(theta) / math.sin(theta))


def nutation_at(x: np.ndarray) -> np.ndarray:
    """theta [rad] of the abscissa `x` (inverse of :func:`abscissa`)."""
    return np.arctan(np.exp(-x))


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="python")
def iterate(theta, t, phi, lo, hi, c_logd, c_time, c_phi, theta_stop, t_stop, last):
    """Iterate the map from the breakaway (theta, t, phi) while more than `last` cycles
    are left to `theta_stop` and the time stays below `t_stop`; [lo, hi] the interval of
    :func:`abscissa`. Returns (theta, t, phi, cycles); the half turns about Z are
    k + cycles k'."""
    cycles = 0
    while True:
        x = (2.0 * abscissa(theta) - lo - hi) / (hi - lo)
        d = -math.exp(_clenshaw(c_logd, x))
        dt = _clenshaw(c_time, x)
        if theta + last * d <= theta_stop or t + last * dt >= t_stop:
            return theta, t, phi, cycles
        theta += d
        t += dt
        phi += _clenshaw(c_phi, x)
        cycles += 1


def _lobatto(n: int) -> np.ndarray:
    """Chebyshev-Lobatto points cos(pi j / (n - 1)) in [-1, 1], from 1 down."""
    return np.cos(np.pi * np.arange(n) / (n - 1))


def coefficient_matrix(n_points: int) -> np.ndarray:
    """M with M @ v the Chebyshev coefficients of the interpolant through values v at
    the :func:`_lobatto` points (n_points of them)."""
    n = n_points - 1
    j = np.arange(n + 1)
    w = np.ones(n + 1)
    w[0] = w[-1] = 0.5
    m = (2.0 / n) * np.cos(np.pi * np.outer(j, j) / n) * w
    m[0] *= 0.5
    m[-1] *= 0.5
    return m


def node_thetas(lo: float, hi: float, n: int) -> np.ndarray:
    """Nutation angles [rad] of `n` Chebyshev-Lobatto nodes of :func:`abscissa` on
    [lo, hi], from hi (the same floats at every nested level, so nodes are reused)."""
    return nutation_at(lo + 0.5 * (hi - lo) * (1.0 + _lobatto(n)))


def _coefficients(values: np.ndarray) -> np.ndarray:
    """Chebyshev coefficients of the interpolant through values at :func:`_lobatto` points."""
    return coefficient_matrix(values.shape[0]) @ values


class _Nodes:
    """The map's values at nodes, the runs' counters, and the nodes' problem."""

    def __init__(self, problem: Problem, controls: Controls, run: RunCycles) -> None:
        self.wp = float(problem.y0[7])
        self.half = math.pi / abs(self.wp)
        p = problem.p.copy()
        p[P_THETA_CR] = -1.0  # no opening inside a node's cycle
        self.problem = problem._replace(p=p, t0=0.0)
        self.rtol = controls.rtol
        rtol, atol = controls.rtol * NODE_TOL_FACTOR, controls.atol * NODE_TOL_FACTOR
        self.controls = controls._replace(
            t_max=4.0 * self.half, rtol=rtol, atol=atol, last_slip_to_lanes=False
        )
        self.run = run
        self.values: dict[float, tuple[float, float, float, int]] = {}
        self.counts = np.zeros(4, dtype=np.int64)
        self.errors: list[float] = []

    def count(self, out: RawSolution) -> None:
        self.counts += (out.nfev, out.njev, out.n_steps, out.n_rejected)

    def cycle(self, theta: float) -> tuple[float, float, float, int] | None:
        """(log(-D), T / half period, Phi, k') of one cycle from B(theta), None if the
        cycle has no exit, does not stick again within two revolutions or keeps theta."""
        y = np.empty(self.problem.y0.shape[0])
        angle = _canonical(theta, self.problem.p, self.wp, _BACK, y)
        if not (math.isfinite(angle) and angle > _BACK):
            return None
        out = self.run(self.problem._replace(y0=y), self.controls, 0.5 * self.half)
        self.count(out)
        if out.status != Status.T_MAX or not out.t_end < self.controls.t_max:
            return None
        ok, theta_new, k, phi = decompose(out.y_end, self.problem.p, self.wp)
        if not ok or not theta_new < theta:
            return None
        t_cycle = out.t_end - _BACK / abs(self.wp)
        return math.log(theta - theta_new), t_cycle / self.half, phi, k

    def at(self, thetas: np.ndarray) -> np.ndarray | None:
        """Node values, rows (log(-D), T / half period, Phi, k'), None if any fails."""
        rows = self.leading(thetas)
        return rows if rows.shape[0] == thetas.shape[0] else None

    def leading(self, thetas: np.ndarray) -> np.ndarray:
        """Node values of `thetas` (from the top) up to the first that fails."""
        rows = []
        for th in thetas:
            key = float(th)
            if key not in self.values:
                v = self.cycle(key)
                if v is None:
                    break
                self.values[key] = v
            rows.append(self.values[key])
        return np.array(rows).reshape(len(rows), 4)


def _same_kind(rows: np.ndarray) -> int:
    """How many of the node `rows` (from the top) have the first's kind: k' and whole
    half periods."""
    kind = (rows[:, 3] == rows[0, 3]) & (np.round(rows[:, 1]) == np.round(rows[0, 1]))
    return int(np.argmin(kind)) if not kind.all() else rows.shape[0]


def _build_map(nodes: _Nodes, theta_lo: float, theta: float, t: float) -> CycleMap | None:
    """The map on [theta_lo, theta] [rad] from this run's spin alone, the run at its
    breakaway at nutation `theta` and time `t` [s]; None where the estimate does not
    reach :data:`MAP_TOL` by :data:`MAX_NODES` nodes, where the nodes' cycles differ in
    kind (k', or whole half periods), or where the 9-node map leaves fewer cycles than
    the next level's nodes.

    Where the 9 nodes' cycles keep their kind from the top down to some node but not
    below it (a node's cycle that does not stick again, or one of another kind: near
    theta_0 = 90 deg the cycles above ~65 deg are the slow ones, those below of another
    kind), the map is built once more on the interval down to the last node of the
    top's kind, and ends there, above theta_cr: the cycles below, few and of large
    change, are integrated one by one with the rest."""
    built = _map_on(nodes, theta_lo, theta, t, LAST_CYCLES)
    if isinstance(built, CycleMap):
        return built
    if built < MIN_KIND_NODES:
        return None
    top = float(node_thetas(abscissa(theta_lo), abscissa(theta), 9)[built - 1])
    shrunk = _map_on(nodes, top, theta, t, 1)
    return shrunk if isinstance(shrunk, CycleMap) else None


def _at_noise_floor(errors: list[float]) -> bool:
    """Whether the last two levels' estimates (17 and 33 nodes) show interpolation at the
    noise of the nodes' own integration and within :data:`PLATEAU_TOL`: the estimate no
    longer falls with twice the nodes (a converging series falls by orders), so more
    nodes cannot lower it; near theta = 90 deg, where one cycle changes theta by ~1e-5
    rad, the nodes' absolute error in theta sets it."""
    return len(errors) >= 2 and errors[-1] > 0.25 * errors[-2] and errors[-1] <= PLATEAU_TOL


def _map_on(nodes: _Nodes, theta_lo: float, theta: float, t: float, last: int) -> CycleMap | int:
    """:func:`_build_map` on [theta_lo, theta] with `last` cycles left to the run; where
    it fails, the count of the 9-node level's nodes of the top's kind (from the top;
    0 where that level had them all, or was not reached)."""
    lo, hi = abscissa(theta_lo), abscissa(theta)
    n = 9
    while n <= MAX_NODES:
        rows = nodes.leading(node_thetas(lo, hi, n))
        kind = _same_kind(rows) if rows.shape[0] else 0
        if kind < n:
            return kind if n == 9 else 0
        c = [_coefficients(rows[:, i]) for i in range(3)]
        c[1] *= nodes.half
        # error estimate: the last two Chebyshev coefficients (log(-D), T / half period)
        err = max(np.max(np.abs(c[0][-2:])), np.max(np.abs(c[1][-2:])) / nodes.half)
        nodes.errors.append(float(err))
        if err <= MAP_TOL * nodes.rtol or (n == MAX_NODES and _at_noise_floor(nodes.errors)):
            return CycleMap(lo, hi, c[0], c[1], c[2], int(rows[0, 3]), theta_lo, last)
        if n == 9:
            cycles = iterate(theta, t, 0.0, lo, hi, *c, theta_lo, math.inf, last)[3]
            if cycles < 2 * (n - 1):
                return 0
        n = 2 * n - 1
    return 0


def integrate(
    problem: Problem, controls: Controls, run: RunCycles, shared: CycleMap | None = None
) -> RawSolution:
    """The run of :mod:`.stick_slip` with its cycles through the return map.

    `run(problem, controls, cycle_end)` is the mode loop stopping at the first
    breakaway at or after `cycle_end` [s]. `shared` is a map built for this problem's
    spin by :func:`.stick_slip_family.shared_maps` (cases that differ in spin alone):
    it is iterated from the first breakaway on if that lies in its interval, and no
    map is built here. Counters (nfev, steps, ...) include this run's own nodes.
    """
    wp = float(problem.y0[7])
    nodes = _Nodes(problem, controls, run)
    y, t = problem.y0, problem.t0  # where the next run starts
    thetas = []
    built = None
    for _ in range(2):  # to the first breakaway, and one cycle: theta's first change
        res = run(problem._replace(y0=y, t0=t), controls, t + 0.5 * nodes.half)
        nodes.count(res)
        if res.status != Status.T_MAX or not res.t_end < controls.t_max:
            return _with_counts(res, nodes, res)
        ok, theta, k, phi = decompose(res.y_end, problem.p, wp)
        thetas.append(theta if ok else math.nan)
        y, t = _rewound(res.y_end, wp), res.t_end - _BACK / abs(wp)
        t_break = res.t_end
        if shared is not None and ok and shared.covers(theta):
            built = shared
            break
    theta_lo = max(float(problem.p[P_THETA_CR]), THETA_LOW)
    if built is None and len(thetas) == 2:
        d = thetas[1] - thetas[0]
        if d < 0.0 and theta > theta_lo and cycles_ahead(theta_lo, theta, -d) > MAP_MIN_CYCLES:
            built = _build_map(nodes, theta_lo, theta, t_break)
    if built is not None:
        theta, t_map, phi, cycles = iterate(
            theta, t_break, phi, built.lo, built.hi, built.c_logd, built.c_time,
            built.c_phi, built.theta_stop, controls.t_max, built.last_cycles,
        )  # fmt: skip
        k += cycles * built.k_step
        y_map = np.empty_like(y)
        if cycles > 0 and compose(theta, k, phi, problem.p, wp, y_map):
            y, t = _rewound(y_map, wp), t_map - _BACK / abs(wp)
    last = run(problem._replace(y0=y, t0=t), controls, math.inf)
    return _with_counts(last, nodes, None)


def cycles_ahead(theta_lo: float, theta: float, drop: float) -> float:
    """Estimated cycles from `theta` down to `theta_lo` [rad] when the first cycle lowers
    theta by `drop` [rad], with D ~ kappa^3 ~ (sin theta cos theta)^3 (the exit
    windows' width, excess and duration each ~ kappa): sum dtheta / |D|."""
    th = np.linspace(theta_lo, theta, 201)
    ratio = (np.sin(th) * np.cos(th) / (math.sin(theta) * math.cos(theta))) ** 3
    inv = 1.0 / (drop * ratio)
    return float(np.sum(0.5 * (inv[1:] + inv[:-1]) * np.diff(th)))


def _rewound(y: np.ndarray, wp: float) -> np.ndarray:
    """A breakaway state turned back by :data:`_BACK` into stick (rigid motion, exact):
    the run from there leaves stick through the mode loop's own exit."""
    out = np.empty_like(y)
    turn_rigidly(y, -math.copysign(_BACK, wp), out)
    return out


def _with_counts(out: RawSolution, nodes: _Nodes, counted: RawSolution | None) -> RawSolution:
    """`out` with the counters of every run (`counted`: `out` itself was counted)."""
    nfev, njev, n_steps, n_rej = nodes.counts
    if counted is None:
        nfev, njev = nfev + out.nfev, njev + out.njev
        n_steps, n_rej = n_steps + out.n_steps, n_rej + out.n_rejected
    return out._replace(nfev=int(nfev), njev=int(njev), n_steps=int(n_steps), n_rejected=int(n_rej))
