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
        "--spin-rate", "120:450:24", "--mu-s", "0.5473", "--workers", "2",
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
        time.sleep(rng.uniform(0.4, 2.5))
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
