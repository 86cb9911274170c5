"""A user's runs with their own settings (issue 29, item 3): the optional CSV columns
theta0, hole_radius, density, ball_mass, theta_measured and t_measured, checked like
every input and used per run by the model."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from obturator import rig_case
from obturator.calibration.data import load_spin_rig_csv
from obturator.calibration.rig_model import apply_run_settings, model_opening_times
from obturator.cli import main
from obturator.errors import InputError
from obturator.model.cases import table1_ball
from obturator.model.geometry import STANDARD_GRAVITY
from obturator.solve import opening_times

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "rig_runs_settings.csv"
_HEAD = "spin_rate_rad_s,t_cr_s"


def _csv(tmp_path: Path, header: str, *rows: str) -> Path:
    p = tmp_path / "runs.csv"
    p.write_text("\n".join([header, *rows]) + "\n")
    return p


def test_units_from_the_header_and_empty_cells(tmp_path):
    p = _csv(
        tmp_path,
        f"{_HEAD},theta0 [deg],hole_radius_mm,density [g/cm^3],ball_mass_g,"
        "theta_measured_deg,t_measured [ms]",
        "200,0.2,87,4.72,7.6696,8.1,60,120",
        "300,0.3,,,,,,",
    )
    d = load_spin_rig_csv(p)
    s = d.settings
    assert s["theta0_deg"][0] == 87.0 and math.isnan(s["theta0_deg"][1])
    assert s["hole_radius"][0] == pytest.approx(4.72e-3)
    assert s["density"][0] == pytest.approx(7669.6)
    assert s["ball_mass"][0] == pytest.approx(8.1e-3)
    assert s["t_measured"][0] == pytest.approx(0.12)
    assert d.run_settings()[1] == ()
    assert dict(d.run_settings()[0])["theta_measured_deg"] == 60.0
    # a bare name is in the documented unit (hole radius: mm)
    bare = load_spin_rig_csv(_csv(tmp_path, f"{_HEAD},hole_radius", "200,0.2,3.75"))
    assert bare.settings["hole_radius"][0] == pytest.approx(3.75e-3)
    assert len(d.select([1])) == 1 and d.select([1]).run_settings() == [()]


@pytest.mark.parametrize(
    "header, row, column, what",
    [
        (f"{_HEAD},theta0_furlong", "200,0.2,87", "theta0_furlong", "unit"),
        (f"{_HEAD},hole_radius [kg]", "200,0.2,4", "hole_radius [kg]", "unit"),
        (f"{_HEAD},theta0_deg", "200,0.2,95", "theta0_deg", "outside the allowed range"),
        (f"{_HEAD},hole_radius_mm", "200,0.2,6", "hole_radius_mm", "outside the allowed range"),
        (f"{_HEAD},density_kg_m3", "200,0.2,-1", "density_kg_m3", "outside the allowed range"),
        (f"{_HEAD},ball_mass_g", "200,0.2,abc", "ball_mass_g", "not a number"),
        (f"{_HEAD},theta_measured_deg", "200,0.2,60", "t_measured", "come together"),
        (
            f"{_HEAD},theta_measured_deg,t_measured_s",
            "200,0.2,88,0.1",
            "theta_measured",
            "not between",
        ),
        ("spin_rate_rad_s,theta0_deg", "200,87", "t_cr_s", "missing column"),
    ],
)
@pytest.mark.parametrize("command", ["calibrate", "validate"])
def test_bad_column_is_one_line_exit_2(tmp_path, capsys, header, row, column, what, command):
    p = _csv(tmp_path, header, row, "300,0.3" + ",87" * (header.count(",") - 1))
    argv = (
        ["calibrate", str(p), "--bootstrap", "0"]
        if command == "calibrate"
        else ["validate", "--data", str(p), "--models", "mu"]
    )
    measured = "theta_measured" in header
    if command == "calibrate" and measured:
        # calibrate fits t_cr only: the intermediate-angle columns are refused (issue 46)
        column, what = header.split(",")[2], "not used by this command"
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith(f"obturator: error: {column}: ")
    assert what in err[0] and ", line " in err[0]


def test_run_settings_reach_the_case():
    """Hole radius and density make the run's ball; the mass sets the load W = m g (and
    the density when it is the only one given); a run's theta_0 takes a fitted offset."""
    case = apply_run_settings(rig_case, 200.0, {"hole_radius": 3.75e-3, "density": 6000.0})
    assert case.ball == table1_ball(hole_radius=3.75e-3, density=6000.0)
    assert case.torque.friction.weight == pytest.approx(case.ball.weight)
    m = 9e-3
    heavy = apply_run_settings(rig_case, 200.0, {"ball_mass": m})
    assert heavy.torque.friction.weight == pytest.approx(m * STANDARD_GRAVITY)
    assert heavy.ball.mass == pytest.approx(m, rel=1e-12)
    tilted = apply_run_settings(rig_case, 200.0, {"theta0_deg": 86.0}, theta0_deg=85.25)
    assert math.degrees(tilted.theta0) == pytest.approx(86.0 - 2.0)
    event = apply_run_settings(rig_case, 200.0, {"theta_cr_deg": 60.0})
    assert event.theta_cr == pytest.approx(math.radians(60.0))
    # the calibration's model takes them per run
    w = np.array([200.0, 200.0])
    runs = [(), (("density", 6000.0), ("hole_radius", 3.75e-3))]
    t = model_opening_times(w, mu_s=0.55, run_settings=runs, t_max=5.0)
    ref = opening_times(
        [apply_run_settings(rig_case, 200.0, dict(r), mu_s=0.55, t_max=5.0) for r in runs]
    )[0]
    assert t == pytest.approx(ref, rel=1e-12)
    assert t[0] != pytest.approx(t[1], rel=1e-3)


