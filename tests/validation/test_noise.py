"""Heteroscedastic likelihood and goodness of fit against the replicate floor (issue 29, item 5).

Reference values are independent computations: scipy's normal log-density for the
likelihood, and the lack-of-fit F test written out by hand for the goodness of fit.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from obturator.cli import main
from obturator.validation import CANDIDATES, fit_candidate, replicate_floor
from obturator.validation.evaluate import ModelEvaluator
from obturator.validation.goodness import band_goodness, cluster_goodness, overall_goodness
from obturator.validation.likelihood import (
    MIN_GROUP_RUNS,
    effective_sd,
    nll_terms,
    noise_groups,
    profile_noise,
)

# a tiny data set: two noise groups with very different scatter
_Y = np.array([0.50, 0.62, 0.41, 0.55, 0.200, 0.203, 0.198, 0.201, 0.204])
_M = np.array([0.52, 0.52, 0.52, 0.52, 0.201, 0.201, 0.201, 0.201, 0.201])
_G = np.array(["slow"] * 4 + ["fast"] * 5)


def test_band_likelihood_matches_scipy_normal_log_density():
    """Without spin error each group's ML sigma is its rms residual, and -log L is the
    sum of scipy's normal log-densities with those sigmas."""
    per_run, by_group, nll = profile_noise(_Y, _M, np.zeros(_Y.size), 5.0, _G, 0.0)
    for g in ("slow", "fast"):
        sel = _G == g
        rms = math.sqrt(np.mean((_Y[sel] - _M[sel]) ** 2))
        assert by_group[g] == pytest.approx(rms, rel=1e-12)
        assert np.all(per_run[sel] == by_group[g])
    ref = -np.sum(stats.norm.logpdf(_Y, loc=_M, scale=per_run))
    assert nll == pytest.approx(ref, rel=1e-12)
    assert np.sum(nll_terms(_Y, _M, per_run, 5.0)) == pytest.approx(ref, rel=1e-12)
    # one pooled sigma fits these data worse: the band model's -log L is lower
    _, pooled, nll_pooled = profile_noise(_Y, _M, np.zeros(_Y.size), 5.0, ["all"] * 9, 0.0)
    assert nll < nll_pooled - 5.0
    assert pooled["all"] == pytest.approx(math.sqrt(np.mean((_Y - _M) ** 2)))


def test_band_likelihood_with_spin_error_is_the_maximum():
    """With the errors-in-variables term s_i^2 = sigma_b^2 + (g_i sigma_w)^2 (by hand,
    scipy's density): the returned sigmas are the maximum, per group."""
    slope = np.array([-0.02, -0.03, -0.01, -0.02, 1e-4, 2e-4, 1e-4, 0.0, 1e-4])
    spin_sd = 1.0
    _, by_group, nll = profile_noise(_Y, _M, slope, 5.0, _G, spin_sd)

    def hand(sig: dict[str, float]) -> float:
        s = np.sqrt(np.array([sig[g] for g in _G]) ** 2 + (slope * spin_sd) ** 2)
        return float(-np.sum(stats.norm.logpdf(_Y, loc=_M, scale=s)))

    assert nll == pytest.approx(hand(by_group), rel=1e-10)
    for g in by_group:
        for f in (0.97, 1.03):
            assert hand({**by_group, g: by_group[g] * f}) > nll
    sd = effective_sd([by_group[g] for g in _G], slope, spin_sd)
    assert np.sum(nll_terms(_Y, _M, sd, 5.0)) == pytest.approx(nll, rel=1e-10)


def test_noise_groups_merge_small_bands_and_pool():
    band = np.array(["<120", "<120", "120-200", "120-200", "120-200", "200-300", ">300"] * 1)
    groups = noise_groups(band, "band")
    # 200-300 (1 run) joins 120-200, then >300 (1 run) joins 120-200 too; <120 (2 runs)
    # has fewer than MIN_GROUP_RUNS and joins its upper neighbour
    assert MIN_GROUP_RUNS == 3
    assert len(set(groups)) == 1
    big = np.repeat(["<120", "120-200", ">300"], [3, 4, 5])
    assert list(dict.fromkeys(noise_groups(big, "band"))) == ["<120", "120-200", ">300"]
    assert set(noise_groups(big, "pooled")) == {"all"}
    with pytest.raises(Exception, match="noise"):
        noise_groups(big, "per-run")


def _synthetic(spins: np.ndarray, noise: np.ndarray) -> np.ndarray:
    ev = ModelEvaluator(CANDIDATES["mu"], 5.0)
    return ev.opening_times([0.55], spins) + noise


