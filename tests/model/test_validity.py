"""Inputs far outside the validated range: a one-line warning with the expected cost,
and a step limit that names its cause and the fix (issue: ``--spin-rate "150 deg/s"``,
2.6 rad/s, ran 11 minutes without a word and then failed with a bare step limit)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from obturator import SolverOptions
from obturator.calibration import load_thesis_data
from obturator.cli import main
from obturator.cli import simulate as simulate_cli
from obturator.errors import InputError
from obturator.model.cases import case_from_settings, flight_case, rig_case
from obturator.model.validity import (
    RIG_RUN_SPINS,
    holding_jet_moment,
    holding_moment,
    outside_validated_data,
    outside_validated_range,
    rig_run_holding_moments,
    seat_friction_moment,
)


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


# -- release angle, holding moment and ball against the Appendix B runs (issue 47) --


def _table1_inertias(hole: float) -> tuple[float, float]:
    """C and A of the bored ball from the thesis's closed forms (Eqs. 10b, 11), written
    here: napkin ring of half-height sqrt(R^2 - r^2) and mass properties by shells."""
    from scipy.integrate import quad

    R, rho = 7.899e-3, 7669.6
    u = R * R - hole * hole
    c = 4 * math.pi * rho * (hole**2 / 5 + 2 * R * R / 15) * u**1.5

    def a_shell(r: float) -> float:  # shell of radius r, half-height h: I about a diameter
        h = math.sqrt(R * R - r * r)
        return 2 * math.pi * r * rho * (2 * h * r * r / 2 + 2 * h**3 / 3)

    a = quad(a_shell, hole, R, epsabs=0.0, epsrel=1e-12)[0]
    return c, a


def test_holding_moment_closed_form_and_the_audits_numbers():
    case = case_from_settings(
        {"spin_rate": 200.0, "theta0_deg": 70.0, "hole_radius": 5.58e-3, "mu_s": 0.5473}
    )
    c, a = _table1_inertias(5.58e-3)
    t = math.radians(70.0)
    expect = 200.0**2 * (c - a) * math.sin(t) * math.cos(t)
    assert holding_moment(case) == pytest.approx(expect, rel=1e-9)
    # the audit: 1.1e-3 N m, 4.7 x the seat's mu_s W R_s, ~3.5 x the holding jet's bound
    assert holding_moment(case) == pytest.approx(1.1e-3, rel=0.03)
    w = case.ball.weight  # the load follows the new ball: W = rho g V
    assert seat_friction_moment(case) == pytest.approx(0.5473 * w * 7.899e-3, rel=1e-12)
    assert holding_moment(case) / seat_friction_moment(case) == pytest.approx(4.7, abs=0.05)
    assert holding_jet_moment(case) == pytest.approx(0.04 * 7.899e-3, rel=1e-12)
    assert holding_moment(case) / holding_jet_moment(case) == pytest.approx(3.5, abs=0.1)
    # the 54 runs needed 0.08-2.5 x the seat's moment at the calibrated mu_s
    lo, hi = rig_run_holding_moments(0.5473)
    assert (lo, hi) == pytest.approx((0.076, 2.51), abs=0.005)


@pytest.mark.parametrize(
    ("settings", "fragments"),
    [
        ({"spin_rate": 300.0}, None),
        ({"spin_rate": 300.0, "theta0_deg": 87.0}, None),
        ({"spin_rate": 600.0}, ["spin_rate 600 rad/s is outside the runs' 77.8-446.1"]),
        ({"spin_rate": 200.0, "theta0_deg": 80.0}, ["theta_0 80 deg", "86.25-88.25"]),
        ({"spin_rate": 200.0, "hole_radius": 3.75e-3}, ["r_s 3.75 mm (runs 4.72)"]),
        ({"spin_rate": 200.0, "theta0_deg": 70.0}, ["holding moment", "the runs needed"]),
    ],
)
def test_outside_validated_data(settings, fragments):
    note = outside_validated_data(case_from_settings(settings))
    if fragments is None:
        assert note is None
        return
    assert note is not None
    for f in fragments:
        assert f in note
    assert outside_validated_data(flight_case()) is None  # flight: not the rig's release


def test_simulate_warns_one_line_for_an_unholdable_release(capsys):
    argv = ["simulate", "--case", "spin-rig", "--spin-rate", "200", "--theta0-deg", "70"]
    assert main([*argv, "--no-check", "--t-max", "1"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    line = err[0]
    assert line.startswith("obturator: warning: outside the validated data: ")
    assert "holding moment" in line and "N m" in line
    assert "the runs needed 2.6e-05-0.00087 N m" in line


def test_simulate_takes_the_ball_dimensions(capsys):
    argv = ["simulate", "--spin-rate", "300", "--theta0-deg", "87.25", "--no-check", "--json"]
    assert main([*argv, "--hole-radius", "5.58mm", "--density", "7.8 g/cm^3"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["inputs"]["hole_radius_m"] == pytest.approx(5.58e-3)
    assert out["inputs"]["density_kg_m3"] == pytest.approx(7800.0)
    assert main(["simulate", "--hole-radius", "6 mm", "--no-check"]) == 2  # > R_s/sqrt(2)
    assert "--hole-radius" in capsys.readouterr().err


def test_sweep_warns_once_for_points_outside_the_data(tmp_path, capsys):
    out = str(tmp_path / "s.nc")
    argv = ["sweep", "--case", "spin-rig", "--spin-rate", "300:600:2", "--out", out]
    assert main([*argv, "--workers", "1", "--no-progress", "--t-max", "2"]) == 0
    err = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert len(err) == 1, err
    assert "1 of 2 points lie outside the validated data" in err[0]
    assert "spin_rate 600 rad/s is outside the runs' 77.8-446.1 rad/s" in err[0]


def test_montecarlo_warns_for_samples_outside_the_data(tmp_path, capsys):
    out = str(tmp_path / "m.nc")
    argv = ["montecarlo", "--case", "spin-rig", "--spin-rate", "300", "--samples", "4"]
    argv += ["--vary", "theta0_deg=uniform:80,82", "--out", out, "--seed", "1"]
    assert main([*argv, "--workers", "1", "--no-progress", "--t-max", "2"]) == 0
    err = [line for line in capsys.readouterr().err.splitlines() if "warning" in line]
    assert len(err) == 1, err
    assert "4 of 4 points lie outside the validated data" in err[0] and "86.25-88.25" in err[0]


def test_sweep_dataset_carries_the_note_computed_while_workers_run(monkeypatch):
    """The note is the same whether the parent computes it while pool workers run (the
    job's ``meanwhile``) or after an in-process run; beyond VALIDITY_POINTS it is taken on
    evenly spaced points and says so. Expected counts from Appendix B's 77.8-446.1 rad/s:
    of 250, 350, 450, 550 rad/s the last two lie outside."""
    from obturator.runs import Runner
    from obturator.sweeps import SweepSpec, points
    from obturator.sweeps.sweep import execute_sweep

    spec = SweepSpec("spin-rig", {"spin_rate": [250.0, 350.0, 450.0, 550.0]}, t_max=2.0)
    notes = [
        execute_sweep(spec, Runner(workers=w, progress=False)).dataset.attrs[
            "outside_validated_data"
        ]
        for w in (1, 2)
    ]
    assert notes[0] == notes[1] and notes[0].startswith("2 of 4 points lie outside")
    monkeypatch.setattr(points, "VALIDITY_POINTS", 3)  # indices 0, 1, 3: 250, 350, 550 rad/s
    run = execute_sweep(spec, Runner(workers=1, progress=False))
    note = run.dataset.attrs["outside_validated_data"]
    assert note.startswith("1 of 3 points") and note.endswith("(3 evenly spaced points checked)")
    flight = SweepSpec("flight", {"spin_rate": [300.0, 600.0]}, t_max=2.0)
    assert (
        execute_sweep(flight, Runner(workers=1, progress=False)).dataset.attrs[
            "outside_validated_data"
        ]
        == ""
    )


def test_the_notes_respun_cases_are_the_cases_built_one_by_one():
    """The validity note builds one case per group of rows that differ in the spin alone
    and re-spins it; the reference is every row's case built on its own (the sweep's
    own path), invalid rows included: a release rate beyond the spin (a check that
    depends on the spin), with the group's first row invalid and later ones valid."""
    import itertools

    from obturator.errors import InputError
    from obturator.model.validity import outside_validated_data_many
    from obturator.sweeps import SweepSpec, points

    spec = SweepSpec(
        "spin-rig",
        {"spin_rate": [90.0, 460.0], "theta0_deg": [86.0, 89.0], "theta_dot0": [0.0, 50.0]},
        {"mu_s": 0.5473},
    )
    values = {"spin_rate": [40.0, 90.0, 300.0, 460.0], "theta0_deg": [86.0, 87.25, 89.0]}
    values["theta_dot0"] = [50.0, 0.0]
    rows = np.array(list(itertools.product(*(values[n] for n in spec.dims))))
    rows = rows[np.argsort(rows[:, spec.dims.index("spin_rate")], kind="stable")]
    respun = points._respun_cases(spec, spec.dims, rows)
    one_by_one = points.rows_to_cases(spec, spec.dims, rows)
    assert len(respun) == len(one_by_one) == 24
    n_invalid = 0
    for a, b in zip(respun, one_by_one, strict=True):
        assert isinstance(a, InputError) == isinstance(b, InputError)
        n_invalid += isinstance(b, InputError)
        if not isinstance(b, InputError):
            assert a == b
    assert n_invalid == 3  # 40 rad/s with theta_dot0 = 50 rad/s, at each theta_0
    assert outside_validated_data_many(respun) == outside_validated_data_many(one_by_one)
    note = points.validity_note(spec, spec.dims, spec.rows, spec.n_points)
    assert note == outside_validated_data_many(
        points.rows_to_cases(spec, spec.dims, spec.rows(np.arange(spec.n_points)))
    )
