"""Interrupted studies lose nothing: SIGKILL / SIGTERM at random moments, then resume.

Each trial starts ``obturator sweep`` in a child process, kills it after a random
delay (seeded), and finally lets a run finish; the result must equal an
uninterrupted run bit for bit, with no point lost or duplicated, no leftover
partial-results, lock or temporary files, and no orphaned worker processes.
"""

from __future__ import annotations

import os
import random
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr


def _sweep_args(out: Path) -> list[str]:
    return [
        sys.executable, "-m", "obturator", "sweep", "--case", "spin-rig",
        "--spin-rate", "42:60:24", "--mu-s", "0.5473", "--workers", "2",
        "--chunk-size", "2", "--no-progress", "--out", str(out),
    ]  # fmt: skip


def _processes_mentioning(text: str) -> list[int]:
    pids = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit() and int(d.name) != os.getpid():
            try:
                if text.encode() in (d / "cmdline").read_bytes():
                    pids.append(int(d.name))
            except OSError:
                continue
    return pids


@pytest.mark.slow  # ~10 s per signal
@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="uses /proc and PDEATHSIG")
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_killed_sweep_resumes_bit_identical(tmp_path: Path, sig: signal.Signals) -> None:
    ref = tmp_path / "ref.nc"
    subprocess.run(_sweep_args(ref), check=True, capture_output=True, timeout=300)
    out = tmp_path / "killed.nc"
    rng = random.Random(20261122 + int(sig))
    kills = 0
    for _ in range(3):
        proc = subprocess.Popen(_sweep_args(out), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        time.sleep(rng.uniform(0.5, 1.5))  # the sweep takes ~2.5-3 s
        if proc.poll() is None:
            proc.send_signal(sig)
            kills += 1
        proc.communicate(timeout=60)
        # no worker outlives the main process (PR_SET_PDEATHSIG)
        deadline = time.time() + 5
        while _processes_mentioning(str(out)) and time.time() < deadline:
            time.sleep(0.1)
        assert _processes_mentioning(str(out)) == []
        if out.exists():  # the run finished before the signal: start again from scratch
            out.unlink()
    assert kills >= 1
    done = subprocess.run(_sweep_args(out), capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    with xr.open_dataset(ref) as a, xr.open_dataset(out) as b:
        np.testing.assert_array_equal(a["t_cr"].values, b["t_cr"].values)
        np.testing.assert_array_equal(a["status"].values, b["status"].values)
        assert int((b["status"].values == -128).sum()) == 0  # nothing missing
    left = sorted(p.name for p in tmp_path.iterdir())
    assert left == sorted(["ref.nc", "ref.csv", "killed.nc", "killed.csv"]), left


def test_dask_scheduler_dying_mid_sweep_keeps_work_and_resumes(tmp_path: Path) -> None:
    # A LocalCluster closed while a sweep runs on it: the sweep ends with one ClusterError
    # within seconds (never a hang), the finished chunks stay in the resume store, and
    # a local rerun completes to the uninterrupted result bit for bit.
    import threading

    from distributed import LocalCluster

    from obturator.errors import ClusterError
    from obturator.runs import Runner
    from obturator.sweeps import SweepSpec, execute_sweep, run_sweep, sidecar_path

    spec = SweepSpec("spin-rig", {"spin_rate": np.linspace(60.0, 120.0, 12)}, {"mu_s": 0.5473})
    store = tmp_path / "dask.nc"
    cluster = LocalCluster(
        n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None
    )
    side = sidecar_path(store)

    def close_after_first_chunk() -> None:  # mid-sweep, however fast the machine is
        deadline = time.time() + 60
        while time.time() < deadline:
            if side.exists() and len(side.read_text().splitlines()) >= 2:
                break
            time.sleep(0.05)
        cluster.close()

    closer = threading.Thread(target=close_after_first_chunk, daemon=True)
    closer.start()
    t0 = time.time()
    try:
        with pytest.raises(ClusterError):
            runner = Runner(scheduler=cluster.scheduler_address, chunk_size=1, store=store)
            execute_sweep(spec, runner)
    finally:
        closer.join(timeout=70)
        cluster.close()
    assert time.time() - t0 < 90
    assert side.exists()
    finished = len(side.read_text().splitlines()) - 1
    resumed = execute_sweep(spec, runner=Runner(workers=1, store=store))
    assert resumed.n_resumed == finished
    full = run_sweep(spec, runner=Runner(workers=1))
    # the chunks from the dask worker and the local ones agree to rounding: these spins
    # run set-valued, whose compiled code can round differently in a process that loads
    # it from the cache than in one that compiled it (numba's binding of inlined callee
    # copies, docs/stick_slip.md section 11: <= 5e-11 measured)
    np.testing.assert_allclose(resumed.dataset["t_cr"].values, full["t_cr"].values, rtol=1e-9)


@pytest.mark.slow  # waits out a 10 s timeout
def test_dask_scheduler_that_never_answers_is_one_line_in_bounded_time(tmp_path: Path) -> None:
    import socket

    from obturator.cli import main

    srv = socket.socket()
    srv.bind(("127.0.0.1", 0))
    srv.listen(8)  # accepts connections, never speaks
    port = srv.getsockname()[1]
    t0 = time.time()
    try:
        rc = main(
            ["sweep", "--spin-rate", "100:200:3", "--out", str(tmp_path / "x.nc"),
             "--scheduler", f"tcp://127.0.0.1:{port}", "--no-progress"]
        )  # fmt: skip
    finally:
        srv.close()
    assert rc == 2 and time.time() - t0 < 20