def test_fit_band_noise_counts_a_sigma_per_band_and_finds_each():
    w = np.array([130.0, 140.0, 150.0, 160.0, 330.0, 340.0, 360.0, 380.0, 400.0])
    rng = np.random.default_rng(3)
    e = np.where(w < 200, 0.002, 0.03) * rng.standard_normal(w.size)
    y = _synthetic(w, e)
    band = fit_candidate(CANDIDATES["mu"], w, y, t_max=5.0, spin_sd=0.0, noise="band")
    pooled = fit_candidate(CANDIDATES["mu"], w, y, t_max=5.0, spin_sd=0.0, noise="pooled")
    assert band.k == 1 + 2 and pooled.k == 1 + 1
    assert set(band.sigma_by_group) == {"120-200", ">300"}
    assert band.sigma_by_group["120-200"] < band.sigma_by_group[">300"] / 3
    # each band's sigma is its rms residual (no spin error, no censoring)
    for g, s in band.sigma_by_group.items():
        sel = band.noise_group == g
        assert s == pytest.approx(math.sqrt(np.mean(band.residuals[sel] ** 2)), rel=1e-9)
    # near the t_cr minimum (130-160 rad/s) t_cr hardly moves with mu_s: the estimate is
    # within 3 standard errors, and weighting the bands brings it nearer than pooling
    assert band.values["mu_s"] == pytest.approx(0.55, abs=3 * band.stderr["mu_s"])
    assert abs(band.values["mu_s"] - 0.55) < abs(pooled.values["mu_s"] - 0.55)
    assert band.stderr["mu_s"] < pooled.stderr["mu_s"]
    # the quiet band pins mu_s: the band fit is closer to the truth there
    quiet = w < 200
    assert np.sqrt(np.mean(band.residuals[quiet] ** 2)) <= np.sqrt(
        np.mean(pooled.residuals[quiet] ** 2)
    )


def test_goodness_per_band_and_cluster_by_hand():
    """The lack-of-fit F test per band, written out from the cluster means."""
    w = np.array([96.0, 97.0, 98.0, 150.0, 151.0, 152.0, 250.0, 251.0])
    y = np.array([0.226, 0.229, 0.225, 0.18, 0.17, 0.175, 0.21, 0.23])
    fl = replicate_floor(w, y)
    fit = fit_candidate(CANDIDATES["thesis-1980"], w, y, t_max=5.0, noise="band")
    rows = cluster_goodness(fl, fit)
    assert [r["name"] for r in rows] == ["97 rad/s", "151 rad/s", "250 rad/s"]
    bands = band_goodness(fl, fit)
    for label, sel in (("<120", slice(0, 3)), ("120-200", slice(3, 6))):
        yc, mc = y[sel], fit.model[sel]
        ss_lof = 3 * (mc.mean() - yc.mean()) ** 2
        s2_pe = np.sum((yc - yc.mean()) ** 2) / 2
        f = ss_lof / s2_pe
        assert bands[label]["F"] == pytest.approx(f, rel=1e-10)
        assert bands[label]["p_value"] == pytest.approx(stats.f.sf(f, 1, 2), rel=1e-10)
        r = next(r for r in rows if r["band"] == label)
        assert r["z_band"] == pytest.approx(
            (mc.mean() - yc.mean()) / math.sqrt(s2_pe / 3), rel=1e-10
        )
    over = overall_goodness(bands, 0)
    assert over["dof"] == 1 + 1 + 1 and over["n_bands"] == 3


def test_cli_validate_noise_flag_and_goodness_json(tmp_path, capsys):
    w = np.array([150.0, 151.0, 152.0, 230.0, 231.0, 232.0, 300.0, 302.0])
    y = _synthetic(w, np.array([3, -2, 1, -4, 2, 5, -3, 1]) * 1e-3)
    path = tmp_path / "runs.csv"
    path.write_text(
        "spin_rate_rad_s,t_cr_s\n" + "".join(f"{a},{b:.5f}\n" for a, b in zip(w, y, strict=True))
    )
    import json

    argv = ["validate", "--data", str(path), "--models", "thesis-1980", "--json"]
    assert main([*argv, "--no-progress", "--noise", "pooled"]) == 0
    pooled = json.loads(capsys.readouterr().out)
    assert main([*argv, "--no-progress"]) == 0
    band = json.loads(capsys.readouterr().out)
    assert pooled["settings"]["noise"] == "pooled" and band["settings"]["noise"] == "band"
    m = band["models"][0]
    # the two runs above 300 rad/s share the sigma of 200-300 (fewer than 3 runs)
    assert set(m["sigma_by_group_s"]) == {"120-200", "200-300"}
    assert m["k"] == 2 and pooled["models"][0]["k"] == 1
    g = m["goodness"]
    assert set(g["bands"]["120-200"]) >= {"rms_s", "sigma_s", "pure_error_sd_s", "F", "p_value"}
    assert [c["name"] for c in g["clusters"]] == ["151 rad/s", "231 rad/s", "301 rad/s"]
    assert {"residual_s", "z_band", "t_sd_s"} <= set(g["clusters"][0])
    assert main([*argv, "--noise", "per-run"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("obturator: error: --noise")


def test_runs_with_another_ball_are_no_replicates():
    from obturator.validation import cluster_runs

    w = [100.0, 101.0, 100.5, 200.0]
    assert list(cluster_runs(w)) == [0, 0, 0, 1]
    assert list(cluster_runs(w, groups=["a", "a", "b", "a"])) == [0, 0, 1, 2]
    fl = replicate_floor(w, [0.2, 0.3, 0.9, 0.4], groups=["a", "a", "b", "a"])
    assert fl.overall.ss_pe == pytest.approx(2 * 0.05**2)  # only the pair of group a
