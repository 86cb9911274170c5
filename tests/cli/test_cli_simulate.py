"""``obturator simulate`` end to end, config files with units, and bad input."""

import json
import math
import subprocess
import sys

import pytest

from obturator.cli import main
from obturator.io import load_config
from obturator.units import parse_quantity


def run_json(capsys, *args):
    assert main(["simulate", *args, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


def test_rig_json_has_documented_fields(capsys):
    out = run_json(capsys, "--case", "spin-rig", "--spin-rate", "300", "--mu-s", "0.5473")
    for key in ("t_cr_s", "theta_cr_deg", "spin_rate_rad_s", "mu_s", "torque_model", "status"):
        assert key in out
    assert out["torque_model"] == "thesis"
    assert out["status"] == 1
    assert out["theta_cr_deg"] == pytest.approx(36.694, abs=1e-3)
    assert 0.25 < out["t_cr_s"] < 0.30


def test_flight_case_and_mach_altitude(capsys):
    base = run_json(capsys, "--case", "flight")
    assert base["t_cr_s"] < 0.1
    # a weaker bow shock (lower Mach) presses the ball less: it opens later
    slow = run_json(capsys, "--case", "flight", "--mach", "2", "--altitude-m", "0")
    assert slow["t_cr_s"] > base["t_cr_s"]


def test_quantities_with_units_on_the_command_line(capsys):
    a = run_json(capsys, "--spin-rate", "300", "--rtol", "1e-7")
    b = run_json(capsys, "--spin-rate", f"{300 * 60 / (2 * math.pi)} rpm", "--rtol", "1e-7")
    assert b["spin_rate_rad_s"] == pytest.approx(300.0, rel=1e-12)
    assert b["t_cr_s"] == pytest.approx(a["t_cr_s"], rel=1e-9)


def test_config_file_with_units(tmp_path, capsys):
    cfg = tmp_path / "run.toml"
    cfg.write_text(
        'case = "spin-rig"\nspin_rate = "300 rad/s"\nmu_s = 0.5473\ntheta0 = "87.25 deg"\n'
        '[ball]\nradius = "7.899 mm"\nhole_radius = "0.472 cm"\ndensity = "7669.6 kg/m^3"\n'
        '[rig]\nweight = "0.07987 N"\n'
    )
    s = load_config(cfg)
    assert s["ball_radius"] == pytest.approx(7.899e-3)
    assert s["hole_radius"] == pytest.approx(4.72e-3)
    via_cfg = run_json(capsys, "--config", str(cfg))
    direct = run_json(capsys, "--spin-rate", "300", "--mu-s", "0.5473")
    assert via_cfg["t_cr_s"] == pytest.approx(direct["t_cr_s"], rel=1e-9)
    # flags override the file
    over = run_json(capsys, "--config", str(cfg), "--spin-rate", "450")
    assert over["spin_rate_rad_s"] == 450.0


def test_plot_and_csv_outputs(tmp_path, capsys):
    png, csv = tmp_path / "theta.png", tmp_path / "theta.csv"
    assert main(["simulate", "--spin-rate", "450", "--plot", str(png), "--csv", str(csv)]) == 0
    assert png.stat().st_size > 10_000 and png.read_bytes()[:4] == b"\x89PNG"
    header = csv.read_text().splitlines()[0]
    assert header.startswith("t [s],theta [rad]")
    out = capsys.readouterr().out
    assert "opening time t_cr" in out


@pytest.mark.parametrize(
    ("args", "fragment"),
    [
        (["--theta0-deg", "95"], "--theta0-deg: 95 deg is outside the allowed range (0, 90] deg"),
        (["--theta0-deg", "0"], "--theta0-deg"),
        (["--mu-s", "-0.1"], "--mu-s: -0.1 is outside the allowed range [0, 2]"),
        (["--spin-rate", "-5"], "--spin-rate"),
        (["--spin-rate", "12 kg"], "--spin-rate: '12 kg' cannot be converted to rad/s"),
        (["--spin-rate", "fast"], "--spin-rate:"),
        (["--mach", "0.5", "--case", "flight"], "mach"),
        (["--mach", "3"], "mach: applies to --case flight only"),
        (["--rtol", "2"], "--rtol"),
    ],
)
def test_bad_input_is_one_readable_line(args, fragment, capsys):
    assert main(["simulate", *args]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("obturator: error: ")
    assert len(err.splitlines()) == 1
    assert fragment in err


@pytest.mark.parametrize(
    ("text", "fragment"),
    [
        (
            '[ball]\ndensity = "-7800 kg/m^3"\n',
            "density: -7800 kg/m^3 is outside the allowed range",
        ),
        ('[ball]\nhole_radius = "6 mm"\n', "hole_radius: 0.006 m is outside the allowed range"),
        ('[ball]\nradius = "7.9 kg"\n', "ball.radius: '7.9 kg' cannot be converted to m"),
        ("spin_rate = \n", "malformed TOML"),
        ("colour = 3\n", "colour: unknown key"),
        ("[engine]\nx = 1\n", "unknown section [engine]"),
        ('mu_s = "-1"\n', "mu_s: -1 is outside the allowed range"),
    ],
)
def test_bad_config_files(tmp_path, capsys, text, fragment):
    cfg = tmp_path / "bad.toml"
    cfg.write_text(text)
    assert main(["simulate", "--config", str(cfg)]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("obturator: error: ") and len(err.splitlines()) == 1
    assert fragment in err


def test_missing_config_file(capsys, tmp_path):
    assert main(["simulate", "--config", str(tmp_path / "nope.toml")]) == 2
    assert "No such file" in capsys.readouterr().err


def test_parse_quantity_rpm():
    # 115000 rpm is the thesis's 12042.77 rad/s (p. 52)
    assert parse_quantity("spin_rate", "115000 rpm", "rad/s") == pytest.approx(12042.77, abs=0.01)


def test_console_script_subprocess():
    out = subprocess.run(
        [sys.executable, "-m", "obturator", "simulate", "--spin-rate", "450", "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert json.loads(out.stdout)["status"] == 1
    bad = subprocess.run(
        [sys.executable, "-m", "obturator", "simulate", "--mu-s", "-1"],
        capture_output=True,
        text=True,
    )
    assert bad.returncode == 2
    assert bad.stderr.strip().splitlines() == [bad.stderr.strip()]
    assert "Traceback" not in bad.stderr


def test_json_reports_a_passing_convergence_check(capsys):
    out = run_json(capsys, "--spin-rate", "300", "--mu-s", "0.5473")
    conv = out["convergence"]
    assert conv["converged"] is True
    assert conv["tolerance_rel_change"] < 1e-3 and conv["width_rel_change"] < 1e-3
    assert conv["t_cr_narrower_width_s"] == pytest.approx(out["t_cr_s"], rel=1e-3)


def test_unconverged_case_is_flagged(capsys, tmp_path):
    # At 78 rad/s the ball spends ~1.7 s near stick; a width of 1e-5 omega_p moves t_cr by
    # ~1 % against width / 10 and against the linear family: the CLI must say so (of the
    # regularised law: the default auto runs 78 rad/s set-valued, with no width).
    args = ["simulate", "--spin-rate", "78", "--mu-s", "0.5473", "--friction-width", "1e-5"]
    config = tmp_path / "regularised.toml"
    config.write_text('[solver]\nmethod = "regularised"\n')
    args += ["--config", str(config)]
    assert main([*args, "--json"]) == 0
    captured = capsys.readouterr()
    conv = json.loads(captured.out)["convergence"]
    assert conv["converged"] is False
    assert conv["width_rel_change"] > 1e-3 and conv["family_rel_change"] > 1e-3
    assert conv["other_family"] == "linear"
    assert "warning: t_cr is not converged" in captured.err


def test_documented_config_examples_run_verbatim(tmp_path, capsys):
    # the two examples in obturator.io's docstring, cut out of it and run as they stand
    import obturator.io

    doc = obturator.io.__doc__
    blocks, current = [], None
    for line in doc.splitlines():
        if line.endswith("::"):
            current = []
            blocks.append(current)
        elif current is not None and (line.startswith("    ") or not line.strip()):
            current.append(line[4:])
        else:
            current = None
    assert len(blocks) == 2
    for k, block in enumerate(blocks):
        path = tmp_path / f"example{k}.toml"
        path.write_text("\n".join(block), encoding="utf-8")
        assert main(["simulate", "--config", str(path), "--json", "--no-check"]) == 0, k
        out = json.loads(capsys.readouterr().out)
        assert out["status"] == 1 and out["t_cr_s"] > 0


def test_mechanism_flags_reach_the_case(capsys):
    # the validation study's mechanisms as simulate options (spin rig only)
    args = ["simulate", "--spin-rate", "100", "--mu-s", "0.75", "--no-check", "--json"]
    mech = ["--speed-law", "strengthening", "--speed-ratio", "0.3", "--slip-speed", "0.12 m/s"]
    mech += ["--theta-dot0", "0.2", "--release-phase", "1 rad"]
    assert main([*args, *mech]) == 0
    inputs = json.loads(capsys.readouterr().out)["inputs"]
    assert inputs["slip_speed_law"] == {"kind": "strengthening", "ratio": 0.3, "speed_m_s": 0.12}
    assert inputs["release_rate_rad_s"] == [0.2, 0.0, 0.0] and inputs["release_phase_rad"] == 1.0
    assert main(["simulate", "--case", "flight", "--speed-law", "weakening", "--no-check"]) == 2
    assert main(["simulate", "--speed-ratio", "0.3", "--no-check"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err[0].startswith("obturator: error: speed_law: applies to --case spin-rig only")
    assert err[1].startswith("obturator: error: speed_law: give the law")
