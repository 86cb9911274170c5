"""One schema for the run files of calibrate, validate and design-experiment (issue 46).

Every column is known or refused (naming the closest known name and the allowed list),
numbers are plain decimals, a run's columns agree with each other and with a ball that
can open, a command refuses a known column it does not use, and a fit the runs cannot
identify is refused, never reported as a success.

References: the opening angle beta_s = asin(r_s / R_s) (Eq. 6) with Table 1's
r_s = 4.72 mm and R_s = 7.899 mm, 36.69 deg; the intermediate value theorem for the
time to an intermediate angle (below the run's t_cr).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from obturator.calibration.data import CASE_COLUMNS, SpinRigData, load_spin_rig_csv
from obturator.calibration.exact import fit_exact
from obturator.cli import main
from obturator.errors import InputError

BETA_S_DEG = math.degrees(math.asin(4.72 / 7.899))  # Table 1, Eq. 6: 36.69 deg


def _csv(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "runs.csv"
    p.write_text(text)
    return p


@pytest.mark.parametrize("header", ["theta0 (deg)", "theta0 [deg]", "theta0_deg", "theta0"])
def test_theta0_spellings_are_read(tmp_path, header):
    # issue 46: "theta0 (deg)" was dropped without a word and the fit used Table 1's
    d = load_spin_rig_csv(_csv(tmp_path, f"spin_rate_rad_s,t_cr_s,{header}\n446,0.28,86\n"))
    assert d.settings["theta0_deg"].tolist() == [86.0]


def test_theta0_in_radians_converts(tmp_path):
    d = load_spin_rig_csv(_csv(tmp_path, "spin_rate_rad_s,t_cr_s,theta0 (rad)\n446,0.28,1.5\n"))
    assert d.settings["theta0_deg"][0] == pytest.approx(math.degrees(1.5), rel=1e-12)


@pytest.mark.parametrize(
    ("header", "closest"),
    [
        ("theta_0", "theta0_deg"),
        ("Theta0 deg", "theta0_deg"),
        ("t_cr", "t_cr_s"),
        ("hole radius (mm)", "hole_radius_mm"),
        ("stared", "starred"),
    ],
)
def test_unknown_columns_are_refused(tmp_path, capsys, header, closest):
    p = _csv(tmp_path, f"spin_rate_rad_s,t_cr_s,{header}\n446,0.28,86\n")
    with pytest.raises(InputError) as exc:
        load_spin_rig_csv(p)
    msg = str(exc.value)
    assert msg.startswith(f"{header}: ") and f"unknown column {header!r}" in msg
    assert f"closest known: {closest!r}" in msg and "allowed: t_cr_s" in msg
    assert main(["calibrate", str(p)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "unknown column" in err[0]


def test_comment_column_is_free_text(tmp_path):
    d = load_spin_rig_csv(_csv(tmp_path, "spin_rate_rad_s,t_cr_s,comment\n446,0.28,hot day\n"))
    assert d.opening_time.tolist() == [0.28]


@pytest.mark.parametrize("cell", ["3_00", "inf", "nan", "0x1f", "\uff13\uff10\uff10", "1e", "."])
@pytest.mark.parametrize("column", ["spin_rate_rad_s", "theta0_deg"])
def test_numbers_are_plain_decimals(tmp_path, cell, column):
    # float() reads 3_00 as 300 and fullwidth digits as digits; a data file may not
    row = {"spin_rate_rad_s": f"{cell},0.28,86", "theta0_deg": f"446,0.28,{cell}"}[column]
    p = _csv(tmp_path, f"spin_rate_rad_s,t_cr_s,theta0_deg\n{row}\n")
    with pytest.raises(InputError, match=f"^{column}: .*line 2: .*not a number"):
        load_spin_rig_csv(p)


@pytest.mark.parametrize("cell", ["300", "+300", "3e2", "300.", ".3e3", "3.00E+02"])
def test_plain_decimals_are_read(tmp_path, cell):
    d = load_spin_rig_csv(_csv(tmp_path, f"spin_rate_rad_s,t_cr_s\n{cell},0.28\n"))
    assert d.spin_rate.tolist() == [300.0]


@pytest.mark.parametrize(
    ("row", "column", "what"),
    [
        # issue 46: t_measured 5 s for a run that opens at 0.276 s
        ("446,0.276,60,5", "t_measured", "5 s is not below the run's t_cr_s = 0.276 s"),
        ("446,0.276,60,0.276", "t_measured", "0.276 s is not below the run's t_cr_s"),
        # below the opening angle beta_s = 36.69 deg: the run has ended there
        ("446,0.276,30,0.1", "theta_measured", "30 deg is not between the run's opening angle"),
        ("446,0.276,87.25,0.1", "theta_measured", "87.25 deg is not between"),
    ],
)
def test_measured_angle_agrees_with_its_run(tmp_path, row, column, what):
    p = _csv(tmp_path, f"spin_rate_rad_s,t_cr_s,theta_measured_deg,t_measured_s\n{row}\n")
    with pytest.raises(InputError, match=f"^{column}: .*line 2: {what}"):
        load_spin_rig_csv(p)


def test_opening_angle_of_the_check_is_eq_6(tmp_path):
    head = "spin_rate_rad_s,t_cr_s,theta_measured_deg,t_measured_s\n"
    above = load_spin_rig_csv(_csv(tmp_path, head + f"446,0.276,{BETA_S_DEG + 1e-3},0.27\n"))
    assert above.settings["theta_measured_deg"][0] == pytest.approx(BETA_S_DEG + 1e-3)
    with pytest.raises(InputError, match="opening angle beta_s = 36.69 deg"):
        load_spin_rig_csv(_csv(tmp_path, head + f"446,0.276,{BETA_S_DEG - 1e-3},0.27\n"))


def test_runs_that_cannot_open_are_named(tmp_path, capsys):
    p = _csv(
        tmp_path,
        "spin_rate_rad_s,t_cr_s,theta0_deg,hole_radius_mm\n"
        "446,0.28,90,4.72\n300,0.3,87,4.72\n200,0.2,30,4.72\n",
    )
    assert main(["validate", "--data", str(p)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("obturator: error: theta0: ")
    assert "2 run(s) where the ball cannot open" in err[0]
    assert "line 2 (theta0 = 90 deg" in err[0] and "line 4 (theta0 = 30 deg" in err[0]


def test_a_hole_below_the_case_bound_is_refused(tmp_path):
    # 0 mm and 0.1 mm: inside the geometry's [0, R_s/sqrt 2), below a case's R_s/10
    for mm in ("0", "0.1"):
        p = _csv(tmp_path, f"spin_rate_rad_s,t_cr_s,hole_radius_mm\n446,0.28,{mm}\n")
        with pytest.raises(InputError, match="^hole_radius_mm: .*outside the allowed range"):
            load_spin_rig_csv(p)


def test_a_command_refuses_columns_it_does_not_use(tmp_path, capsys):
    p = _csv(
        tmp_path,
        "spin_rate_rad_s,t_cr_s,theta_measured_deg,t_measured_s\n446,0.28,60,0.1\n300,0.3,,\n",
    )
    assert load_spin_rig_csv(p).settings["t_measured"][0] == 0.1  # validate reads them
    with pytest.raises(InputError, match="^theta_measured_deg: .*not used by this command"):
        load_spin_rig_csv(p, columns=CASE_COLUMNS)
    for argv in (["calibrate", str(p)], ["design-experiment", "--data", str(p)]):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "not used by this command" in err[0]


def _help(capsys: pytest.CaptureFixture[str], command: str) -> str:
    try:
        assert main([command, "--help"]) == 0
    except SystemExit as exc:
        assert exc.code == 0
    return " ".join(capsys.readouterr().out.split())


def test_help_lists_only_the_columns_a_command_uses(capsys):
    text = _help(capsys, "calibrate")
    assert "theta0" in text and "ball_mass" in text
    assert "theta_measured" not in text and "t_measured" not in text
    assert "measured angle" in _help(capsys, "validate")


# --------------------------------------------------------------------------- fits


def _two_runs(**settings: list[float]) -> SpinRigData:
    return SpinRigData(
        spin_rate=np.array([300.0, 446.0]),
        opening_time=np.array([0.25, 0.28]),
        starred=np.array([False, False]),
        settings={k: np.array(v) for k, v in settings.items()},
    )


def test_a_fit_with_every_run_censored_is_refused():
    """theta_0 = 90 deg is the equilibrium with the hole square to the spin (Eq. 5 has
    theta_dot = 0 there): no run opens, and the fit used to report mu_s at its start
    with an error of NaN and success = True."""
    with pytest.raises(InputError, match="^data: the model opens none of the 2 fitted runs"):
        fit_exact(_two_runs(), theta0_deg=90.0, t_max=0.05, bootstrap=0)


def test_a_parameter_without_information_is_refused():
    """With the constant law (the thesis's one mu, Eq. 61) t_cr does not depend on the
    slip-speed law's reference speed: its Jacobian column is exactly zero."""
    with pytest.raises(InputError, match="^fit: slip_speed: the 2 fitted runs carry no"):
        fit_exact(_two_runs(), fit=("mu_s", "slip_speed"), t_max=1.0, bootstrap=0)
