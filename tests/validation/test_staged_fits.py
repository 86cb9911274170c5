"""The all-run fit in three runner stages equals the fit in one task.

``design-experiment`` fits two candidates on two workers: their steps (first fit,
restarts along the flat direction, the settled fit) run as tasks of their own
(:func:`obturator.validation.study._staged_fits`); ``validate`` runs each fit as one task
(:func:`obturator.validation.tasks.all_run_fit_task`). The reference is that one task,
run in this process: every field of the two fits must agree exactly.
"""

from __future__ import annotations

import json

import pytest

from obturator.calibration.data import load_thesis_data
from obturator.runs import Runner
from obturator.validation.candidates import CANDIDATES
from obturator.validation.evaluate import DEFAULT_T_MAX, VALIDATION_OPTIONS
from obturator.validation.floor import DEFAULT_CLUSTER_GAP
from obturator.validation.likelihood import SPIN_SD
from obturator.validation.study import STAGED_BELOW, _fits_of, _observations
from obturator.validation.tasks import AllRuns, all_run_fit_task


@pytest.mark.slow
def test_staged_all_run_fit_is_the_one_task_fit():
    data = load_thesis_data()
    common = (SPIN_SD, DEFAULT_T_MAX, VALIDATION_OPTIONS, "band")
    _, obs = _observations(data, DEFAULT_CLUSTER_GAP, common, 2)
    runner = Runner(workers=2, progress=False)
    assert 1 < STAGED_BELOW * runner.n_workers  # one candidate on two workers: staged
    cand = CANDIDATES["strengthening"]
    staged = _fits_of([cand], obs, DEFAULT_CLUSTER_GAP, runner, data, memo=False)[cand.name]
    one, _ = all_run_fit_task(
        cand.name, AllRuns(obs.w, obs.y, obs.band, obs.run, *common, obs.conds)
    )
    assert one.n_restarts == 2  # the restarts stage ran
    mine, ref = staged.to_dict(), one.to_dict()
    for d in (mine, ref):
        assert d.pop("elapsed_s") > 0.0  # the settled fit's own time, not a result
    assert json.dumps(mine, sort_keys=True) == json.dumps(ref, sort_keys=True)
