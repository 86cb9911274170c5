"""The runner: chunk order, the progress reporter, the plan line, the store's header."""

from __future__ import annotations

import json
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from obturator.errors import InputError
from obturator.runs import Progress, Runner, sidecar_path, study_digest
from obturator.runs.progress import PLAN_MIN_S, fmt_duration


@dataclass(frozen=True)
class Slow:
    """Picklable toy task: its value, after burning `cpu_s` of CPU."""

    cpu_s: float = 0.0

    def __call__(self, task):
        import time

        t0 = time.thread_time()
        while time.thread_time() - t0 < self.cpu_s:
            pass
        return {"y": task["x"] * 2}


def tasks(n: int) -> list[dict[str, float]]:
    return [{"x": float(i)} for i in range(n)]


def test_chunk_size_one_keeps_the_task_order_and_values() -> None:
    order: list[float] = []

    def record(task):
        order.append(task["x"])
        return task["x"] + 1

    runner = Runner(workers=1, chunk_size=7)
    out = runner.map(record, tasks(10), chunk_size=1, probe_first=False)
    assert out == [float(i + 1) for i in range(10)] and order == [float(i) for i in range(10)]
    assert runner.n_computed == 10 and runner.n_resumed == 0


def test_plain_lines_count_percent_and_eta(capsys: pytest.CaptureFixture[str]) -> None:
    out = Runner(workers=1, chunk_size=2, progress=Progress("lines", interval_s=0.0)).map(
        Slow(0.002), tasks(10), label="toy", unit="cases"
    )
    assert [r["y"] for r in out] == [2.0 * i for i in range(10)]
    lines = capsys.readouterr().err.splitlines()
    progress = [line for line in lines if re.match(r"obturator: toy: \d+/10 cases", line)]
    assert progress, lines
    # every line: count, percent, elapsed and time left; the count grows
    counts = [int(re.search(r"(\d+)/10", line).group(1)) for line in progress]
    assert counts == sorted(counts) and counts[-1] < 10
    assert all(re.search(r"\(\d+ %\), .* elapsed, about .* left$", line) for line in progress)


def test_off_is_silent_and_plan_only_for_long_runs(capsys: pytest.CaptureFixture[str]) -> None:
    Runner(workers=1, chunk_size=2, progress=Progress("off")).map(Slow(), tasks(6))
    assert capsys.readouterr().err == ""
    p = Progress("lines")
    p.plan("sweep", "10 points on 2 workers", 0.5 * PLAN_MIN_S)
    assert capsys.readouterr().err == ""  # short: nothing announced
    p.plan("sweep", "10000 points on 2 workers", 2 * PLAN_MIN_S)
    assert capsys.readouterr().err == (
        f"obturator: sweep: 10000 points on 2 workers; estimated "
        f"{fmt_duration(2 * PLAN_MIN_S)} on idle cores\n"
    )
    p.plan("validate", "9 fits on 2 workers")  # no probe: the work, always
    assert capsys.readouterr().err == "obturator: validate: 9 fits on 2 workers\n"


