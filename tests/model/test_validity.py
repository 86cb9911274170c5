"""Inputs far outside the validated range: a one-line warning with the expected cost,
and a step limit that names its cause and the fix (issue: ``--spin-rate "150 deg/s"``,
2.6 rad/s, ran 11 minutes without a word and then failed with a bare step limit)."""

from __future__ import annotations

import json
import math

import pytest

from obturator import SolverOptions
from obturator.calibration import load_thesis_data
from obturator.cli import main
from obturator.cli import simulate as simulate_cli
from obturator.errors import InputError
from obturator.model.cases import flight_case, rig_case
from obturator.model.validity import RIG_RUN_SPINS, outside_validated_range


def test_rig_run_spins_are_appendix_b():
    spins = load_thesis_data().spin_rate  # the 54 runs' readouts (18-tooth wheel)
    assert RIG_RUN_SPINS == pytest.approx((spins.min(), spins.max()), abs=0.01)


@pytest.mark.parametrize(
    ("case", "flagged"),
    [
        (rig_case(150 * math.pi / 180), True),  # "150 deg/s", the unit slip
        (rig_case(30.0), True),
        (rig_case(40.0), False),  # convergence-tested (tests/solve/test_convergence.py)
        (rig_case(300.0), False),
        (rig_case(2000.0), False),  # high spin is cheap: not flagged
        (flight_case(), False),
        (flight_case(150 * math.pi / 180), True),  # issue 48: flight warned of nothing
    ],
)
def test_outside_validated_range(case, flagged):
    note = outside_validated_range(case)
    assert (note is not None) == flagged
    if flagged:
        assert f"{case.spin_rate:.4g} rad/s" in note and "77.8-446.1 rad/s" in note


def test_low_spin_warns_once_with_expected_cost(capsys):
    assert main(["simulate", "--spin-rate", "150 deg/s", "--t-max", "1e-3", "--no-check"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    assert err[0].startswith("obturator: warning: spin_rate 2.618 rad/s is far below")
    assert "a timed probe" in err[0] and "expects ~" in err[0]  # it covered all of t_max


def test_a_failed_convergence_check_leaves_the_answer(monkeypatch, capsys):
    """Issue 48: the check's reruns of a 2.6 rad/s run (regularised, near stick) stop at
    their step budget; the answer stays "not opened by t_max", the check is marked."""
    monkeypatch.setattr(simulate_cli, "CHECK_MIN_STEPS", 50)
    monkeypatch.setattr(simulate_cli, "CHECK_STEP_FACTOR", 1)
    assert main(["simulate", "--spin-rate", "150 deg/s", "--t-max", "1"]) == 0
    out, err = capsys.readouterr()
    assert "not opened by t_max" in out and "check FAILED" in out
    assert "the convergence check of t_cr could not finish" in err
    assert main(["simulate", "--spin-rate", "150 deg/s", "--t-max", "1", "--json"]) == 0
    conv = json.loads(capsys.readouterr().out)["convergence"]
    assert conv["converged"] is False and "steps" in conv["failed"]


@pytest.mark.parametrize(
    "argv",
    [
        ["sweep", "--spin-rate", "150,3000 deg/s", "--out", "{tmp}/s.nc"],
        ["montecarlo", "--samples", "2", "--vary", "spin_rate=uniform:2,60"],
    ],
)
def test_studies_warn_like_simulate(argv, tmp_path, monkeypatch, capsys):
    """Issue 48: the warning comes before any work (the study itself is stubbed)."""
    import obturator.cli.montecarlo as mc
    import obturator.cli.sweep as sw

    def stop(*args, **kwargs):
        raise InputError("stub", "stopped before the work")

    monkeypatch.setattr(sw, "runner_from_args", stop)
    monkeypatch.setattr(mc, "runner_from_args", stop)
    assert main([a.replace("{tmp}", str(tmp_path)) for a in argv]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("obturator: warning: spin_rate ") and "far below" in err[0]
    assert "step limit" in err[0]


def test_normal_spin_does_not_warn(capsys):
    assert main(["simulate", "--spin-rate", "300", "--no-check"]) == 0
    assert capsys.readouterr().err == ""


def test_step_limit_names_cause_and_fix(monkeypatch, capsys):
    # the regularised law (the default auto runs 2.6 rad/s set-valued: stick throughout,
    # no step limit)
    monkeypatch.setattr(
        simulate_cli,
        "options_from_settings",
        lambda s: SolverOptions(max_steps=200, method="regularised"),
    )
    assert main(["simulate", "--spin-rate", "150 deg/s", "--t-max", "1", "--no-check"]) == 3
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert err.startswith("obturator: solver failure: step limit: 200 steps reached at t = ")
    for fragment in ("near stick", "width 2.6e-07 rad/s", "--friction-width", "--t-max", "unit"):
        assert fragment in err


@pytest.mark.parametrize(
    ("toml", "field"),
    [
        ('[ball]\nradius = "7.899"\n', "ball.radius"),  # metres as documented: a 7.9 m ball
        ("[ball]\ndensity = 7.8e6\n", "ball.density"),
    ],
)
def test_config_error_names_the_key_the_user_wrote(tmp_path, capsys, toml, field):
    """Not the rig weight W = rho g V derived from it, which the user never set."""
    cfg = tmp_path / "run.toml"
    cfg.write_text(toml)
    assert main(["simulate", "--config", str(cfg), "--no-check"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"obturator: error: {field}: ") and "weight:" not in err
    assert "outside the allowed [0, 10] N" in err
