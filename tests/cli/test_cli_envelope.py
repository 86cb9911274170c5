"""Command line: trajectory, envelope, probability, sensitivity, optimize."""

from __future__ import annotations

import json

import pytest
import xarray as xr

from obturator.cli import main

FAST = ["--rtol", "1e-6", "--atol", "1e-8", "--workers", "1", "--no-progress"]


def run_json(capsys, argv):
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


def test_trajectory(capsys, tmp_path):
    out = run_json(capsys, ["trajectory", "--mach", "2", "--altitude-m", "1 km", "--json"])
    assert out["status_coupled"] == "opened"
    assert out["convergence_coupled"]["converged"] and out["convergence_constant"]["converged"]
    assert out["relative_difference"] > 0
    fig, nc = tmp_path / "t.png", tmp_path / "t.nc"
    assert main(["trajectory", "--figure", str(fig), "--out", str(nc), "--t-max", "0.1"]) == 0
    text = capsys.readouterr().out
    assert "t_cr coupled" in text and fig.stat().st_size > 0
    assert "mach" in xr.open_dataset(nc).data_vars


def test_envelope_writes_netcdf_and_figure(capsys, tmp_path):
    nc, fig = tmp_path / "env.nc", tmp_path / "env.png"
    argv = ["envelope", "--mach", "1.5:3:2", "--altitude-m", "0,10000", "--out", str(nc)]
    out = run_json(capsys, [*argv, "--figure", str(fig), "--no-convergence-check", *FAST, "--json"])
    assert out["points"] == 4 and out["computed"] == 4 and out["coupled_opened"] == 4
    ds = xr.open_dataset(nc)
    assert ds["t_cr_coupled"].shape == (2, 2) and ds.attrs["requirement_s"] == 0.1
    assert fig.stat().st_size > 0
    assert not (tmp_path / "env.nc.partial.jsonl").exists()
    # the plain-text table names both loads
    assert main([*argv, "--no-convergence-check", *FAST]) == 0
    assert "coupled (constant load)" in capsys.readouterr().out


def test_config_file(capsys, tmp_path):
    cfg = tmp_path / "run.toml"
    cfg.write_text('mu_s = 0.3\n[ball]\ndensity = "7.8 g/cm^3"\n[projectile]\nroll_damping = 0\n')
    out = run_json(capsys, ["trajectory", "--config", str(cfg), "--json", "--t-max", "0.1"])
    assert out["t_cr_coupled_s"] > 0.0196  # lower friction and a denser ball open later
    cfg.write_text("[nonsense]\nx = 1\n")
    assert main(["trajectory", "--config", str(cfg)]) == 2


@pytest.mark.parametrize(
    ("argv", "field"),
    [
        (["envelope", "--mach", "0.5:2:3", "--altitude-m", "0"], "mach"),
        (["envelope", "--mach", "2", "--altitude-m", "0", "--mu-s", "-1"], "mu_s"),
        (["trajectory", "--hole-radius", "6 mm"], "hole_radius"),
        (["trajectory", "--altitude-m", "30 km"], "altitude_m"),
        (["probability", "--vary", "mu_s=weird:1"], "mu_s"),
        (["optimize", "--objective", "mean"], "objective"),
    ],
)
def test_errors_are_one_line(capsys, argv, field):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    flag = "--" + field.replace("_", "-")  # refused while parsing (its kind) or after
    assert len(err) == 1 and err[0].startswith(
        (f"obturator: error: {field}", f"obturator: error: {flag}")
    )


def test_probability_both_methods(capsys, tmp_path):
    out = run_json(
        capsys,
        [
            "probability", "--mach", "1.75", "--altitude-m", "7000", "--method", "both",
            "--vary", "mu_s=lognormal:0.35,0.1", "--samples", "200", "--stage-samples", "50",
            "--final-samples", "100", "--load", "constant", "--no-convergence-check",
            "--out", str(tmp_path / "p.nc"), *FAST, "--json",
        ],
    )  # fmt: skip
    pt = out["points"][0]
    assert 0.1 < pt["is"]["probability"] < 0.7 and 0.1 < pt["mc"]["probability"] < 0.7
    assert abs(pt["difference_in_std_errors"]) < 3
    assert xr.open_dataset(tmp_path / "p.nc")["probability_is"].shape == (1, 1)


def test_sensitivity_and_optimize(capsys, tmp_path):
    out = run_json(
        capsys,
        [
            "sensitivity", "--samples", "8", "--resamples", "20", "--load", "constant",
            "--no-convergence-check", "--figure", str(tmp_path / "s.png"), *FAST, "--json",
        ],
    )  # fmt: skip
    assert out["input"][0] == "mu_s" and out["ST"][0] > 0.5
    out = run_json(
        capsys,
        [
            "optimize", "--mach", "2", "--altitude-m", "5000", "--variables", "mu_s,gap",
            "--maxiter", "2", "--popsize", "3", "--load", "constant", "--pareto", "2",
            "--figure", str(tmp_path / "p.png"), "--out", str(tmp_path / "o.nc"), *FAST, "--json",
        ],
    )  # fmt: skip
    assert out["optimum"]["mu_s"] == pytest.approx(0.45, rel=1e-3)
    assert out["improvement"] > 0 and out["pareto"]["degenerate"] in (True, False)
    assert xr.open_dataset(tmp_path / "o.nc")["t_cr_optimum"].size == 1
