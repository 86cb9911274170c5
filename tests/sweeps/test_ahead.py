"""Points packed by a helper process while the integrators load (obturator.sweeps.ahead).

The reference is the packing done where the points are integrated
(:func:`obturator.sweeps.points.pack_rows` in the worker), which the helper must
reproduce exactly, and a sweep without the helper, which the sweep with it must
reproduce bit for bit.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

import obturator.sweeps.ahead as ahead
import obturator.sweeps.points as points
from obturator.runs import Runner
from obturator.solve import SolverOptions
from obturator.status import Status
from obturator.sweeps import SweepSpec, execute_sweep
from obturator.sweeps.points import pack_rows

FAST = SolverOptions(rtol=1e-6, atol=1e-8)
SPEC = SweepSpec(
    "spin-rig",
    {"spin_rate": [150.0, 300.0, 450.0, 600.0], "theta0_deg": [80.0, 87.25, 89.0]},
    {"mu_s": 0.5473},
    options=FAST,
)
NAMES = ("spin_rate", "theta0_deg")


def _rows_of(idx: np.ndarray) -> np.ndarray:
    """Rows of 12 points, a third with theta0 = 95 deg: not a case (INVALID_INPUT)."""
    w, th = np.unravel_index(idx, (4, 3))
    return np.column_stack(
        [np.array([150.0, 300.0, 450.0, 600.0])[w], np.array([80.0, 87.25, 95.0])[th]]
    )


def test_helper_packs_what_the_worker_would():
    """Given time, the helper packs every point exactly as the worker would (invalid
    points marked), in any order asked; points it was not given are not claimed."""
    import time

    index = np.array([11, 3, 7, 0, 5, 2, 9, 1, 4, 6, 8, 10])
    done = ahead.pack_ahead(SPEC, NAMES, _rows_of, index, lambda: time.sleep(1.0))
    assert len(done) == index.size
    for idx in (index, index[::-1], index[:1], np.array([2, 5, 8, 11])):
        got = done.take(idx)
        want = pack_rows(SPEC, NAMES, _rows_of(idx))
        for a, b in zip(got, want, strict=True):
            np.testing.assert_array_equal(a, b)
    assert done.take(np.arange(12)).valid.tolist() == [True, True, False] * 4  # 95 deg
    assert done.take(np.array([12])) is None
    assert done.take(np.array([0, 12])) is None


def test_helper_stopped_early_gives_finished_batches_only(monkeypatch):
    monkeypatch.setattr(ahead, "_BATCH", 1)
    index = np.arange(12)
    done = ahead.pack_ahead(SPEC, NAMES, _rows_of, index, lambda: None)
    n = len(done)
    assert 0 <= n <= 12
    if n:
        got = done.take(index[:n])
        for a, b in zip(got, pack_rows(SPEC, NAMES, _rows_of(index[:n])), strict=True):
            np.testing.assert_array_equal(a, b)
    assert n == 12 or done.take(index) is None


def test_failing_helper_leaves_the_packing_to_the_workers(monkeypatch):
    def broken(*args, **kw):
        raise RuntimeError("boom")

    monkeypatch.setattr(ahead, "pack_rows", broken)
    done = ahead.pack_ahead(SPEC, NAMES, _rows_of, np.arange(12), lambda: None)
    assert len(done) == 0 and done.take(np.arange(3)) is None


def test_sweep_with_helper_is_identical_to_sweep_without(monkeypatch):
    """A pool sweep in a process that has not loaded the integrators packs ahead: the
    workers integrate the helper's arrays (packing in a worker would fail here) and the
    dataset is identical to the in-process sweep's."""
    import time

    import obturator.sweeps.job as executors
    from obturator.runs import mp_context

    if mp_context().get_start_method() != "fork":  # pragma: no cover - test order only
        # packing ahead needs fork, which the pools use only while this process runs no
        # other thread; an earlier test's Dask client can leave threads behind under
        # pytest-xdist (conftest.py runs this module first in a serial session)
        pytest.skip("threads left by another test: the pools spawn, nothing packs ahead")
    one = execute_sweep(SPEC, runner=Runner(workers=1)).dataset
    assert np.all(one["status"].values == Status.OPENED)
    used = []
    real_pack, real_warm = ahead.pack_ahead, executors.warm

    def spy(*args, **kw):
        out = real_pack(*args, **kw)
        used.append(len(out))
        return out

    def slow_warm(*args, **kw):  # a fresh process's load takes ~0.3 s
        time.sleep(1.0)
        real_warm(*args, **kw)

    def no_packing(*args, **kw):
        raise AssertionError("a worker packed points the helper had packed")

    monkeypatch.setattr(points, "_WARM", set())  # as in a fresh process
    monkeypatch.setattr(executors, "pack_ahead", spy)
    monkeypatch.setattr(executors, "warm", slow_warm)
    monkeypatch.setattr(executors, "default_workers", lambda: 2)
    monkeypatch.setattr(points, "pack_rows", no_packing)
    run = execute_sweep(SPEC, runner=Runner(workers=2, chunk_size=2))
    assert run.workers == 2 and used == [12]
    xr.testing.assert_identical(one, run.dataset)


def test_warm_process_does_not_pack_ahead(monkeypatch):
    """Integrators already loaded: nothing to overlap, no helper."""
    points.warm(SPEC.options)
    called = []
    monkeypatch.setattr("obturator.sweeps.job.pack_ahead", lambda *a, **k: called.append(1))
    run = execute_sweep(SPEC, runner=Runner(workers=2, chunk_size=2))
    assert run.workers == 2 and not called


def test_gc_frozen_unfreezes_even_on_error():
    """Objects are frozen only while loading and forking; this process collects as
    before afterwards, also when the body raises."""
    import gc

    from obturator.runs import gc_frozen

    before = gc.get_freeze_count()
    with gc_frozen():
        assert gc.get_freeze_count() > before
    assert gc.get_freeze_count() == before
    with pytest.raises(KeyboardInterrupt), gc_frozen():
        raise KeyboardInterrupt
    assert gc.get_freeze_count() == before
