"""Monte Carlo studies: distributions, seeding, invariance to parallelism, summary, CLI."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy import stats

import obturator.sweeps as ss
import obturator.sweeps.job as sweep_job
from obturator.cli import main
from obturator.errors import InputError
from obturator.model.cases import rig_case
from obturator.runs import Runner
from obturator.solve import SolverOptions, opening_time
from obturator.status import Status
from obturator.sweeps import (
    Distribution,
    monte_carlo,
    monte_carlo_summary,
    parse_distribution,
    sample_inputs,
    sidecar_path,
    summarize_monte_carlo,
)

FAST = SolverOptions(rtol=1e-6, atol=1e-8)
VARY = ["mu_s=normal:0.5473,0.03", "theta0_deg=uniform:86.25,88.25"]


def run_mc(**kw: object) -> xr.Dataset:
    args: dict[str, object] = {
        "samples": 10,
        "seed": 7,
        "fixed": {"spin_rate": 450.0},
        "options": FAST,
    }
    execution = {k: kw.pop(k) for k in ("workers", "chunk_size", "store", "restart") if k in kw}
    args.update(kw)
    runner = Runner(**{"workers": 1, **execution})  # type: ignore[arg-type]
    return monte_carlo("spin-rig", VARY, runner=runner, **args)  # type: ignore[arg-type]


# --------------------------------------------------------------------------- distributions


def test_parse_distribution() -> None:
    name, d = parse_distribution("mu_s=normal:0.55,0.03")
    assert name == "mu_s" and d == Distribution("normal", (0.55, 0.03))
    name, d = parse_distribution("theta0-deg=uniform:86.25,88.25")
    assert name == "theta0_deg" and d.params == (86.25, 88.25)
    assert parse_distribution("gap=lognormal:5e-5,0.1")[1].kind == "lognormal"
    assert parse_distribution("spin_rate=truncnormal:400,50,300,500")[1].params[3] == 500.0
    assert str(d) == "uniform:86.25,88.25"


@pytest.mark.parametrize(
    "text",
    [
        "mu_s",
        "mu_s=0.5",
        "mu_s=normal:0.5",
        "mu_s=normal:0.5,-0.1",
        "mu_s=gauss:0.5,0.1",
        "mu_s=uniform:2,1",
        "mu_s=normal:0.5,x",
        "friction=normal:0.5,0.1",
        "gap=lognormal:-1,0.1",
        "mu_s=truncnormal:0.5,0.1,0.6,0.4",
    ],
)
def test_parse_distribution_rejects(text: str) -> None:
    with pytest.raises(InputError):
        parse_distribution(text)


def test_draws_follow_their_distributions() -> None:
    dists = {
        "mu_s": Distribution("truncnormal", (0.5, 0.2, 0.45, 0.9)),
        "gap": Distribution("lognormal", (5e-5, 0.2)),
        "spin_rate": Distribution("uniform", (300.0, 500.0)),
        "theta0_deg": Distribution("normal", (87.0, 0.5)),
    }
    x = sample_inputs(dists, 4000, 11)
    assert x["mu_s"].min() >= 0.45 and x["mu_s"].max() <= 0.9
    lo, hi = (0.45 - 0.5) / 0.2, (0.9 - 0.5) / 0.2
    assert stats.kstest(x["mu_s"], stats.truncnorm(lo, hi, 0.5, 0.2).cdf).pvalue > 1e-3
    assert stats.kstest(np.log(x["gap"]), stats.norm(math.log(5e-5), 0.2).cdf).pvalue > 1e-3
    assert stats.kstest(x["spin_rate"], stats.uniform(300.0, 200.0).cdf).pvalue > 1e-3
    assert stats.kstest(x["theta0_deg"], stats.norm(87.0, 0.5).cdf).pvalue > 1e-3
    # far upper tail of a truncated normal stays inside its bounds
    far = Distribution("truncnormal", (0.0, 1.0, 8.0, 9.0))
    rng = np.random.default_rng(0)
    assert all(8.0 <= far.draw(rng) <= 9.0 for _ in range(100))


def test_per_sample_seeds() -> None:
    d = {"mu_s": Distribution("normal", (0.5, 0.03)), "gap": Distribution("uniform", (4e-5, 6e-5))}
    a = sample_inputs(d, 20, 3)
    b = sample_inputs(d, 50, 3)
    c = sample_inputs(dict(reversed(list(d.items()))), 20, 3)
    for k in d:
        np.testing.assert_array_equal(a[k], b[k][:20])  # sample i does not depend on n
        np.testing.assert_array_equal(a[k], c[k])  # nor on the order given
    assert not np.array_equal(a["mu_s"], sample_inputs(d, 20, 4)["mu_s"])


# --------------------------------------------------------------------------- running


def test_samples_and_results() -> None:
    ds = run_mc()
    assert ds.sizes["sample"] == 10 and ds.sizes["quantile"] == 3
    assert ds["mu_s"].attrs["units"] == "1" and ds["theta0_deg"].attrs["units"] == "deg"
    assert ds["t_cr"].attrs["units"] == "s"
    assert float(ds["spin_rate"]) == 450.0
    for k in (0, 9):  # each sample is the plain opening time of its inputs
        case = rig_case(450.0, float(ds["mu_s"][k]), theta0_deg=float(ds["theta0_deg"][k]))
        assert ds["t_cr"].values[k] == opening_time(case, FAST)
    q = ds["t_cr_quantile"].values
    assert q[0] <= q[1] <= q[2]
    assert np.all(ds["t_cr_quantile_lower"].values <= q)
    assert np.all(ds["t_cr_quantile_upper"].values >= q)
    assert ds.attrs["seed"] == 7 and "mu_s=normal:0.5473,0.03" in ds.attrs["distributions"]


def test_independent_of_workers_and_chunking() -> None:
    ref = run_mc(workers=1, chunk_size=10)
    for kw in ({"workers": 2}, {"workers": 2, "chunk_size": 1}, {"workers": 1, "chunk_size": 3}):
        xr.testing.assert_identical(ref, run_mc(**kw))


def test_monte_carlo_store_resumes(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    store = tmp_path / "mc.nc"
    original = sweep_job.run_chunk  # every chunk runs here
    calls: list[int] = []

    def exploding(spec: ss.SweepSpec, names, rows, *packed):
        if len(calls) == 4:
            raise KeyboardInterrupt
        calls.extend([1] * len(rows))
        return original(spec, names, rows, *packed)

    monkeypatch.setattr(sweep_job, "run_chunk", exploding)
    with pytest.raises(KeyboardInterrupt):
        run_mc(store=store, chunk_size=2)
    assert sidecar_path(store).exists()
    calls.clear()

    def counting(spec: ss.SweepSpec, names, rows, *packed):
        calls.extend([1] * len(rows))
        return original(spec, names, rows, *packed)

    monkeypatch.setattr(sweep_job, "run_chunk", counting)
    ds = run_mc(store=store, chunk_size=2)
    assert len(calls) == 6 and not sidecar_path(store).exists()
    monkeypatch.setattr(sweep_job, "run_chunk", original)
    xr.testing.assert_identical(ds, run_mc())
    with xr.open_dataset(store) as on_disk:
        np.testing.assert_array_equal(on_disk["t_cr"].values, ds["t_cr"].values)


def test_out_of_range_samples_are_refused() -> None:
    with pytest.raises(InputError, match="truncnormal"):
        monte_carlo(
            "spin-rig", ["mu_s=normal:0.01,0.05"], samples=50, seed=0, options=FAST, runner=Runner()
        )
    with pytest.raises(InputError, match="both varied and fixed"):
        run_mc(fixed={"mu_s": 0.5})
    with pytest.raises(InputError, match="flight case only"):
        monte_carlo("spin-rig", ["mach=uniform:2,3"], samples=2, seed=0, runner=Runner())
    with pytest.raises(InputError, match="samples"):
        run_mc(samples=0)
    with pytest.raises(InputError, match="seed"):
        run_mc(seed=-1)


# --------------------------------------------------------------------------- summary


def test_order_statistic_intervals() -> None:
    n = 200
    t = np.arange(1, n + 1, dtype=float)  # x_(k) = k
    s = np.full(n, Status.OPENED)
    summ = summarize_monte_carlo(t, s, t_max=1e3, quantiles=[0.05, 0.5, 0.95])
    q05, q50, q95 = summ.quantiles
    assert q50.value == 100.0 and q05.value == 10.0 and q95.value == 190.0
    for q in summ.quantiles:
        lo, hi = int(q.lower), int(q.upper)
        cover = stats.binom.cdf(hi - 1, n, q.probability) - stats.binom.cdf(
            lo - 1, n, q.probability
        )
        assert q.coverage == pytest.approx(cover) and q.coverage >= 0.95
        assert lo <= q.value <= hi
    assert summ.fraction_not_opened == 0.0 and summ.fraction_not_opened_ci[0] == 0.0
    assert summ.mean_s == pytest.approx(100.5)


def test_interval_coverage_by_simulation() -> None:
    rng = np.random.default_rng(5)
    hits = 0
    trials = 400
    for _ in range(trials):
        x = rng.exponential(1.0, 60)
        q = summarize_monte_carlo(x, np.ones(60), t_max=1e9, quantiles=[0.5]).quantiles[0]
        hits += q.lower <= math.log(2.0) <= q.upper
    assert hits / trials > 0.92  # nominal 95 %, conservative by construction


def test_censored_and_failed_samples() -> None:
    t = np.array([0.3, 0.4, np.nan, np.nan, 0.35, np.nan])
    s = np.array([1, 1, Status.T_MAX, Status.T_MAX, 1, Status.FAILED])
    summ = summarize_monte_carlo(t, s, t_max=1.0, quantiles=[0.2, 0.9])
    assert summ.n_opened == 3 and summ.n_not_opened == 2 and summ.n_failed == 1
    assert summ.fraction_not_opened == pytest.approx(0.4)
    lo, hi = summ.fraction_not_opened_ci
    assert lo == pytest.approx(stats.beta.ppf(0.025, 2, 4))
    assert hi == pytest.approx(stats.beta.ppf(0.975, 3, 3))
    assert summ.quantiles[0].value == 0.3
    assert summ.quantiles[1].value == math.inf  # among the samples that never opened
    d = summ.to_dict()
    assert d["quantiles"][1]["t_cr_s"] is None and d["quantiles"][1]["beyond_t_max"]
    json.dumps(d)


def test_summary_roundtrip_from_dataset() -> None:
    ds = run_mc()
    summ = monte_carlo_summary(ds)
    assert [q.value for q in summ.quantiles] == ds["t_cr_quantile"].values.tolist()
    assert summ.n_opened == ds.attrs["n_opened"] == 10


# --------------------------------------------------------------------------- CLI


def test_cli_montecarlo_table_and_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    base = ["montecarlo", "--case", "spin-rig", "--samples", "8", "--seed", "7"]
    base += ["--vary", VARY[0], "--vary", VARY[1], "--spin-rate", "450", "--rtol", "1e-6"]
    base += ["--workers", "1", "--no-progress"]
    out = tmp_path / "mc.nc"
    assert main([*base, "--out", str(out), "--csv", str(tmp_path / "mc.csv")]) == 0
    text = capsys.readouterr().out
    assert "quantile" in text and "50 %" in text and "95% CI" in text
    with xr.open_dataset(out) as ds:
        assert ds.sizes["sample"] == 8
        t = ds["t_cr"].values
    rows = [r for r in (tmp_path / "mc.csv").read_text().splitlines() if not r.startswith("#")]
    assert rows[0] == "mu_s [1],theta0_deg [deg],t_cr [s],status,route"
    assert len(rows) == 9
    assert main([*base, "--json", "--quantiles", "10,50"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert [q["probability"] for q in d["quantiles"]] == [0.1, 0.5]
    assert d["n_opened"] == 8 and d["seed"] == 7
    assert d["quantiles"][1]["t_cr_s"] == float(np.sort(t)[3])


@pytest.mark.parametrize(
    ("extra", "field"),
    [
        (["--vary", "mu_s=normal:0.5"], "mu_s"),
        (["--vary", "mu_s:normal:0.5,0.1"], "vary"),
        (["--vary", "mu_s=normal:0.5,0.1", "--samples", "ten"], "samples"),
        (["--vary", "mu_s=normal:0.5,0.1", "--quantiles", "50,120"], "quantiles"),
        (["--vary", "mu_s=normal:0.5,0.1", "--spin-rate", "fast"], "--spin-rate"),
    ],
)
def test_cli_montecarlo_bad_input(
    capsys: pytest.CaptureFixture[str], extra: list[str], field: str
) -> None:
    argv = ["montecarlo", "--samples", "4", "--no-progress", *extra]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("obturator: error:") and err.count("\n") == 1 and field in err


def test_unconverged_openings_are_flagged_and_excluded():
    # 78 rad/s, the regularised law with a too-wide friction width (1e-5 omega_p): t_cr moves
    # ~1 % against width/10 and another family, so every opening is a status-2 sample: kept
    # in the dataset but
    # excluded from quantiles and mean (the Monte Carlo default checks convergence).
    from obturator.sweeps import monte_carlo, monte_carlo_summary

    ds = monte_carlo(
        "spin-rig",
        ["mu_s=uniform:0.5,0.6"],
        samples=3,
        seed=1,
        fixed={"spin_rate": 78.0},
        options=SolverOptions(friction_width=1e-5, method="regularised"),
        runner=Runner(workers=1),
    )
    assert ds["status"].values.tolist() == [Status.UNCONVERGED] * 3
    assert np.all(np.isfinite(ds["t_cr"].values))
    summ = monte_carlo_summary(ds)
    assert summ.n_unconverged == 3 and summ.n_opened == 0 and math.isnan(summ.mean_s)
    assert ds.attrs["n_unconverged"] == 3
