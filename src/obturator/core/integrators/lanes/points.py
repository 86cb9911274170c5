"""What both lane drivers take (the points) and give back (one outcome per point).

The drivers (:mod:`.dop853`, :mod:`.radau`) load points into lanes as lanes come
free and write each point's outcome when its lane ends; these are the two ends.
Lane state is flat and component-major (``x[i * LANES + lane]``, :mod:`.simd`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from ...layout import N_STATE
from .simd import DRIVER_PHASE, LANES, NO_REFCOUNT, REFCOUNT

__all__ = [
    "Points",
    "Outcome",
    "new_outcome",
    "finish",
    "pack_lanes",
    "copy_lane",
    "lane_vector",
]


class Points(NamedTuple):
    """The points to integrate, one row each (the drivers' arguments)."""

    y0: np.ndarray  #: (n, 8) start states
    t0: np.ndarray  #: (n,) start times [s]
    p: np.ndarray  #: (n, N_PARAM) packed parameters
    scale: np.ndarray  #: (n, 8) error-weight scales
    t_max: np.ndarray  #: (n,) end times [s]
    h0: np.ndarray  #: (n,) first steps [s]
    h_max: np.ndarray  #: (n,) largest steps [s]
    max_steps: np.ndarray  #: (n,) accepted-step limits
    hand_back: np.ndarray  #: (n,) bool: Radau IIA stops once sliding has resumed
    slip_floor: np.ndarray  #: (n,) DOP853: slip speed below which the point ends [rad/s] (0: none)
    order: np.ndarray  #: (n,) the order in which points enter the lanes


class Outcome(NamedTuple):
    """Where each point's run ended."""

    status: np.ndarray  #: (n,) int8 :class:`~obturator.status.Status` codes
    t_event: np.ndarray  #: (n,) opening time [s] (NaN if none)
    t_end: np.ndarray  #: (n,) time of the last state [s]
    y_end: np.ndarray  #: (n, 8) last state (the event state if opened)
    counts: np.ndarray  #: (3, n) int64: right-hand sides, accepted and rejected steps


@njit(cache=True, fastmath=False, error_model="numpy", **REFCOUNT)
def new_outcome(n: int) -> Outcome:
    """An :class:`Outcome` for `n` points (status 0, t_event NaN, the rest zeros)."""
    return Outcome(
        np.zeros(n, dtype=np.int8),
        np.full(n, math.nan),
        np.zeros(n),
        np.zeros((n, N_STATE)),
        np.zeros((3, n), dtype=np.int64),
    )


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def finish(out, j, status, t_event, y, t, idx, cnt) -> bool:
    """Write the outcome of lane j (its state `y`, time `t`, counters rows 0-2 of `cnt`)
    to its point ``idx[j]``; returns False (the lane is free)."""
    q = idx[j]
    out.status[q] = status
    out.t_event[q] = t_event
    out.t_end[q] = t[j]
    for i in range(N_STATE):
        out.y_end[q, i] = y[i * LANES + j]
    for c in range(3):
        out.counts[c, q] = cnt[c, j]
    return False


@njit(**DRIVER_PHASE)
def pack_lanes(ln, nl, move_lane) -> int:
    """Move the live lanes (``ln.live``) of 0..nl-1 to the front, ``move_lane(ln, a, b)``
    copying lane a into lane b; returns how many there are."""
    j = 0
    while j < nl:
        if ln.live[j]:
            j += 1
            continue
        if nl - 1 > j:
            move_lane(ln, nl - 1, j)
        nl -= 1
    return nl


@njit(cache=True, inline="always", **NO_REFCOUNT)
def copy_lane(x, a, b) -> None:
    """Lane a of the flat lane array `x` (every component) into lane b."""
    for i in range(x.shape[0] // LANES):
        x[i * LANES + b] = x[i * LANES + a]


@njit(cache=True, **NO_REFCOUNT, fastmath=False, error_model="numpy")
def lane_vector(x, j, k, out) -> None:
    """Copy lane j of the k-th vector of `x` (offset ``k * N_STATE * LANES``) into out."""
    for i in range(N_STATE):
        out[i] = x[k * N_STATE * LANES + i * LANES + j]
