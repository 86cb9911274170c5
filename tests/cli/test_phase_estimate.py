"""One whole-run estimate for a run of phases (issue 48, "honest waiting"): within
:meth:`Progress.phases` the plain lines' time left covers the phases still to come, and
the line at the end of the first phase gives an estimate within a factor of 2 of the
final elapsed time. The phases are fake slow tasks whose costs the test knows (sleeps);
the validation study's weights are checked against measured phase times."""

from __future__ import annotations

import itertools
import re
import time

import pytest

import obturator.runs.progress as progress
from obturator.runs import Runner

UNIT_S = 0.05  # the fake tasks' time per unit of weight


def _sleep(units: float) -> float:
    time.sleep(units * UNIT_S)
    return units


def _left_s(line: str) -> float:
    m = re.search(r"about ([0-9.]+) (s|min) left", line)
    assert m, line
    return float(m.group(1)) * (60.0 if m.group(2) == "min" else 1.0)


@pytest.mark.parametrize(
    ("first", "second"),
    [
        ([2.0] * 4, [1.0] * 24),  # a short first phase before a long second one
        ([4.0] * 6, [1.0] * 4),  # a long first phase, a short second one
    ],
)
def test_the_estimate_after_the_first_phase_covers_the_whole_run(first, second, capsys):
    """Each phase's weight is the sum of its tasks' known costs (UNIT_S per unit). The
    first phase's own estimate said nothing about the second (equal tasks: "0 s left"
    at its end, as validate's per-phase lines in issue 48); the plan's line at its end
    gives the second phase's time, and so the whole run within a factor of 2."""
    runner = Runner(workers=1, progress=progress.Progress("lines", interval_s=0.0))
    plan_w = [("first", sum(first)), ("second", sum(second))]
    t0 = time.monotonic()
    with runner.reporter.phases("fake", plan_w) as plan:
        plan.start("first")
        runner.map(_sleep, first, label="fake: first", unit="tasks", probe_first=False,
                   chunk_size=1)  # fmt: skip
        plan.start("second")
        runner.map(_sleep, second, label="fake: second", unit="tasks", probe_first=False,
                   chunk_size=1)  # fmt: skip
    total = time.monotonic() - t0
    lines = capsys.readouterr().err.splitlines()
    ends = [line for line in lines if line.startswith("obturator: fake: first done")]
    assert len(ends) == 1, lines
    share = sum(first) / (sum(first) + sum(second))
    assert f"({100 * share:.0f} % of the run)" in ends[0]
    elapsed = float(re.search(r"([0-9.]+) s elapsed", ends[0]).group(1))
    estimate = elapsed + _left_s(ends[0])
    assert total / 2 < estimate < 2 * total, (estimate, total, lines)
    # the lines within the first phase give the whole run's share but no time left (the
    # first estimate is the one at the end of the first phase); those of the second give
    # the whole run's time left, each within a factor of 2 of the run
    inside = [line for line in lines if re.match(r"obturator: fake: first: \d+/", line)]
    assert inside and all("% of the run)" in line for line in inside), lines
    assert not [line for line in inside if "left" in line], lines
    later = [line for line in lines if re.match(r"obturator: fake: second: \d+/", line)]
    assert later, lines
    for line in later:
        seen = float(re.search(r"([0-9.]+) s elapsed", line).group(1)) + _left_s(line)
        assert total / 2 < seen < 2 * total, (line, total)


def test_a_phase_weight_set_when_the_phase_starts(capsys):
    """A weight known only once the earlier phases end (validate's profiles: the
    recommended model) replaces the planned one: 1 unit done, 3 left -> 75 % left."""
    clock = itertools.chain([0.0], itertools.repeat(10.0))
    p = progress.Progress("lines")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(progress.time, "monotonic", lambda: next(clock))
        with p.phases("x", [("a", 1.0), ("b", 100.0)]) as plan:
            plan.start("a")
            plan.start("b", 3.0)
    line = capsys.readouterr().err.strip()
    assert line == "obturator: x: a done (25 % of the run), 10 s elapsed, about 30 s left; next: b"


def test_phases_in_order_and_weights_checked():
    p = progress.Progress("lines")
    with pytest.raises(ValueError, match="positive sum"):
        with p.phases("x", [("a", 0.0)]):
            pass
    with p.phases("x", [("a", 1.0), ("b", 1.0)]) as plan:
        plan.start("b")
        with pytest.raises(ValueError):
            plan.start("a")  # phases run in their planned order


def test_no_lines_from_a_plan_when_off(capsys):
    with progress.Progress("off").phases("x", [("a", 1.0), ("b", 1.0)]) as plan:
        plan.start("a")
        plan.start("b")
    assert capsys.readouterr().err == ""


def test_validation_weights_against_measured_phase_times():
    """The weights of validation/cost.py against measured wall times (docs/benchmarks.md,
    history, validation/cost.py): reproduce --quick's validation (strengthening,
    thesis-1980, mu, no profiles; 2 workers) took 1065.5 s for the all-run fits and
    212.8 s for the second phase; the estimate made at the end of the first phase
    (its time times the weights' ratio) must put the whole run within a factor of 2.
    And ``--profile-all`` costs "about 2-3 times the study's time" (run_validation)."""
    from obturator.calibration.data import load_thesis_data
    from obturator.validation.candidates import get_candidates
    from obturator.validation.floor import DEFAULT_CLUSTER_GAP
    from obturator.validation.study import _observations, _phase_weights

    floor, obs = _observations(
        load_thesis_data(), DEFAULT_CLUSTER_GAP, (1.0, 20.0, None, "band"), 48
    )
    quick = get_candidates(["strengthening", "thesis-1980", "mu"])
    (_, w1), (_, w2) = _phase_weights(quick, obs, floor, 48, [])
    t1, t2 = 1065.5, 212.8
    estimate = t1 * (1.0 + w2 / w1)
    assert (t1 + t2) / 2 < estimate < 2 * (t1 + t2), (w1, w2)
    cands = get_candidates(None)
    rec = [c for c in cands if c.name == "strengthening"]
    default = sum(w for _, w in _phase_weights(cands, obs, floor, 48, rec))
    everything = sum(w for _, w in _phase_weights(cands, obs, floor, 48, cands))
    assert 1.5 < everything / default < 3.5
