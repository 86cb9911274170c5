"""One case file for every command (issue 48): the two examples of ``obturator.io``'s
docstring (the rig file and the flight file that ``simulate`` runs), cut out of it as
they stand, run unchanged with every command that runs that case, as its base case; and
what a command cannot honour is refused by name with the reason.

Reference values: the rig file states Table 1's values (obturator.reference.TABLE1), so a
sweep of it equals a sweep without it point for point (same inputs, same bits); a flight
file's launch point equals the flags that say the same.
"""

from __future__ import annotations

import json
import math
import re

import pytest

import obturator.io
from obturator.cli import main


def _examples() -> tuple[str, str]:
    """The rig and the flight file of obturator.io's docstring, as they stand."""
    blocks = re.findall(r"::\n\n((?:    .*\n|\n)+)", obturator.io.__doc__ or "")
    rig, flight = ("\n".join(line[4:] for line in b.splitlines()) for b in blocks[:2])
    assert 'case = "spin-rig"' in rig and 'case = "flight"' in flight
    return rig, flight


RIG, FLIGHT = _examples()
FAST = ["--rtol", "1e-6", "--atol", "1e-8"]


@pytest.fixture
def rig(tmp_path):
    path = tmp_path / "rig.toml"
    path.write_text(RIG, encoding="utf-8")
    return str(path)


@pytest.fixture
def flight(tmp_path):
    path = tmp_path / "flight.toml"
    path.write_text(FLIGHT, encoding="utf-8")
    return str(path)


def _json(capsys, argv):
    assert main(argv) == 0, capsys.readouterr().err
    return json.loads(capsys.readouterr().out)


def test_the_rig_file_is_the_base_case_of_a_sweep(rig, tmp_path, capsys):
    """The file states Table 1's ball, gap and weight: the sweep's points are those of
    the same sweep without the file at mu_s 0.5473, theta_0 87.25 deg, t_max 10 s."""
    common = ["sweep", "--spin-rate", "300,400", "--workers", "1", "--no-progress", "--json"]
    a = _json(capsys, [*common, "--config", rig, "--out", str(tmp_path / "a.nc")])
    b = _json(
        capsys,
        [*common, "--mu-s", "0.5473", "--t-max", "10", "--out", str(tmp_path / "b.nc")],
    )
    assert a["settings"]["base"] == {
        "ball_radius": pytest.approx(7.899e-3),
        "viscosity": pytest.approx(1.917e-5),
        "weight": pytest.approx(0.07987),
    }
    assert a["t_cr_min_s"] == b["t_cr_min_s"] and a["t_cr_max_s"] == b["t_cr_max_s"]
    assert a["n_opened"] == 2


def test_the_rig_file_is_the_base_case_of_a_monte_carlo(rig, tmp_path, capsys):
    argv = ["montecarlo", "--config", rig, "--samples", "3", "--vary", "mu_s=uniform:0.5,0.6"]
    argv += ["--spin-rate", "400", "--t-max", "1", "--workers", "1", "--no-progress"]
    out = _json(capsys, [*argv, "--no-convergence-check", "--json"])
    assert out["n_opened"] == 3


def test_the_rig_file_runs_with_calibrate(rig, tmp_path, capsys):
    """Calibrate replaces the file's spin by each run's and fits mu_s, and says so; with
    Table 1's ball, gap and weight the fit is that of the same data without the file."""
    data = tmp_path / "runs.csv"
    data.write_text("t_cr_s,spin_rate_rad_s\n0.9,200\n0.5,300\n0.35,400\n", encoding="utf-8")
    argv = ["calibrate", str(data), "--bootstrap", "0", "--json"]
    assert main([*argv, "--config", rig]) == 0
    captured = capsys.readouterr()
    assert "spin_rate and mu_s are replaced" in captured.err
    with_file = json.loads(captured.out)
    horizon = tmp_path / "horizon.toml"
    horizon.write_text('t_max = "10 s"\n', encoding="utf-8")  # the rig file's
    without = _json(capsys, [*argv, "--config", str(horizon)])
    mu = [f["parameters"]["mu_s"]["value"] for f in (with_file, without)]
    assert mu[0] == pytest.approx(mu[1], rel=1e-9) and 0.1 < mu[0] < 2.0


