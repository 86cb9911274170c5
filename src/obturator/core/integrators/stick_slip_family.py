"""One return map for many spins: the cycle map of :mod:`.stick_slip_map` in (theta, omega_p).

A sweep over the spin rate gives the set-valued solver hundreds of cases that differ in
the spin alone. Each would build its own return map from 17-33 integrated cycles
(:mod:`.stick_slip_map`), which at 40-70 rad/s is most of its cost, and below about
60 predicted cycles (70-218 rad/s on the rig) it builds none and integrates every
cycle. Yet the map's three functions D, T, Phi of theta are smooth in the spin too:
at constant spin the cycle from the breakaway state B(theta) depends on theta and
omega_p alone (the other parameters equal), D ~ kappa^3 with kappa ~ omega_p^2, so
log(-D) is close to linear in log(omega_p). So cases are grouped (equal parameters,
initial attitude, tolerances, and steps proportional to the spin period) and each
group's spins fall into fixed bands, [BAND_RATIO^k, BAND_RATIO^(k+1)) rad/s
(:func:`band_edges`); per band the cycles are integrated on a tensor grid of
Chebyshev-Lobatto nodes, in :func:`abscissa` of theta (from the initial nutation down
to theta_cr, or to where the stick ratio reaches :data:`KAPPA_END`:
:meth:`_Grid.interval`) and in log(omega_p), and interpolated. The error estimate is
that of the one-spin map in each direction (the last two Chebyshev coefficients,
summed over the other direction, which bounds them at every node of it) against
:data:`~.stick_slip_map.MAP_TOL` times rtol; the grid grows (nested levels, 9-17-33 in
theta, 5-9-17 in the spin) until both hold. A band whose nodes' cycles differ in kind,
or that does not converge, is halved (at most :data:`MAX_SPLITS` times); else its cases
build their own maps. Each case then gets its spin's series in theta (the sums over the
spin's Chebyshev polynomials), and :func:`.stick_slip_map.integrate` iterates it from
the case's first breakaway: the case integrates its first breakaway and its last
cycles only.

Because the bands and nodes are fixed and the node problems are built from the group's
spin-normalised data, a case's map, and so its t_cr, are the same alone
(:func:`band_map`) or in any batch (:func:`shared_maps`); a process keeps the grids it
built (:data:`_MEMO_SIZE`), so the cases of one band pay for its grid once.

This is the envelope-following idea of :mod:`.stick_slip_map` (Petzold 1981) with the
spin as a second interpolation variable; the opening itself is never interpolated
(t_cr jumps by a stick phase where the last slip window just misses theta_cr), each
case locates it by integration.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from ...errors import InputError
from ..dynamics import nutation_angle_of_state
from ..friction_sets import moment_scale
from ..layout import P_A, P_C, P_THETA_CR
from .contract import Controls, Problem
from .stick_slip import at_zero_width, run_cycles
from .stick_slip_map import (
    LAST_CYCLES,
    MAP_TOL,
    MAX_NODES,
    THETA_LOW,
    CycleMap,
    RunCycles,
    _lobatto,
    _Nodes,
    abscissa,
    applies,
    coefficient_matrix,
    cycles_ahead,
    node_thetas,
)

__all__ = [
    "BAND_RATIO",
    "KAPPA_END",
    "MAX_SPIN_NODES",
    "MAX_SPLITS",
    "BAND_MIN_CYCLES",
    "band_edges",
    "band_map",
    "shared_maps",
]

#: Stick ratio kappa down to which a band's map reaches (theta_lo of
#: :meth:`_Grid.interval`): below it a cycle from B(theta) may no longer stick again
#: within two revolutions (a node that fails splits its band); the case integrates its
#: cycles below it itself. The largest value with no node failure on the rig
#: (``docs/benchmarks.md``).
KAPPA_END = 0.38
#: Ratio of the highest to the lowest spin of one band. The bands are a fixed lattice,
#: [BAND_RATIO^k, BAND_RATIO^(k+1)) rad/s, so which band a case is in, and so its map,
#: depend on its own spin alone, never on the other cases of a batch.
BAND_RATIO = 1.15
#: Times a band whose grid fails (a node cycle that does not stick again, cycles that
#: differ in kind, no convergence) is halved in log(omega_p) before its cases keep their
#: own one-spin maps.
MAX_SPLITS = 2
#: Fewest cycles (:meth:`_Grid.cycles_ahead`) through the map at a band's highest spin
#: for which the band's grid is built: the case integrates its last
#: :data:`~.stick_slip_map.LAST_CYCLES` cycles anyway, so with fewer left the grid costs
#: more than it saves.
BAND_MIN_CYCLES = 4.0
#: Most spin nodes of a band (Chebyshev-Lobatto levels 5, 9, 17).
MAX_SPIN_NODES = 17
#: Band grids kept per process (least recently used dropped first). A grid is a function
#: of its group and band alone, so dropping one costs time, never bits.
_MEMO_SIZE = 256
_MEMO: OrderedDict[tuple, tuple] = OrderedDict()


def band_edges(wp: float) -> tuple[float, float]:
    """The fixed band [lo, hi) of :data:`BAND_RATIO` powers [rad/s] that holds spin |wp|."""
    wp = abs(wp)
    k = math.floor(math.log(wp) / math.log(BAND_RATIO))
    while BAND_RATIO**k > wp:  # log rounding at an edge
        k -= 1
    while BAND_RATIO ** (k + 1) <= wp:
        k += 1
    return BAND_RATIO**k, BAND_RATIO ** (k + 1)


def shared_maps(
    problems: Sequence[Problem], controls: Sequence[Controls]
) -> tuple[list[CycleMap | None], np.ndarray]:
    """:func:`band_map` of each problem; the counters of the band grids built here.

    Returns
    -------
    maps : list of CycleMap or None
        Per problem, its spin's map for :func:`.stick_slip.integrate`'s `shared`.
    counts : ndarray of int64, shape (4,)
        Right-hand sides, Jacobians, steps and rejected steps of the node cycles this
        call integrated (a grid built earlier in this process costs nothing again).
    """
    counts = np.zeros(4, dtype=np.int64)
    maps = [band_map(p, c, counts) for p, c in zip(problems, controls, strict=True)]
    return maps, counts


def band_map(
    problem: Problem, controls: Controls, counts: np.ndarray | None = None
) -> CycleMap | None:
    """The return map of `problem` (set-valued, constant spin, t_cr only) interpolated
    from the grid of node cycles of its spin's fixed band (:func:`band_edges`), shared by
    every case whose parameters differ in the spin alone.

    The grid's node problems are built from the group's spin-normalised data
    (:func:`_group`), so the map, and the case's t_cr, are functions of the case alone.
    Where the band's grid fails it is halved (at most :data:`MAX_SPLITS` times); None
    where the case is outside the map's scope, fewer than :data:`BAND_MIN_CYCLES` cycles are
    left or no grid holds (the case then builds its own one-spin map). `counts`
    (right-hand sides, Jacobians, steps, rejected steps) gains the node cycles integrated.
    """
    try:
        problem = at_zero_width(problem)
    except InputError:  # the case's own run says why
        return None
    if not applies(problem, controls):
        return None
    group = _group(problem, controls)
    wp = abs(float(problem.y0[7]))
    w_lo, w_hi = band_edges(wp)
    for _ in range(MAX_SPLITS + 1):
        kind, built = _band(group, w_lo, w_hi, counts)
        if kind == "built":
            return _series_at(built, wp, w_lo, w_hi, float(problem.p[P_THETA_CR]))
        if kind == "none":
            return None
        mid = math.sqrt(w_lo * w_hi)
        w_lo, w_hi = (w_lo, mid) if wp < mid else (mid, w_hi)
    return None


class _Group(NamedTuple):
    """What cases that share a map have in common, spin-normalised: the key and the
    data the node problems are built from."""

    key: tuple
    p: np.ndarray
    attitude: np.ndarray  #: y0[:4]
    rates: np.ndarray  #: y0[4:] / omega_p, rounded to 12 digits
    scale: np.ndarray  #: scale with its rate components / omega_p, rounded to 12 digits
    sign: float  #: sign of omega_p
    controls: Controls  #: with h0, h_max times omega_p (rounded to 12 digits)


def _group(problem: Problem, controls: Controls) -> _Group:
    """The :class:`_Group` of `problem`: everything but the spin, with the rates, their
    error scales and the steps normalised by it (rounded to 12 digits, so that the
    spins' own rounding does not split a group; the node problems use the rounded
    values, so a grid never depends on which case built it)."""
    wp = abs(float(problem.y0[7]))
    norm = np.r_[1.0, 1.0, 1.0, 1.0, wp, wp, wp, wp]
    rates = np.round(problem.y0[4:] / problem.y0[7], 12)
    scale = np.round(problem.scale / norm, 12)
    sign = math.copysign(1.0, problem.y0[7])
    ctl = controls._replace(h0=round(controls.h0 * wp, 12), h_max=round(controls.h_max * wp, 12))
    key = (
        problem.p.tobytes(), problem.y0[:4].tobytes(), rates.tobytes(), sign, scale.tobytes(),
        float(problem.t0), ctl.t_max, ctl.rtol, ctl.atol, ctl.max_steps, ctl.event_tol,
        ctl.h0, ctl.h_max,
    )  # fmt: skip
    return _Group(key, problem.p, problem.y0[:4].copy(), rates, scale, sign, ctl)


def _band(group: _Group, w_lo: float, w_hi: float, counts: np.ndarray | None) -> tuple:
    """("built", grid) of the band [w_lo, w_hi) of `group`, ("none", None) where no grid
    pays, ("split", None) where its grid failed; memoised per process."""
    key = (group.key, w_lo, w_hi)
    if key in _MEMO:
        _MEMO.move_to_end(key)
        return _MEMO[key]
    grid = _Grid(group, run_cycles())
    try:
        pays = grid.cycles_ahead(w_lo, w_hi) >= BAND_MIN_CYCLES
        built = grid.build(w_lo, w_hi) if pays else None
    except (RuntimeError, ArithmeticError):  # a node that fails: split the band
        pays, built = True, None
    if counts is not None:
        counts += grid.counts()
    out = ("none", None) if not pays else ("split", None) if built is None else ("built", built)
    _MEMO[key] = out
    if len(_MEMO) > _MEMO_SIZE:
        _MEMO.popitem(last=False)
    return out


def _series_at(built: tuple, wp: float, w_lo: float, w_hi: float, theta_cr: float) -> CycleMap:
    """The band's grid summed over the Chebyshev polynomials of log(omega_p) at `wp`."""
    lo, hi, theta_lo, (c_logd, c_time, c_phi), k_step = built
    # the opening lies below a map that ends above theta_cr: the iteration may stop one
    # cycle before its end, not LAST_CYCLES
    last = 1 if theta_lo > theta_cr else LAST_CYCLES
    x = (2.0 * math.log(wp) - math.log(w_lo) - math.log(w_hi)) / math.log(w_hi / w_lo)
    t_w = np.cos(np.arange(c_logd.shape[1]) * math.acos(min(1.0, max(-1.0, x))))
    return CycleMap(
        lo, hi, c_logd @ t_w, (c_time @ t_w) * (math.pi / wp), c_phi @ t_w, k_step, theta_lo,
        last,
    )  # fmt: skip