def test_the_probe_estimates_the_run(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """10 ms of CPU per task, 200 tasks in this process: about 2 s (announced above 1 s)."""
    import obturator.runs.progress as progress

    monkeypatch.setattr(progress, "PLAN_MIN_S", 1.0)
    Runner(workers=1, progress=Progress("lines")).map(Slow(0.01), tasks(200), label="toy")
    err = capsys.readouterr().err
    est = re.search(r"obturator: toy: 200 points on 1 worker; estimated ([\d.]+) s", err)
    assert est is not None, err
    assert 1.0 <= float(est.group(1)) <= 2.5  # 168 tasks left after the probe: 1.68 s


def test_the_probe_runs_a_fixed_count_of_tasks() -> None:
    """The probe runs the first `n_tasks` tasks of the first chunk (kept: sunk and gone
    from it), a count never taken from a timing, so a run's chunks, and with them the
    results of tasks that depend on their chunk-mates, are the same every time; the
    runner asks for one task before a pool of a non-separable job (a sweep in lanes)."""
    import numpy as np

    from obturator.runs.chunks import PROBE_TASKS, Job, make_chunks, probe

    def kept(n, n_tasks):
        sunk: list[int] = []
        chunks = make_chunks(np.arange(n), 2, None, contiguous=True)
        job = Job(lambda idx: idx, lambda idx: (idx,))
        cost = probe(job, chunks, lambda idx, _: sunk.extend(idx.tolist()), True, n_tasks)
        assert sorted(np.concatenate(chunks).tolist() + sunk) == list(range(n))
        return cost.n_tasks, sunk

    assert kept(10_000, 1) == (1, [0])
    assert kept(10_000, PROBE_TASKS) == (PROBE_TASKS, list(range(PROBE_TASKS)))
    assert kept(40, PROBE_TASKS) == (3, [0, 1, 2])  # the first chunk holds 3 tasks


def _pid_of_each(batch):
    """Batched toy task (module level: picklable): the process that ran each task."""
    import os

    return [os.getpid()] * len(batch)


def test_a_pool_probes_one_task_of_a_non_separable_job(monkeypatch, capsys) -> None:
    """Before a pool (forced here), a batched job (non-separable: its tasks' results may
    depend on their chunk-mates) runs one probe task in this process, the rest in the
    workers, and announces no estimate from that one task; a separable one runs
    PROBE_TASKS here."""
    import os

    import obturator.runs.progress as progress
    from obturator.runs import runner as runs_runner
    from obturator.runs.chunks import PROBE_TASKS

    monkeypatch.setattr(runs_runner, "POOL_MIN_SERIAL_S", 0.0)
    monkeypatch.setattr(progress, "PLAN_MIN_S", 0.0)
    here = os.getpid()
    runner = Runner(workers=2, chunk_size=50, progress=Progress("lines", interval_s=1e9))
    batched = runner.map(_pid_of_each, tasks(200), batched=True, label="toy")
    assert sum(p == here for p in batched) == 1
    assert "obturator: toy: 200 points on 2 workers\n" in capsys.readouterr().err
    one_by_one = Runner(workers=2, chunk_size=50).map(_pid_of_each_task, tasks(200))
    assert sum(p == here for p in one_by_one) == PROBE_TASKS


def test_a_large_pool_run_starts_without_a_probe(monkeypatch) -> None:
    """From POOL_SURE_TASKS tasks on, a pool run whose probe would be one task (batched,
    or a sweep's consecutive points) starts its workers at once: no task runs here; a
    run of one task fewer still probes one."""
    import os

    from obturator.runs import runner as runs_runner

    monkeypatch.setattr(runs_runner, "POOL_MIN_SERIAL_S", 0.0)
    monkeypatch.setattr(runs_runner, "POOL_SURE_TASKS", 200)
    here = os.getpid()
    at = Runner(workers=2, chunk_size=50).map(_pid_of_each, tasks(200), batched=True)
    assert sum(p == here for p in at) == 0 and len(at) == 200
    below = Runner(workers=2, chunk_size=50).map(_pid_of_each, tasks(199), batched=True)
    assert sum(p == here for p in below) == 1


def _pid_of_each_task(task):
    import os

    return os.getpid()


def test_fmt_duration() -> None:
    assert fmt_duration(4.25) == "4.2 s" and fmt_duration(42.4) == "42 s"
    assert fmt_duration(330) == "5.5 min" and fmt_duration(7200) == "2.0 h"


def test_empty_sidecar_from_an_unwritten_header_is_taken_as_absent(tmp_path: Path) -> None:
    """A store whose header never reached the disk (an older release on a full disk)
    resumes as new instead of refusing a "different study (hash ?)"."""
    out = tmp_path / "env.nc"
    sidecar_path(out).write_bytes(b"")
    runner = Runner(workers=1, store=out)
    runner.open(study_digest({"study": "toy"}))
    assert runner.map(Slow(), tasks(3)) == [{"y": 0.0}, {"y": 2.0}, {"y": 4.0}]
    header = json.loads(sidecar_path(out).read_text().splitlines()[0])
    assert header["study"] == study_digest({"study": "toy"})
    runner.close()
    with pytest.raises(InputError, match="different study"):
        Runner(store=out).open(study_digest({"study": "other"}))


def test_non_mapping_tasks_are_not_stored(tmp_path: Path) -> None:
    runner = Runner(workers=1, store=tmp_path / "o.nc")
    runner.open(study_digest({"study": "toy"}))
    with pytest.raises(InputError, match="^store:"):
        runner.map(len, [(1, 2), (3,)])
    runner.close()


def test_a_pool_probes_one_point_of_a_sweep(monkeypatch, tmp_path: Path) -> None:
    """A sweep's chunks are runs of consecutive points (``Job.contiguous``): before its pool
    this process runs one probe point, not PROBE_TASKS, since the probe is serial work that
    delays every worker, and a contiguous job's first points are the costliest end of the
    grid (the lowest spins)."""
    import os

    from obturator.runs import runner as runs_runner
    from obturator.sweeps import SweepSpec
    from obturator.sweeps import job as sweep_job
    from obturator.sweeps.sweep import execute_sweep

    log = tmp_path / "chunks.txt"
    monkeypatch.setenv("OBTURATOR_TEST_CHUNK_LOG", str(log))  # read by the forked workers
    monkeypatch.setattr(sweep_job, "run_chunk", _logged_run_chunk)
    monkeypatch.setattr(runs_runner, "POOL_MIN_SERIAL_S", 0.0)
    spec = SweepSpec("spin-rig", {"spin_rate": list(np.linspace(300.0, 400.0, 40))}, t_max=2.0)
    run = execute_sweep(spec, Runner(workers=2, chunk_size=10))
    assert run.workers == 2 and run.n_computed == 40
    here = [int(n) for pid, n in (line.split() for line in log.read_text().splitlines())
            if int(pid) == os.getpid()]  # fmt: skip
    assert sum(here) == 1, here


def _logged_run_chunk(spec, names, rows, *packed):
    """:func:`obturator.sweeps.points.run_chunk`, appending "pid points" to a log."""
    import os

    from obturator.sweeps.points import run_chunk

    with open(os.environ["OBTURATOR_TEST_CHUNK_LOG"], "a") as fh:
        fh.write(f"{os.getpid()} {len(rows)}\n")
    return run_chunk(spec, names, rows, *packed)
