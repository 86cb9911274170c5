"""A flag that would do nothing in the combination given is refused (issue 46, item 5).

Each refused pair is one line ``obturator: error: <flag>: ...`` naming both flags, exit
2, before any work; the combinations where the flag acts still run (or parse) and get
the documented defaults. In-process (:func:`obturator.cli.main`), no solver run.
"""

from __future__ import annotations

import argparse
import json

import pytest

from obturator.cli import build_parser, main
from obturator.cli._args import study_options
from obturator.cli._flight_args import model_from_args
from obturator.cli._robust_args import PROBABILITY_DEFAULTS
from obturator.cli.robust import _resolve_sampling_flags


def _one_line_exit_2(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("obturator: error: ") and err.count("\n") == 1, err
    assert "Traceback" not in err
    return err.strip()


@pytest.fixture
def rig_csv(tmp_path):
    p = tmp_path / "rig.csv"
    p.write_text("spin_rate_rad_s,t_cr_s\n300,0.3\n400,0.2\n")
    return str(p)


REFUSED = [
    (
        ["probability", "--method", "is", "--samples", "20"],
        "--samples: applies to --method mc or both (brute force), not --method is",
    ),
    (
        ["probability", "--samples", "20"],  # --method is is the default
        "--samples: applies to --method mc or both (brute force), not --method is",
    ),
    (
        ["probability", "--method", "mc", "--stage-samples", "50"],
        "--stage-samples: applies to --method is or both (importance sampling), not --method mc",
    ),
    (
        ["probability", "--method", "mc", "--final-samples", "50"],
        "--final-samples: applies to --method is or both (importance sampling), not --method mc",
    ),
    (
        ["probability", "--method", "mc", "--rho", "0.2"],
        "--rho: applies to --method is or both (importance sampling), not --method mc",
    ),
    (
        ["gasdyn", "choke", "--fld", "0.5", "--reynolds", "1e6"],
        "--reynolds: applies with --l-over-d only, not with --fld",
    ),
    (
        ["gasdyn", "choke", "--fld", "0.5", "--bore-diameter-m", "9 mm"],
        "--bore-diameter-m: applies with --l-over-d only, not with --fld",
    ),
    (
        ["gasdyn", "choke", "--fld", "0.5", "--reynolds-mach", "2"],
        "--reynolds-mach: applies with --reynolds only, not with --fld",
    ),
    (
        ["gasdyn", "choke", "--fld", "0.5", "--iterations", "3"],
        "--iterations: applies with --reynolds only, not with --fld",
    ),
    (
        ["gasdyn", "choke", "--fld", "0.5", "--altitude-m", "1 km"],
        "--altitude-m: applies with --bore-diameter-m only, not with --fld",
    ),
    (
        ["gasdyn", "choke", "--fld", "0.5", "--roughness", "0.001"],
        "--roughness: applies with --reynolds or --bore-diameter-m only, not with --fld",
    ),
    (
        ["gasdyn", "choke", "--fld", "0.5", "--correlation", "haaland"],
        "--correlation: applies with --reynolds or --bore-diameter-m only, not with --fld",
    ),
    (
        ["gasdyn", "choke", "--l-over-d", "8", "--reynolds", "5e5", "--altitude-m", "100"],
        "--altitude-m: applies with --bore-diameter-m only, not with --reynolds",
    ),
    (
        ["gasdyn", "choke", "--l-over-d", "8", "--reynolds", "5e5", "--branch", "subsonic"],
        "--branch: applies with --fld only, not with --reynolds",
    ),
    (
        ["gasdyn", "choke", "--l-over-d", "8", "--bore-diameter-m", "9 mm", "--iterations", "2"],
        "--iterations: applies with --reynolds only, not with --bore-diameter-m",
    ),
    (
        ["gasdyn", "choke", "--l-over-d", "8", "--bore-diameter-m", "9 mm", "--reynolds-mach", "2"],
        "--reynolds-mach: applies with --reynolds only, not with --bore-diameter-m",
    ),
    (
        ["gasdyn", "choke", "--l-over-d", "8", "--bore-diameter-m", "9 mm", "--branch", "subsonic"],
        "--branch: applies with --fld only, not with --bore-diameter-m",
    ),
    (
        ["trajectory", "--twist", "0.4 m", "--spin-rate", "10000"],
        "--twist: sets the muzzle spin by the twist law, which --spin-rate replaces",
    ),
    (
        ["envelope", "--mach", "3", "--altitude-m", "0", "--twist", "0.4", "--spin-rate", "1e4"],
        "--twist: sets the muzzle spin by the twist law, which --spin-rate replaces",
    ),
    (
        ["sweep", "--spin-rate", "300", "--out", "x.nc", "--csv", "x.csv", "--no-csv"],
        "--no-csv: turns off the automatic CSV, and --csv asks for one",
    ),
    (
        ["sweep", "--method", "moreau-jean", "--friction-width", "1e-6", "--spin-rate", "300",
         "--out", "x.nc"],
        "--friction-width: sets the regularised law, which --method moreau-jean does not use",
    ),
    (
        ["montecarlo", "--method", "moreau-jean", "--friction-family", "tanh", "--samples", "2",
         "--vary", "mu_s=uniform:0.5,0.6"],
        "--friction-family: sets the regularised law, which --method moreau-jean does not use",
    ),
    (
        ["sweep", "--method", "set-valued", "--friction-width", "1e-6", "--spin-rate", "300",
         "--out", "x.nc"],  # the sweep's convergence check is off by default
        "--friction-width: acts with --method set-valued only through the convergence check's "
        "regularised reruns, which are off here",
    ),
    (
        ["montecarlo", "--method", "set-valued", "--friction-family", "tanh",
         "--no-convergence-check", "--samples", "2", "--vary", "mu_s=uniform:0.5,0.6"],
        "--friction-family: acts with --method set-valued only through the convergence check's "
        "regularised reruns, which are off here",
    ),
    (
        ["validate", "--profile-all", "--no-profile"],
        "--profile-all: profiles every candidate, which --no-profile turns off",
    ),
]  # fmt: skip


@pytest.mark.parametrize(("argv", "message"), REFUSED, ids=lambda a: " ".join(a)[:60])
def test_an_ineffective_pair_is_one_line_exit_2(capsys, tmp_path, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    line = _one_line_exit_2(capsys, argv)
    assert line.startswith("obturator: error: " + message), line
    assert not (tmp_path / "x.nc").exists() and not (tmp_path / "x.csv").exists()


def test_calibrate_seed_without_bootstrap_is_refused(capsys, rig_csv):
    line = _one_line_exit_2(capsys, ["calibrate", rig_csv, "--bootstrap", "0", "--seed", "3"])
    assert line == ("obturator: error: --seed: seeds the bootstrap, which --bootstrap 0 turns off")


def _probability_args(*argv: str) -> argparse.Namespace:
    return build_parser("probability").parse_args(["probability", *argv])


@pytest.mark.parametrize(
    ("argv", "expected"),
    [
        ([], {"stage_samples": 500, "final_samples": 1000, "rho": "0.1"}),
        (["--method", "is", "--stage-samples", "50", "--rho", "0.2"], {"stage_samples": 50}),
        (["--method", "mc", "--samples", "20"], {"samples": 20}),
        (["--method", "mc"], {"samples": 2000}),
        (
            ["--method", "both", "--samples", "20", "--stage-samples", "30", "--final-samples",
             "40", "--rho", "0.3"],
            {"samples": 20, "stage_samples": 30, "final_samples": 40},
        ),
    ],
)  # fmt: skip
def test_probability_flags_where_they_act_parse_and_defaults_are_the_documented_ones(
    argv, expected
):
    args = _probability_args(*argv)
    _resolve_sampling_flags(args)
    for dest, default in PROBABILITY_DEFAULTS.items():  # every flag resolved: none unset
        assert getattr(args, dest) is not None, dest
        if dest not in expected and dest not in {a.lstrip("-").replace("-", "_") for a in argv}:
            assert str(getattr(args, dest)) == default, dest
    for dest, value in expected.items():
        assert str(getattr(args, dest)) == str(value), dest


def test_probability_help_states_the_defaults():
    parser = build_parser("probability")
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    helps = {a.option_strings[0]: a.help for a in sub.choices["probability"]._actions if a.help}
    for flag, dest in (
        ("--samples", "samples"),
        ("--stage-samples", "stage_samples"),
        ("--final-samples", "final_samples"),
        ("--rho", "rho"),
    ):
        assert f"default {PROBABILITY_DEFAULTS[dest]};" in helps[flag], flag


@pytest.mark.parametrize(
    ("argv", "mach"),
    [
        # thesis Fig. 4 route: f_D L/D alone, either branch
        (["--fld", "0.102"], None),
        (["--fld", "0.102", "--branch", "subsonic"], None),
        (["--l-over-d", "8.07", "--reynolds", "5e5", "--reynolds-mach", "3", "--iterations",
          "3", "--roughness", "0.001", "--correlation", "haaland"], None),
        (["--l-over-d", "8.07", "--bore-diameter-m", "9.44 mm", "--altitude-m", "1 km",
          "--roughness", "0.001", "--correlation", "haaland"], None),
    ],
)  # fmt: skip
def test_choke_flags_on_their_own_route_still_run(capsys, argv, mach):
    assert main(["gasdyn", "choke", *argv, "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["mach"] > 0


def test_choke_defaults_are_the_documented_ones(capsys):
    """Unset flags resolve to the defaults the help states: the explicit defaults give the
    same answer as none."""
    argv = ["gasdyn", "choke", "--l-over-d", "8.07", "--reynolds", "5e5", "--json"]
    assert main(argv) == 0
    implicit = json.loads(capsys.readouterr().out)
    explicit = [*argv, "--reynolds-mach", "2.5", "--iterations", "1", "--roughness", "0"]
    assert main([*explicit, "--correlation", "colebrook"]) == 0
    assert json.loads(capsys.readouterr().out) == implicit


@pytest.mark.parametrize("argv", [["--twist", "0.4"], ["--spin-rate", "10000"], []])
def test_twist_or_spin_rate_alone_still_builds_the_model(argv):
    args = build_parser("trajectory").parse_args(["trajectory", *argv])
    model = model_from_args(args)
    if "--spin-rate" in argv:
        assert model.launch.spin_rate == 10000.0
    if "--twist" in argv:
        assert model.launch.twist == 0.4 and model.launch.spin_rate is None


@pytest.mark.parametrize(
    ("command", "argv", "width", "family"),
    [
        ("sweep", ["--method", "set-valued", "--convergence-check", "--friction-width", "1e-6",
                   "--friction-family", "tanh"], 1e-6, "tanh"),
        ("montecarlo", ["--method", "set-valued", "--friction-width", "1e-6"], 1e-6, "algebraic"),
        ("sweep", ["--method", "regularised", "--friction-width", "1e-6"], 1e-6, "algebraic"),
        ("sweep", ["--friction-family", "linear"], 1e-7, "linear"),  # auto: its regularised cases
        ("montecarlo", ["--method", "moreau-jean"], 1e-7, "algebraic"),
    ],
)  # fmt: skip
def test_width_and_family_where_they_act_reach_the_options(command, argv, width, family):
    required = ["--out", "x.nc"] if command == "sweep" else ["--vary", "mu_s=uniform:0,1"]
    required += [] if command == "sweep" else ["--samples", "2"]
    args = build_parser(command).parse_args([command, *argv, *required])
    opts = study_options(args)
    assert (opts.friction_width, opts.friction_family) == (width, family)
