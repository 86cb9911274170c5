"""Tests of the ``obturator gasdyn`` command line."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from obturator.cli import main


def run_json(capsys: pytest.CaptureFixture[str], *argv: str) -> dict:
    assert main(["gasdyn", *argv, "--json"]) == 0
    out = capsys.readouterr().out
    assert out.count("\n") == 1  # exactly one JSON object
    return json.loads(out)


def test_normal_shock_json(capsys: pytest.CaptureFixture[str]) -> None:
    d = run_json(capsys, "normal-shock", "--mach", "3")
    # NACA 1135 at M1 = 3: 0.4752, 10.33, 3.857, 2.679, 0.3283.
    assert d["mach2"] == pytest.approx(0.4752, abs=5e-5)
    assert d["pressure_ratio"] == pytest.approx(10.33, abs=5e-3)
    assert d["stagnation_pressure_ratio"] == pytest.approx(0.3283, abs=5e-5)


def test_normal_shock_table(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["gasdyn", "normal-shock", "--mach", "2", "--gamma", "1.4"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert any("p2/p1" in line and "4.5" in line for line in lines)
    # Aligned: every value column ends at the same place.
    ends = {line.rstrip().rfind(" -") for line in lines}
    assert len(ends) == 1


def test_start_from_area_ratio(capsys: pytest.CaptureFixture[str]) -> None:
    d = run_json(capsys, "start", "--area-ratio", "1.0")
    assert d["start_mach"] == 1.0 and d["unstart_mach"] == 1.0
    d = run_json(capsys, "start", "--area-ratio", "1.2")
    assert d["start_mach"] > d["unstart_mach"] > 1.0
    d = run_json(capsys, "start", "--area-ratio", "1.7")
    assert d["start_mach"] is None
    assert d["swallow_area_ratio_limit"] == pytest.approx(1.66613, abs=1e-5)
    assert main(["gasdyn", "start", "--area-ratio", "1.7"]) == 0
    assert "never" in capsys.readouterr().out


def test_start_from_mach(capsys: pytest.CaptureFixture[str]) -> None:
    d = run_json(capsys, "start", "--mach", "2")
    assert d["regurgitate_area_ratio"] == pytest.approx(1.6875)
    assert d["swallow_area_ratio"] == pytest.approx(1.2165, abs=1e-4)


def test_choke_fld(capsys: pytest.CaptureFixture[str]) -> None:
    d = run_json(capsys, "choke", "--fld", "0.102")
    assert d["mach"] == pytest.approx(1.41, abs=0.01)
    d = run_json(capsys, "choke", "--fld", "0.102", "--branch", "subsonic")
    assert d["mach"] < 1.0


def test_choke_iteration(capsys: pytest.CaptureFixture[str]) -> None:
    d = run_json(capsys, "choke", "--l-over-d", "8.07", "--reynolds", "5e5", "--iterations", "1")
    assert len(d["steps"]) == 2
    assert d["steps"][0]["mach"] == pytest.approx(1.41, abs=0.01)
    assert d["mach"] == pytest.approx(1.44, abs=0.02)
    assert main(["gasdyn", "choke", "--l-over-d", "8.07", "--reynolds", "5e5"]) == 0
    out = capsys.readouterr().out
    assert "iteration" in out and "Mach" in out


def test_choke_freestream(capsys: pytest.CaptureFixture[str]) -> None:
    d = run_json(capsys, "choke", "--l-over-d", "8.07", "--bore-diameter-m", "0.00944")
    assert d["mach"] == pytest.approx(1.44, abs=0.01)
    assert d["reynolds"] == pytest.approx(2.1991e5 * d["mach"], rel=1e-3)


def test_atmosphere(capsys: pytest.CaptureFixture[str]) -> None:
    d = run_json(capsys, "atmosphere", "--altitude-m", "0")
    assert d["pressure_Pa"] == 101325.0 and d["temperature_K"] == 288.15
    assert main(["gasdyn", "atmosphere", "--altitude-m", "11000"]) == 0
    out = capsys.readouterr().out
    assert "Pa" in out and "kg/m^3" in out and "216.774" in out


@pytest.mark.parametrize(
    ("argv", "field"),
    [
        (["normal-shock", "--mach", "0.5"], "mach"),
        (["normal-shock", "--mach", "abc"], "mach"),
        (["normal-shock", "--mach", "2", "--gamma", "1"], "gamma"),
        (["start", "--area-ratio", "0.5"], "area_ratio"),
        (["start", "--mach", "0.9"], "mach"),
        (["choke", "--fld", "-1"], "fld"),
        (["choke", "--fld", "0.9"], "fld"),
        (["choke", "--l-over-d", "0", "--reynolds", "5e5"], "l_over_d"),
        (["choke", "--l-over-d", "8", "--reynolds", "-5"], "reynolds"),
        (["choke", "--l-over-d", "8", "--reynolds", "5e5", "--iterations", "x"], "iterations"),
        (["choke", "--l-over-d", "8"], "reynolds"),
        (["atmosphere", "--altitude-m", "-10"], "altitude_m"),
        (["atmosphere", "--altitude-m", "90000"], "altitude_m"),
    ],
)
def test_bad_input_one_line_exit_2(
    capsys: pytest.CaptureFixture[str], argv: list[str], field: str
) -> None:
    assert main(["gasdyn", *argv]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.splitlines()
    assert len(lines) == 1
    flag = "--" + field.replace("_", "-")  # refused while parsing (its kind) or after
    assert lines[0].startswith((f"obturator: error: {field}:", f"obturator: error: {flag}:"))


def test_console_script_subprocess() -> None:
    proc = subprocess.run(
        [sys.executable, "-m", "obturator", "gasdyn", "normal-shock", "--mach", "2", "--json"],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["pressure_ratio"] == pytest.approx(4.5)
    bad = subprocess.run(
        [sys.executable, "-m", "obturator", "gasdyn", "atmosphere", "--altitude-m", "1e6"],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert bad.returncode == 2
    assert bad.stderr.startswith("obturator: error: --altitude-m:")


def _strict(text: str):
    def reject(token: str):
        raise ValueError(f"non-standard JSON token {token}")

    return json.loads(text, parse_constant=reject)


@pytest.mark.parametrize(
    "args",
    [
        ["gasdyn", "normal-shock", "--mach", "3", "--json"],
        ["gasdyn", "start", "--mach", "2.5", "--json"],
        ["gasdyn", "atmosphere", "--altitude-m", "86000", "--json"],
        ["simulate", "--spin-rate", "450", "--json", "--no-check"],
    ],
)
def test_json_outputs_are_strict_rfc8259(args, capsys):
    # RFC 8259 has no NaN/Infinity: every --json output parses with those rejected
    assert main(args) == 0
    _strict(capsys.readouterr().out)


def test_huge_mach_is_rejected_not_printed_as_nan(capsys):
    assert main(["gasdyn", "normal-shock", "--mach", "1e308", "--json"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("obturator: error: mach:") and err.count("\n") == 1


def test_study_json_outputs_are_strict_and_echo_settings(tmp_path, capsys):
    data = str(tmp_path / "x.nc")
    cases = [
        ["sweep", "--spin-rate", "300,400", "--mu-s", "0.5", "--out", data, "--json",
         "--workers", "1", "--no-progress"],
        ["montecarlo", "--spin-rate", "300", "--vary", "mu_s=uniform:0.5,0.6", "--samples", "3",
         "--json", "--workers", "1", "--no-progress"],
    ]  # fmt: skip
    for args in cases:
        assert main(args) == 0, args
        out = _strict(capsys.readouterr().out)
        settings = out["settings"]
        text = json.dumps(settings)
        assert "obturator_version" in text and "rtol" in text and "0.5" in text
