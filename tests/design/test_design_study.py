"""The design study end to end on a tiny problem: ten synthetic runs, nine candidate
settings, ten campaigns (seconds), through the runner's resume store."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import xarray as xr

from obturator.calibration.data import SpinRigData
from obturator.cli import _json
from obturator.design import Setting, SettingRanges, design_experiment
from obturator.design.plotting import save_design_figure
from obturator.design.surrogate import opening_time_table
from obturator.design.textreport import format_design
from obturator.runs import Runner, study_digest
from obturator.sweeps import write_netcdf

SPINS = (130.0, 150.0, 151.0, 250.0, 251.0, 260.0, 350.0, 351.0, 400.0, 440.0)


@pytest.fixture(scope="module")
def data() -> SpinRigData:
    rows = [Setting(w).to_dict() for w in SPINS]
    task = {"model": "theta0", "values": [{"mu_s": 0.55, "theta0_deg": 84.5}], "settings": rows}
    (t,) = opening_time_table({**task, "t_max": 20.0})
    y = np.array(t) + np.random.default_rng(5).standard_normal(len(SPINS)) * 0.012
    return SpinRigData(
        spin_rate=np.array(SPINS),
        opening_time=y,
        starred=np.zeros(len(SPINS), bool),
        source="synthetic",
    )


def _study(data: SpinRigData, runner: Runner):
    return design_experiment(
        ["mu", "theta0"],
        ranges=SettingRanges(
            spin_rate=(150.0, 300.0),
            theta0_deg=(80.0, 89.0),
            n_spin=2,
            n_theta0=2,
            n_hole=1,
            n_density=1,
        ),
        n_runs=(2, 3),
        campaigns=10,
        seed=3,
        data=data,
        runner=runner,
        naive_runs=(3, 6),
    )


def test_design_end_to_end_and_resume(data, tmp_path):
    out = tmp_path / "design.nc"
    runner = Runner(workers=1, store=out)
    runner.open(study_digest({"test": "design"}))
    res = _study(data, runner)
    runner.close()
    assert res.models == ("mu", "theta0")
    # 3 spins x 3 release angles, less those the rig cannot hold: at 300 rad/s the ball
    # held at 80 deg needs 1.4e-3 N m, above the 8.4e-4 N m the 440 rad/s run needed
    grid = [i for i, s in enumerate(res.settings) if s.spin_rate in (150.0, 200.0, 300.0)]
    infeasible = [i for i in grid if not res.feasibility[i].feasible]
    assert len(grid) == 9 and infeasible
    assert int(res.candidate_mask.sum()) == 9 - len(infeasible)
    c_minus_a = 3.125e-7 - 2.216e-7  # C - A of the Table 1 ball as the thesis prints them
    for p in res.plans:
        assert len(p.runs) == p.n_runs
        assert all(res.candidate_mask[i] for i in p.runs)
        # never a setting whose holding moment exceeds the rig's bound
        for i in p.runs:
            f, st = res.feasibility[i], res.settings[i]
            th = math.radians(st.theta0_deg)
            hold = st.spin_rate**2 * c_minus_a * math.sin(th) * math.cos(th)
            assert f.holding_moment == pytest.approx(hold, rel=1e-3)
            assert f.holding_moment <= f.bound
        # the design maximises D over the grid; the naive plan's spins lie off it but a
        # plan chosen for D must not be beaten by spreading the measured spins
        assert p.criterion >= p.naive_criterion
        for r in (*p.designed.values(), *p.naive.values()):
            if math.isfinite(r.p_decisive):  # NaN: a truth outside the candidates
                assert 0.0 <= r.p_decisive <= r.p_picked + 1e-12 <= 1.0 + 1e-12
    # the surrogate was checked against exact solves at every campaign draw
    for e in res.surrogate_error.values():
        assert e["n_compared"] > 0 and math.isfinite(e["rms_s"])
    doc = json.loads(_json.dumps(res.to_dict()))
    run = doc["plans"][0]["runs"][0]
    assert {"spin_rate_rad_s", "theta0_set_deg", "hole_radius_m", "density_kg_m3"} <= set(run)
    assert set(run["predicted_t_cr_s"]) == {"mu", "theta0"}
    assert {"holding_moment_N_m", "holding_bound_N_m", "feasible", "extrapolated"} <= set(run)
    # the "neither" check: each candidate's truth and one outside the candidates
    rates = doc["misfit_check"]["p_misfit_exposed_recommended"]
    assert set(rates) == {"mu", "theta0", "mu+discrepancy", "theta0+discrepancy"}
    text = format_design(res)
    assert "Box-Hill" in text and "Feasibility" in text and "'neither'" in text
    write_netcdf(res.to_dataset(), out)
    ds = xr.open_dataset(out)
    assert ds["t_cr_mean"].shape == (2, len(res.settings))
    ds.close()
    save_design_figure(res, tmp_path / "design.png")
    assert (tmp_path / "design.png").stat().st_size > 10_000
    # a rerun with the same store resumes every solve and gives the same study
    again = Runner(workers=1, store=out)
    again.open(study_digest({"test": "design"}))
    res2 = _study(data, again)
    again.close()
    assert again.n_computed == 0 and again.n_resumed > 0
    assert [p.runs for p in res2.plans] == [p.runs for p in res.plans]
    assert res2.plans[-1].designed["theta0"] == res.plans[-1].designed["theta0"]


def test_design_and_validate_report_the_same_parameters(data):
    """One fit per model and data: the design's posterior is validate's fit, computed
    afresh by each (the shared memo emptied in between)."""
    from obturator.validation import run_validation
    from obturator.validation import study as validation_study

    validation_study._FIT_MEMO.clear()
    val = run_validation(
        data, models=["mu", "theta0"], runner=Runner(workers=1), profile="none", curve_points=2
    )
    validation_study._FIT_MEMO.clear()
    res = _study(data, Runner(workers=1))
    for name in ("mu", "theta0"):
        fit = val.model(name).fit
        post = res.posteriors[name]
        assert {k: post.values[k] for k in fit.params} == fit.values
        assert post.aic == fit.aic