def test_calibrate_refuses_what_the_rig_cannot_be(tmp_path, capsys):
    cfg = tmp_path / "c.toml"
    data = tmp_path / "runs.csv"
    data.write_text("t_cr_s,spin_rate_rad_s\n0.5,300\n", encoding="utf-8")
    for body, field in (('case = "flight"\n', "case"), ('spin_mode = "free"\n', "spin_mode")):
        cfg.write_text(body, encoding="utf-8")
        assert main(["calibrate", str(data), "--config", str(cfg)]) == 2
        assert capsys.readouterr().err.startswith(f"obturator: error: {field}: ")


def test_the_flight_file_runs_with_trajectory_at_its_launch_point(flight, capsys):
    """Mach 3 at 1 km from the file equals --mach 3 --altitude-m 1000 with the design
    flags that say the same (Coulomb contacts from the file)."""
    argv = ["trajectory", "--no-convergence-check", *FAST, "--json"]
    a = _json(capsys, [*argv, "--config", flight])
    b = _json(
        capsys,
        [
            *argv,
            "--mach",
            "3",
            "--altitude-m",
            "1000",
            "--torque-model",
            "coulomb",
            "--spin-rate",
            "115000 rpm",
            "--config",
            _design_only(flight),
        ],
    )
    for key in ("t_cr_coupled_s", "t_cr_constant_s"):
        assert a[key] == b[key] and math.isfinite(a[key])


def _design_only(path: str) -> str:
    """The flight file without its launch point (mach, altitude), next to it."""
    text = re.sub(r"(?m)^(mach|altitude) = .*$", "", open(path, encoding="utf-8").read())
    text = re.sub(r"(?m)^(spin_rate|torque_model) = .*$", "", text)
    out = path.replace(".toml", "_design.toml")
    with open(out, "w", encoding="utf-8") as f:
        f.write(text)
    return out


@pytest.mark.parametrize("command", ["envelope", "probability"])
def test_the_flight_file_is_the_launch_point_of_a_grid_command(command, flight, tmp_path, capsys):
    argv = [command, "--config", flight, "--no-convergence-check", *FAST, "--load", "constant"]
    argv += ["--workers", "1", "--no-progress", "--json"]
    if command == "probability":
        argv += ["--method", "mc", "--samples", "4"]
    out = _json(capsys, argv)
    if command == "envelope":  # one point: the file's Mach 3 at 1 km
        assert out["points"] == 1
        at = out["max_relative_difference_at"]
    else:
        (at,) = out["points"] if isinstance(out["points"], list) else (out,)
    assert (at["mach"], at["altitude_m"]) == (3.0, 1000.0)  # not the default sea level


def test_a_grid_flag_wins_over_the_files_launch_point(flight, capsys):
    argv = ["envelope", "--config", flight, "--mach", "2.5", "--altitude-m", "0"]
    argv += ["--no-convergence-check", *FAST, "--workers", "1", "--no-progress", "--json"]
    out = _json(capsys, argv)
    assert out["points"] == 1
    at = out["max_relative_difference_at"]
    assert (at["mach"], at["altitude_m"]) == (2.5, 0.0)


def test_the_flight_file_runs_with_simulate(flight, capsys):
    out = _json(capsys, ["simulate", "--config", flight, "--no-convergence-check", "--json"])
    assert out["case"] == "flight" and out["status"] == 1


def test_a_studys_base_case_is_in_its_identity_only_when_given():
    """A study without a base case keeps the identity (and resume digest) it had."""
    from obturator.errors import InputError
    from obturator.sweeps import SweepSpec

    plain = SweepSpec("spin-rig", {"spin_rate": [300.0, 400.0]})
    assert "base" not in plain.identity()
    based = SweepSpec("spin-rig", {"spin_rate": [300.0, 400.0]}, base={"ball_radius": 8e-3})
    assert based.identity()["base"] == {"ball_radius": 8e-3}
    assert based.digest() != plain.digest()
    assert based.build_case({"spin_rate": 300.0}).ball.radius == 8e-3
    with pytest.raises(InputError, match="mu_s: is not a base-case setting"):
        SweepSpec("spin-rig", {}, base={"mu_s": 0.5})  # a parameter: fixed, not base
