"""Honest waiting (issue 48): a piped ``reproduce``, ``validate`` or ``warmup`` is never
silent for longer than the heartbeat interval (30 s in the issue; shrunk here) while a
fake slow task runs, and ``warmup`` reports each target as it finishes."""

from __future__ import annotations

import importlib
import time

import pytest

import obturator.runs.progress as progress
from obturator.cli import main
from obturator.errors import InputError

SLOW_S = 2.5  # the fake task's length: five heartbeat intervals
BEAT_S = 0.5


class _Recorder:
    """A piped stderr that keeps each line with the time it was written."""

    def __init__(self) -> None:
        self.lines: list[tuple[float, str]] = []

    def write(self, text: str) -> int:
        for line in text.splitlines():
            if line.strip():
                self.lines.append((time.monotonic(), line))
        return len(text)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return False


def _longest_silence(rec: _Recorder, t0: float, t1: float) -> float:
    times = [t0, *(t for t, _ in rec.lines), t1]
    return max(b - a for a, b in zip(times, times[1:], strict=False))


def _slow(*args, **kwargs):
    time.sleep(SLOW_S)
    raise InputError("fake", "the fake slow task ended")


@pytest.fixture
def piped(monkeypatch):
    """Install with ``piped()`` in the test body (pytest's capture resets sys.stderr
    between a fixture's setup and the test's call)."""
    rec = _Recorder()
    monkeypatch.setattr(progress, "HEARTBEAT_S", BEAT_S)

    def install() -> _Recorder:
        monkeypatch.setattr("sys.stderr", rec)
        return rec

    return install


@pytest.mark.parametrize(
    ("argv", "target"),
    [
        (["reproduce", "--out", "{tmp}/r", "--quick"], "obturator.thesis.reproduce.reproduce"),
        (["validate", "--workers", "1"], "obturator.validation.run_validation"),
    ],
)
def test_a_piped_run_is_never_silent_longer_than_the_heartbeat(
    argv, target, piped, monkeypatch, tmp_path
):
    module, _, name = target.rpartition(".")
    monkeypatch.setattr(importlib.import_module(module), name, _slow)
    piped = piped()
    t0 = time.monotonic()
    assert main([a.replace("{tmp}", str(tmp_path)) for a in argv]) == 2
    t1 = time.monotonic()
    beats = [line for _, line in piped.lines if "still running" in line]
    assert len(beats) >= 3, piped.lines  # SLOW_S / BEAT_S = 5 intervals
    assert beats[0].startswith(f"obturator: {argv[0]}: still running (")
    # without the heartbeat the silence is the whole task (SLOW_S); with it, one interval
    # plus the thread's poll and scheduling slack
    assert _longest_silence(piped, t0, t1) < 3 * BEAT_S, piped.lines


def test_no_heartbeat_with_no_progress(piped, monkeypatch, tmp_path):
    monkeypatch.setattr(importlib.import_module("obturator.thesis.reproduce"), "reproduce", _slow)
    piped = piped()
    assert main(["reproduce", "--out", str(tmp_path / "r"), "--no-progress"]) == 2
    assert not [line for _, line in piped.lines if "still running" in line]


def test_warmup_reports_each_target_as_it_finishes(piped, monkeypatch):
    import obturator.warmup as warmup

    def fake(*, jobs, everything, report):
        targets = ("dop853", "radau", "set-valued")  # the CLI names the real ones first
        for i, m in enumerate(targets, 1):
            time.sleep(SLOW_S / 3)
            report(m, 1.0 + i, i != 2, i, len(targets))
        return {
            "seconds": {m: 1.0 for m in targets},
            "compiled": {m: True for m in targets},
            "wall_s": SLOW_S,
            "directory": "/cache",
        }

    monkeypatch.setattr(warmup, "warm_up", fake)
    monkeypatch.setattr(warmup, "WARMUP_TARGETS", ("dop853", "radau", "set-valued"))
    piped = piped()
    t0 = time.monotonic()
    assert main(["warmup"]) == 0
    t1 = time.monotonic()
    done = [line for _, line in piped.lines if line.startswith("obturator: warmup: ")]
    assert done[0].startswith("obturator: warmup: 3 integrators (dop853, radau, set-valued)")
    assert "obturator: warmup: dop853 compiled in 2.0 s (1/3)" in done
    assert "obturator: warmup: radau loaded from the cache in 3.0 s (2/3)" in done
    assert "obturator: warmup: set-valued compiled in 4.0 s (3/3)" in done
    assert _longest_silence(piped, t0, t1) < 3 * BEAT_S, piped.lines


def test_weighted_steps_give_the_time_left_of_the_whole_run(monkeypatch, capsys):
    """Two steps of weight 1 done in 2 s, a step of weight 10 left: about 10 s left (1 s
    per unit of weight), not 1 s (the equal-steps estimate, which read "about 5.9 s
    left" before a 7.5-minute validation in issue 48)."""
    clock = iter([0.0, 0.0, 1.0, 2.0, 2.0, 2.0])
    monkeypatch.setattr(progress.time, "monotonic", lambda: next(clock))
    p = progress.Progress("lines", interval_s=0.0)
    with p.track("reproduce", 3, unit="steps", weights=[1.0, 1.0, 10.0]) as step:
        step(1)
        step(1)
    lines = capsys.readouterr().err.splitlines()
    assert lines[-1] == ("obturator: reproduce: 2/3 steps (17 %), 2 s elapsed, about 10 s left"), (
        lines
    )


def test_weights_must_match_the_tasks():
    with pytest.raises(ValueError, match="2 weights for 3 tasks"):
        with progress.Progress("lines").track("x", 3, weights=[1.0, 1.0]):
            pass