class _Grid:
    """Node cycles of one group on a (theta, spin) grid, each integrated once."""

    def __init__(self, group: _Group, run: RunCycles) -> None:
        self.group, self.run = group, run
        self.theta0 = nutation_angle_of_state(
            np.r_[group.attitude, group.rates * group.sign], group.p
        )
        self.nodes: dict[float, _Nodes] = {}

    def interval(self, w_hi: float) -> tuple[float, float, float]:
        """(lo, hi) of :func:`abscissa` and theta_lo [rad] of a band up to spin `w_hi`:
        from the initial nutation down to theta_cr (THETA_LOW where theta_cr is not in
        (0, 90 deg)) or to where the stick ratio kappa = omega_p^2 |C - A| sin(2 theta)
        / (2 M) reaches :data:`KAPPA_END` at `w_hi` (theta above 45 deg, where kappa
        peaks), whichever is higher."""
        p = self.group.p
        theta_cr = float(p[P_THETA_CR])
        theta_lo = theta_cr if 0.0 < theta_cr < 0.5 * math.pi else THETA_LOW
        s = 2.0 * KAPPA_END * moment_scale(p) / (w_hi * w_hi * abs(p[P_C] - p[P_A]))
        if s < 1.0:
            theta_lo = max(theta_lo, 0.5 * (math.pi - math.asin(s)))
        return abscissa(theta_lo), abscissa(self.theta0), theta_lo

    def at_spin(self, wp: float) -> _Nodes:
        """The node runs at spin `wp` [rad/s] (its sign that of the group), from the
        group's spin-normalised data."""
        if wp not in self.nodes:
            g = self.group
            rates = np.r_[1.0, 1.0, 1.0, 1.0, wp, wp, wp, wp]
            y0 = np.r_[g.attitude, g.rates * (g.sign * wp)]
            problem = Problem(y0, g.p, g.scale * rates)
            ctl = g.controls._replace(h0=g.controls.h0 / wp, h_max=g.controls.h_max / wp)
            self.nodes[wp] = _Nodes(problem, ctl, self.run)
        return self.nodes[wp]

    def cycles_ahead(self, w_lo: float, w_hi: float) -> float:
        """Cycles a case at the band's highest spin `w_hi` [rad/s] would go through the
        map (:func:`~.stick_slip_map.cycles_ahead` from the cycle at the initial nutation,
        the grid's first node, kept for :meth:`build`); 0 where that cycle fails."""
        lo, hi, theta_lo = self.interval(w_hi)
        if not self.theta0 > theta_lo:
            return 0.0
        theta = node_thetas(lo, hi, 2)[:1]
        row = self.at_spin(float(_node_spins(w_lo, w_hi, 2)[0])).at(theta)
        if row is None:
            return 0.0
        return cycles_ahead(theta_lo, float(theta[0]), math.exp(row[0, 0]))

    def counts(self) -> np.ndarray:
        return sum((n.counts for n in self.nodes.values()), np.zeros(4, dtype=np.int64))

    def build(self, w_lo: float, w_hi: float):
        """(lo, hi, theta_lo) of :meth:`interval`, the coefficient matrices (theta rows,
        spin columns) of log(-D), T / half period and Phi, and k'; None where a node
        fails, the kinds differ or the grid does not converge by
        :data:`~.stick_slip_map.MAX_NODES` x :data:`MAX_SPIN_NODES`."""
        lo, hi, theta_lo = self.interval(w_hi)
        if not (self.theta0 > theta_lo and w_hi > w_lo):
            return None
        tol = MAP_TOL * self.group.controls.rtol
        n_t, n_w = 9, 5
        while True:
            thetas, spins = node_thetas(lo, hi, n_t), _node_spins(w_lo, w_hi, n_w)
            values = np.empty((n_t, n_w, 4))
            for j, w in enumerate(spins):
                rows = self.at_spin(float(w)).at(thetas)
                if rows is None:
                    return None
                values[:, j, :] = rows
            if np.ptp(values[..., 3]) != 0.0 or np.ptp(np.round(values[..., 1])) != 0.0:
                return None
            m_t, m_w = coefficient_matrix(n_t), coefficient_matrix(n_w)
            c = [m_t @ values[..., q] @ m_w.T for q in range(3)]
            err_t = max(np.abs(c[q][-2:, :]).sum(axis=1).max() for q in (0, 1))
            err_w = max(np.abs(c[q][:, -2:]).sum(axis=0).max() for q in (0, 1))
            if err_t <= tol and err_w <= tol:
                return lo, hi, theta_lo, c, int(values[0, 0, 3])
            grow_t = err_t > tol and n_t < MAX_NODES
            grow_w = err_w > tol and n_w < MAX_SPIN_NODES
            if not (grow_t or grow_w):
                return None
            n_t, n_w = (2 * n_t - 1 if grow_t else n_t), (2 * n_w - 1 if grow_w else n_w)


def _node_spins(w_lo: float, w_hi: float, n: int) -> np.ndarray:
    """Spins [rad/s] of `n` Chebyshev-Lobatto nodes of log(omega_p), from `w_hi`."""
    return np.exp(math.log(w_lo) + 0.5 * math.log(w_hi / w_lo) * (1.0 + _lobatto(n)))
