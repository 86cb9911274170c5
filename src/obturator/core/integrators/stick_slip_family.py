"""One return map for many spins: the cycle map of :mod:`.stick_slip_map` in (theta, omega_p).

A sweep over the spin rate gives the set-valued solver hundreds of cases that differ in
the spin alone. Each would build its own return map from 17-33 integrated cycles
(:mod:`.stick_slip_map`), which at 40-70 rad/s is most of its cost, and below about
60 predicted cycles (70-218 rad/s on the rig) it builds none and integrates every
cycle. Yet the map's three functions D, T, Phi of theta are smooth in the spin too:
at constant spin the cycle from the breakaway state B(theta) depends on theta and
omega_p alone (the other parameters equal), D ~ kappa^3 with kappa ~ omega_p^2, so
log(-D) is close to linear in log(omega_p). So the cases are grouped (equal parameters,
initial attitude, tolerances, and steps proportional to the spin period) and each
group's spins split into bands no wider than :data:`BAND_RATIO`; per band the cycles are
integrated on a tensor grid of Chebyshev-Lobatto nodes, in :func:`abscissa` of theta
(from the initial nutation down to theta_cr, or to where the stick ratio reaches
:data:`KAPPA_END`: :meth:`_Grid.interval`) and in log(omega_p), and interpolated. The
error estimate is that of the one-spin map in each direction (the last two Chebyshev
coefficients, summed over the other direction, which bounds them at every node of it)
against :data:`~.stick_slip_map.MAP_TOL` times rtol; the grid grows (nested levels,
9-17-33 in theta, 5-9-17 in the spin) until both hold. A band whose nodes' cycles differ
in kind, or that does not converge, is split in two while each half holds
:data:`MIN_SPINS` spins; else its spins build their own maps as before. Each case then
gets its spin's series in theta (the sums over the spin's Chebyshev polynomials), and
:func:`.stick_slip_map.integrate` iterates it from the case's first breakaway: the case
integrates its first breakaway and its last cycles only.

This is the envelope-following idea of :mod:`.stick_slip_map` (Petzold 1981) with the
spin as a second interpolation variable; the opening itself is never interpolated
(t_cr jumps by a stick phase where the last slip window just misses theta_cr), each
case locates it by integration.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

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
    "BAND_MIN_CYCLES",
    "MIN_SPINS",
    "shared_maps",
]

#: Stick ratio kappa down to which a band's map reaches (theta_lo of
#: :meth:`_Grid.interval`): on the rig (Table 1, mu_s 0.5473) a cycle from B(theta)
#: no longer sticks again within two revolutions from kappa ~ 0.52 on (node cycles
#: failed at 70.9 deg from 80.7 rad/s, at 78.6 deg from 93.8 rad/s); below it the case
#: integrates its cycles itself. At 0.45 and 0.48 nodes still failed (bands split and
#: rebuilt: the set-valued band of a 40-1000 rad/s sweep took 3.8 and 4.6 s in one
#: process); 0.30-0.42 took the same 2.5-2.8 s; 0.38 is the largest with no failure.
KAPPA_END = 0.38
#: Widest ratio of the highest to the lowest spin of one band: the set-valued band of a
#: 10,000-point 40-1000 rad/s rig sweep took 2.4-2.5 s in one process at 1.15, 2.6-2.7 s
#: at 1.08, 1.1, 1.25 and 1.4 (wider bands need more spin nodes, narrower more bands).
BAND_RATIO = 1.15
#: Fewest spins of a band that share its map: a band's grid costs 45-561 node cycles
#: (0.2-0.3 ms each), the map saves a case 5-40 cycles (the one-spin map's nodes, or its
#: integrated cycles).
MIN_SPINS = 12
#: Fewest cycles (:meth:`_Grid.cycles_ahead`) through the map at a band's highest spin
#: for which the band's grid is built: the case integrates the last one to
#: :data:`~.stick_slip_map.LAST_CYCLES` of them anyway. On the rig (mu_s 0.5473) from
#: ~125 rad/s up fewer are left above kappa = :data:`KAPPA_END` (120 rad/s: 5.1, 140:
#: 2.1, 160: 0.6), where the grids made the 150-218 rad/s points 8 % slower.
BAND_MIN_CYCLES = 4.0
#: Most spin nodes of a band (Chebyshev-Lobatto levels 5, 9, 17).
MAX_SPIN_NODES = 17


def shared_maps(
    problems: Sequence[Problem], controls: Sequence[Controls]
) -> tuple[list[CycleMap | None], np.ndarray]:
    """Return maps shared by the `problems` that differ in spin alone.

    Parameters
    ----------
    problems, controls : sequence of Problem, Controls
        The cases as :func:`.stick_slip.integrate` takes them, with the controls of each.

    Returns
    -------
    maps : list of CycleMap or None
        Per problem, its spin's map, for :func:`.stick_slip.integrate`'s `shared`; None
        where it has none (outside the solver's scope or the map's, no group, a band of
        fewer than :data:`MIN_SPINS` spins, or no converged map).
    counts : ndarray of int64, shape (4,)
        Right-hand sides, Jacobians, steps and rejected steps of all node cycles.
    """
    maps: list[CycleMap | None] = [None] * len(problems)
    counts = np.zeros(4, dtype=np.int64)
    groups: dict[tuple, list[int]] = {}
    checked = []
    for i, (problem, ctl) in enumerate(zip(problems, controls, strict=True)):
        try:
            problem = at_zero_width(problem)
        except InputError:  # the case's own run says why
            problem = None
        checked.append(problem)
        if problem is not None and applies(problem, ctl):
            groups.setdefault(_group_key(problem, ctl), []).append(i)
    run = run_cycles()
    for members in groups.values():
        members.sort(key=lambda i: abs(float(problems[i].y0[7])))
        for band in _bands([abs(float(problems[i].y0[7])) for i in members]):
            idx = [members[b] for b in band]
            _fill_band(idx, checked, controls, run, maps, counts)
    return maps, counts


def _group_key(problem: Problem, controls: Controls) -> tuple:
    """What must be equal for cases to share a map: everything but the spin, with the
    steps and error scales of the rates proportional to it."""
    wp = abs(float(problem.y0[7]))
    rates = problem.y0[4:] / problem.y0[7]
    return (
        problem.p.tobytes(),
        problem.y0[:4].tobytes(),
        np.round(rates, 12).tobytes(),
        math.copysign(1.0, problem.y0[7]),
        np.round(problem.scale / np.r_[1.0, 1.0, 1.0, 1.0, wp, wp, wp, wp], 12).tobytes(),
        float(problem.t0),
        controls.t_max, controls.rtol, controls.atol, controls.max_steps, controls.event_tol,
        round(controls.h0 * wp, 12), round(controls.h_max * wp, 12),
    )  # fmt: skip


def _bands(spins: list[float]) -> list[list[int]]:
    """Indices of the sorted `spins` in runs no wider than :data:`BAND_RATIO`, each at
    least :data:`MIN_SPINS` long (shorter runs are left out)."""
    bands, start = [], 0
    for i in range(1, len(spins) + 1):
        if i == len(spins) or spins[i] > BAND_RATIO * spins[start]:
            if i - start >= MIN_SPINS:
                bands.append(list(range(start, i)))
            start = i
    return bands


def _fill_band(idx, problems, controls, run, maps, counts) -> None:
    """Maps for the problems `idx` (sorted by spin) from one grid, or from the grids of
    its halves where that fails and they are long enough."""
    grid = _Grid(problems[idx[0]], controls[idx[0]], run)
    w_lo = abs(float(problems[idx[0]].y0[7]))
    w_hi = abs(float(problems[idx[-1]].y0[7]))
    try:
        pays = grid.cycles_ahead(w_lo, w_hi) >= BAND_MIN_CYCLES
        built = grid.build(w_lo, w_hi) if pays else None
    except (RuntimeError, ArithmeticError):  # a node that fails: its cases run alone
        pays, built = False, None
    counts += grid.counts()
    if not pays:
        return
    if built is None:
        if len(idx) >= 2 * MIN_SPINS:
            half = len(idx) // 2
            _fill_band(idx[:half], problems, controls, run, maps, counts)
            _fill_band(idx[half:], problems, controls, run, maps, counts)
        return
    lo, hi, theta_lo, (c_logd, c_time, c_phi), k_step = built
    # the opening lies below a map that ends above theta_cr: the iteration may stop one
    # cycle before its end, not LAST_CYCLES
    last = 1 if theta_lo > problems[idx[0]].p[P_THETA_CR] else LAST_CYCLES
    for i in idx:
        wp = abs(float(problems[i].y0[7]))
        x = (2.0 * math.log(wp) - math.log(w_lo) - math.log(w_hi)) / math.log(w_hi / w_lo)
        t_w = np.cos(np.arange(c_logd.shape[1]) * math.acos(min(1.0, max(-1.0, x))))
        maps[i] = CycleMap(
            lo, hi, c_logd @ t_w, (c_time @ t_w) * (math.pi / wp), c_phi @ t_w, k_step,
            theta_lo, last,
        )  # fmt: skip


class _Grid:
    """Node cycles of one group on a (theta, spin) grid, each integrated once."""

    def __init__(self, problem: Problem, controls: Controls, run: RunCycles) -> None:
        self.problem, self.controls, self.run = problem, controls, run
        self.wp = float(problem.y0[7])
        self.theta0 = nutation_angle_of_state(problem.y0, problem.p)
        self.nodes: dict[float, _Nodes] = {}

    def interval(self, w_hi: float) -> tuple[float, float, float]:
        """(lo, hi) of :func:`abscissa` and theta_lo [rad] of a band up to spin `w_hi`:
        from the initial nutation down to theta_cr (THETA_LOW where theta_cr is not in
        (0, 90 deg)) or to where the stick ratio kappa = omega_p^2 |C - A| sin(2 theta)
        / (2 M) reaches :data:`KAPPA_END` at `w_hi` (theta above 45 deg, where kappa
        peaks), whichever is higher."""
        p = self.problem.p
        theta_cr = float(p[P_THETA_CR])
        theta_lo = theta_cr if 0.0 < theta_cr < 0.5 * math.pi else THETA_LOW
        s = 2.0 * KAPPA_END * moment_scale(p) / (w_hi * w_hi * abs(p[P_C] - p[P_A]))
        if s < 1.0:
            theta_lo = max(theta_lo, 0.5 * (math.pi - math.asin(s)))
        return abscissa(theta_lo), abscissa(self.theta0), theta_lo

    def at_spin(self, wp: float) -> _Nodes:
        """The node runs at spin `wp` [rad/s] (its sign that of the group)."""
        if wp not in self.nodes:
            r = wp / abs(self.wp)
            y0 = self.problem.y0 * np.r_[1.0, 1.0, 1.0, 1.0, r, r, r, r]
            scale = self.problem.scale * np.r_[1.0, 1.0, 1.0, 1.0, r, r, r, r]
            ctl = self.controls._replace(h0=self.controls.h0 / r, h_max=self.controls.h_max / r)
            self.nodes[wp] = _Nodes(self.problem._replace(y0=y0, scale=scale), ctl, self.run)
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
        tol = MAP_TOL * self.controls.rtol
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
