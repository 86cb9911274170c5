"""A pool worker killed by the system (out-of-memory killer, kill -9) is not a crash.

Its pool's unfinished chunks run again on fresh workers (at most
``LOST_WORKER_RETRIES`` times a run, one notice each); a worker lost every time stops
the run with one line that says a rerun resumes, the finished chunks are kept in the
resume store, and the rerun resumes to the uninterrupted result bit for bit. The tasks
kill their own process with SIGKILL where a marker file says so, as the
out-of-memory killer would.
"""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from obturator.errors import InputError
from obturator.runs import Runner, study_digest
from obturator.runs.pools import LOST_WORKER_RETRIES

pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="SIGKILL of a forked worker"
)


def _value(x: float) -> float:
    """An independent closed form of each task's result (no package code)."""
    return math.sin(x) * math.exp(-x / 7.0)


def _task(task: dict) -> float:
    """Kill this worker where the task's marker says so, else compute the value."""
    marker = Path(task["marker"])
    if task["kill"] == "once" and not marker.exists():
        marker.touch()  # the next attempt finds it and computes
        os.kill(os.getpid(), signal.SIGKILL)
    if task["kill"] == "while-poisoned" and marker.exists():
        os.kill(os.getpid(), signal.SIGKILL)
    time.sleep(0.01)
    return _value(task["x"])


def _tasks(tmp_path: Path, kill: str, at: int = 5, n: int = 12) -> list[dict]:
    marker = str(tmp_path / "marker")
    return [{"x": 0.5 * k, "marker": marker, "kill": kill if k == at else "no"} for k in range(n)]


def test_worker_killed_once_is_retried_and_the_run_finishes(
    tmp_path: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    tasks = _tasks(tmp_path, "once")
    runner = Runner(workers=2, chunk_size=1, progress=False)
    # no probe: it would run the first tasks in this process
    got = runner.map(_task, tasks, probe_first=False)
    assert got == [_value(t["x"]) for t in tasks]
    assert (tmp_path / "marker").exists()  # the task did kill its first worker
    notices = [ln for ln in capfd.readouterr().err.splitlines() if "notice" in ln]
    assert len(notices) == 1, notices
    assert notices[0].startswith("obturator: notice: a worker process was killed by SIGKILL")
    assert "(retry 1 of" in notices[0]


def test_worker_lost_every_time_stops_in_one_line_and_a_rerun_resumes(
    tmp_path: Path, capfd: pytest.CaptureFixture[str]
) -> None:
    tasks = _tasks(tmp_path, "while-poisoned")
    (tmp_path / "marker").touch()
    store = tmp_path / "study.nc"
    digest = study_digest({"study": "lost-worker-test"})
    runner = Runner(workers=2, chunk_size=1, progress=False, store=store)
    runner.open(digest)
    with pytest.raises(InputError) as err:
        runner.map(_task, tasks, probe_first=False)
    text = str(err.value)
    assert "\n" not in text
    assert text.startswith("workers: a worker process was killed by SIGKILL")
    assert f"{LOST_WORKER_RETRIES + 1} times in this run" in text
    assert "run the same command again to resume" in text
    notices = [ln for ln in capfd.readouterr().err.splitlines() if "notice" in ln]
    assert len(notices) == LOST_WORKER_RETRIES
    finished = runner.n_computed
    assert 0 < finished < len(tasks)  # the poisoned task is never among them

    (tmp_path / "marker").unlink()  # the memory is back
    again = Runner(workers=2, chunk_size=1, progress=False, store=store)
    again.open(digest)
    got = again.map(_task, tasks, probe_first=False)
    assert again.n_resumed == finished
    assert again.n_computed == len(tasks) - finished
    # bit for bit what one uninterrupted pass computes
    assert np.array_equal(np.array(got), np.array([_value(t["x"]) for t in tasks]))


def _children(pid: int) -> list[int]:
    try:
        text = Path(f"/proc/{pid}/task/{pid}/children").read_text()
    except OSError:
        return []
    return [int(c) for c in text.split()]


@pytest.mark.slow  # two sweeps of ~3-4 s each
def test_kill_9_of_a_sweep_worker_finishes_bit_identical(tmp_path: Path) -> None:
    import xarray as xr

    import obturator

    src = str(Path(obturator.__file__).parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([src, os.environ.get("PYTHONPATH", "")])}

    def sweep(out: Path) -> list[str]:
        return [
            sys.executable, "-m", "obturator", "sweep", "--case", "spin-rig",
            "--spin-rate", "42:60:3000", "--mu-s", "0.5473", "--workers", "2",
            "--chunk-size", "25", "--no-progress", "--out", str(out),
        ]  # fmt: skip

    ref = tmp_path / "ref.nc"
    subprocess.run(sweep(ref), check=True, capture_output=True, timeout=300, env=env)
    out = tmp_path / "killed.nc"
    proc = subprocess.Popen(
        sweep(out), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env
    )
    # seconds of pool work (24 points once finished within the 0.3 s wait on a fast
    # machine, and the worker to kill was gone)
    killed = None
    deadline = time.time() + 120
    while killed is None and proc.poll() is None and time.time() < deadline:
        workers = [c for c in _children(proc.pid) if _children(c) == []]
        if len(workers) >= 2:  # the pool is up: kill one of its workers
            time.sleep(0.3)
            try:
                os.kill(workers[-1], signal.SIGKILL)
                killed = workers[-1]
            except ProcessLookupError:  # a short-lived child, not a worker: look again
                pass
        time.sleep(0.02)
    _, err = proc.communicate(timeout=300)
    assert killed is not None, "the pool never started"
    assert proc.returncode == 0, err
    assert "Traceback" not in err and "internal error" not in err
    assert "a worker process was killed by SIGKILL" in err  # the kill hit a working worker
    with xr.open_dataset(ref) as a, xr.open_dataset(out) as b:
        np.testing.assert_array_equal(a["t_cr"].values, b["t_cr"].values)
        np.testing.assert_array_equal(a["status"].values, b["status"].values)
