"""An interrupted validation study resumes from its store without redoing finished fits."""

from __future__ import annotations

import json

import pytest

from obturator.calibration.data import load_spin_rig_csv
from obturator.cli import main
from obturator.runs import Runner, sidecar_path
from obturator.validation import run_validation
from obturator.validation import tasks as validation_tasks

MODELS = "thesis-1980,mu"


def _models(res) -> str:
    """The models' results, without the wall-clock times."""

    def drop_times(x):
        if isinstance(x, dict):
            return {k: drop_times(v) for k, v in x.items() if "elapsed" not in k}
        return [drop_times(v) for v in x] if isinstance(x, list) else x

    return json.dumps(drop_times(res.to_dict()["models"]), sort_keys=True)


def test_an_interrupted_study_resumes_with_the_same_result(tiny_csv, tmp_path, monkeypatch):
    data = load_spin_rig_csv(tiny_csv)
    fresh = run_validation(data, models=MODELS, runner=Runner(workers=1), profile="none")
    fits = []
    original_fit = validation_tasks.fit_candidate

    def counted(cand, *args, **kwargs):
        fits.append(kwargs.get("selection"))
        return original_fit(cand, *args, **kwargs)

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(validation_tasks, "fit_candidate", counted)
    monkeypatch.setattr(validation_tasks, "curve_task", interrupted)
    store = tmp_path / "validation"
    first = Runner(workers=1, store=store)
    with pytest.raises(KeyboardInterrupt):
        run_validation(data, models=MODELS, runner=first, profile="none")
    # the two all-run fits and the phase-2 tasks before the first curve are kept
    assert fits.count("all") == 2 and first.n_computed > 2 and sidecar_path(store).is_file()
    done_before = first.n_computed
    monkeypatch.undo()
    monkeypatch.setattr(validation_tasks, "fit_candidate", counted)
    fits.clear()
    again = Runner(workers=1, store=store)
    res = run_validation(data, models=MODELS, runner=again, profile="none")
    # every task finished before the interrupt comes from the store, none twice
    assert again.n_resumed == done_before and "all" not in fits
    assert _models(res) == _models(fresh)  # restored fits are the fits themselves


def test_the_command_keeps_its_store_only_until_the_outputs_are_written(tiny_csv, tmp_path):
    out = tmp_path / "study"
    argv = ["validate", "--data", str(tiny_csv), "--models", MODELS, "--jobs", "1"]
    argv += ["--no-profile", "--no-progress", "--json", "--out", str(out)]
    assert main(argv) == 0
    assert not sidecar_path(out / "validation").exists()
    assert {p.name for p in out.iterdir()} == {
        "validation.json",
        "validation.txt",
        "validation.png",
    }
    # a folder holding another study's partial results is refused, --restart discards it
    sidecar_path(out / "validation").write_text(
        '{"format": "obturator-run-store/1", "study": "x"}\n'
    )
    assert main(argv) == 2
    assert main([*argv, "--restart"]) == 0