def _without_angles(tmp_path: Path) -> Path:
    """The example without its intermediate-angle columns (calibrate fits t_cr only)."""
    rows = [
        line.split(",")[:-2] if not line.startswith("#") else [line]
        for line in EXAMPLE.read_text().splitlines()
    ]
    assert all(r[0].startswith("#") or len(r) == 6 for r in rows)
    p = tmp_path / "runs.csv"
    p.write_text("\n".join(",".join(r) for r in rows) + "\n")
    return p


def test_example_file_calibrates_and_validates(capsys, tmp_path):
    """The shipped example (synthetic, mu_s = 0.55, 4 ms noise) through both commands."""
    assert main(["calibrate", str(EXAMPLE), "--bootstrap", "0"]) == 2
    assert "not used by this command" in capsys.readouterr().err
    cal = _without_angles(tmp_path)
    assert main(["calibrate", str(cal), "--bootstrap", "0", "--json"]) == 0
    fit = json.loads(capsys.readouterr().out)
    mu = fit["parameters"]["mu_s"]["value"]
    assert mu == pytest.approx(0.55, abs=0.02)
    argv = ["validate", "--data", str(EXAMPLE), "--models", "mu", "--no-profile", "--json"]
    assert main([*argv, "--no-progress"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert res["settings"]["n_runs"] == 14
    assert res["settings"]["n_angle_observations"] == 3
    assert res["models"][0]["params"]["mu_s"]["value"] == pytest.approx(0.55, abs=0.02)
    with pytest.raises(InputError):
        load_spin_rig_csv(EXAMPLE.parent / "missing.csv")


def test_calibrate_recovers_the_example_campaigns_mu_s(capsys, tmp_path):
    """examples/rig_runs_settings.csv was written by examples/make_rig_runs_settings.py
    from the exact model at mu_s = 0.55 (each run's own ball, load and theta_0) plus 4 ms
    noise: the fit must bracket 0.55 with its 95 % interval, an inverse-problem check of
    how the per-run settings reach the model."""
    rc = main(["calibrate", str(_without_angles(tmp_path)), "--bootstrap", "0", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0
    lo, hi = out["parameters"]["mu_s"]["ci95"]
    assert lo < 0.55 < hi and hi - lo < 0.02
