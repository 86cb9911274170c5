"""``obturator design-experiment``: bad input is one line and exit code 2, before any solve."""

from __future__ import annotations

import pytest

from obturator.cli import main


@pytest.mark.parametrize(
    ("argv", "field"),
    [
        (["--runs", "0"], "--runs"),
        (["--runs", "5,ten"], "--runs"),
        (["--campaigns", "5"], "--campaigns"),
        (["--spin-min", "400", "--spin-max", "100"], "--spin-min"),
        (["--theta0-max", "95 deg"], "--theta0-max"),
        (["--hole-radius-max", "6 mm"], "--hole-radius-max"),  # above R_s / sqrt(2)
        (["--density-min", "3 kg"], "--density-min"),  # wrong unit
        (["--models", "strengthening"], "models"),  # one candidate: nothing to discriminate
        (["--models", "thesis-1980,theta0"], "models"),  # fits no parameter
        (["--models", "nope,theta0"], "models"),
        (["--out", "design.csv"], "--out"),
        # 440-450 rad/s held at 70-75 deg: 4.4e-3 N m or more, 5 times the rig's bound
        (["--spin-min", "440", "--theta0-min", "70", "--theta0-max", "75"], "ranges"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(argv, field, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    rc = main(["design-experiment", "--no-progress", *argv])
    err = capsys.readouterr().err
    assert rc == 2
    assert err.count("\n") == 1 and err.startswith(f"obturator: error: {field}"), err
    assert "Traceback" not in err
