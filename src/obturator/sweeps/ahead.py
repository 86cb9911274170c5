"""Points packed by a helper process while this process loads the integrators.

Before a process pool's workers are forked warm, this process loads the compiled
integrators once (:func:`obturator.sweeps.points.warm`), mostly numba's first-use
set-up, while the other cores idle. Packing points (building and validating each
point's case and the integrators' inputs, :func:`obturator.sweeps.points.pack_rows`:
Python, a noticeable share of a rig sweep's work; ``docs/benchmarks.md``) needs no
compiled code, so a helper forked first packs the study's first
points, chunk order, into shared memory meanwhile; once the integrators are loaded the
helper is stopped and the chunks it has packed go to the workers packed, so that they
only integrate them. The same Python builds the same arrays, so results are the same
bit for bit with and without the helper.

Only with ``fork`` (Linux, see :func:`~obturator.runs.mp_context`), a spare
core for the helper, and integrators not yet loaded in this process (a second sweep in
one session has nothing to overlap).
"""

from __future__ import annotations

import math
import mmap
import multiprocessing
import os
from collections.abc import Callable

import numpy as np

from ..solve import PackedPoints
from ..solve.many import PACKED_WIDTHS
from .points import pack_rows
from .spec import SweepSpec

__all__ = ["AHEAD_POINTS", "PackedAhead", "pack_ahead"]

#: Most points the helper packs (its shared memory: ~420 bytes per point). A fresh
#: process loads the integrators in ~0.3 s, time for ~10,000 points.
AHEAD_POINTS = 32_768
#: Points the helper packs between two updates of its progress counter.
_BATCH = 256
# one row per point: valid, y0, p, scale, t_max, h0, h_max, spin
_WIDTHS = PACKED_WIDTHS
_COLS = sum(_WIDTHS)


def _to_rows(packed: PackedPoints, out: np.ndarray) -> None:
    col = 0
    for a, w in zip(packed, _WIDTHS, strict=True):
        out[:, col : col + w] = a.reshape(len(out), w)
        col += w


def _from_rows(rows: np.ndarray) -> PackedPoints:
    parts = []
    col = 0
    for w in _WIDTHS:
        block = rows[:, col : col + w]
        parts.append(block.copy() if w > 1 else block[:, 0].copy())
        col += w
    parts[0] = parts[0] != 0.0
    return PackedPoints(*parts)


class PackedAhead:
    """The points a helper packed ahead: `index` (flat point indices) and `packed`."""

    def __init__(self, index: np.ndarray, packed: PackedPoints) -> None:
        order = np.argsort(index, kind="stable")
        self._sorted = index[order]
        self._order = order
        self.packed = packed

    def __len__(self) -> int:
        return self._sorted.size

    def take(self, idx: np.ndarray) -> PackedPoints | None:
        """The packed points `idx` (flat indices), or None unless all were packed."""
        if not self._sorted.size:
            return None
        k = np.searchsorted(self._sorted, idx)
        k_in = np.minimum(k, self._sorted.size - 1)
        if not np.all(self._sorted[k_in] == idx):
            return None
        return self.packed.take(self._order[k_in])


def _pack(
    shared: mmap.mmap,
    parent: int,
    spec: SweepSpec,
    names: tuple[str, ...],
    rows_of: Callable[[np.ndarray], np.ndarray],
    index: np.ndarray,
) -> None:
    """The helper: pack `index` batch by batch into `shared` (counter first, then rows)."""
    from ..runs.pools import die_with_parent

    die_with_parent(parent)
    buf = np.frombuffer(shared, dtype=np.float64)
    rows = buf[1:].reshape(-1, _COLS)
    try:
        for start in range(0, index.size, _BATCH):
            part = index[start : start + _BATCH]
            _to_rows(pack_rows(spec, names, rows_of(part)), rows[start : start + part.size])
            buf[0] = start + part.size  # after the rows: the parent reads only finished ones
    except BaseException:  # the workers pack what is missing; nothing to report
        os._exit(1)
    os._exit(0)  # no clean-up of the parent's state (atexit handlers, open stores)


def pack_ahead(
    spec: SweepSpec,
    names: tuple[str, ...],
    rows_of: Callable[[np.ndarray], np.ndarray],
    index: np.ndarray,
    load: Callable[[], None],
) -> PackedAhead:
    """Run `load` here while a forked helper packs the points `index` (flat indices,
    the order in which they will be computed; at most :data:`AHEAD_POINTS`).

    Parameters
    ----------
    spec : SweepSpec
        The study (its :meth:`~SweepSpec.build_case` and options).
    names : tuple of str
        Names of the varied parameters, in the order of the rows' columns.
    rows_of : callable
        Flat point indices -> rows of values (SI units, as :class:`SweepSpec`).
    index : ndarray of int
        Flat indices of the points to pack, first computed first.
    load : callable
        What this process does meanwhile (loading the compiled integrators).

    Returns
    -------
    PackedAhead
        The points the helper had packed when `load` returned (none if it failed:
        the workers then pack them, as without it).
    """
    index = np.asarray(index[:AHEAD_POINTS], dtype=np.int64)
    shared = mmap.mmap(-1, 8 * (1 + index.size * _COLS))
    ctx = multiprocessing.get_context("fork")
    helper = ctx.Process(
        target=_pack, args=(shared, os.getpid(), spec, names, rows_of, index),
        name="obturator-pack-ahead", daemon=True,
    )  # fmt: skip
    helper.start()
    try:
        load()
    finally:
        helper.kill()
        helper.join()
    buf = np.frombuffer(shared, dtype=np.float64)
    done = int(buf[0]) if math.isfinite(buf[0]) else 0
    out = PackedAhead(index[:done], _from_rows(buf[1:].reshape(-1, _COLS)[:done]))
    del buf
    shared.close()
    return out
