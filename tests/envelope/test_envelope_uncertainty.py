"""Exceedance probability (importance sampling vs exact and vs brute force) and Sobol indices."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from obturator.envelope.model import FlightModel
from obturator.envelope.reliability import brute_force, clopper_pearson, importance_sampling
from obturator.envelope.sensitivity import sobol_indices
from obturator.envelope.trajectory import Launch
from obturator.envelope.uncertain import (
    RigModel,
    parse_input_distribution,
    performance,
    points_from_normal,
    ppf,
)
from obturator.errors import InputError
from obturator.runs import Runner
from obturator.solve import SolverOptions
from obturator.sweeps import Distribution

FAST = SolverOptions(rtol=1e-6, atol=1e-8)
N01 = Distribution("normal", (0.0, 1.0))


def linear(d: int, scale: float = 0.1):
    """t = 1 + scale * sum(x)/sqrt(d): P(t > 1 + scale b) = Phi(-b) exactly."""

    def f(points):
        x = np.array([[p[f"x{i}"] for i in range(d)] for p in points])
        return 1.0 + scale * x.sum(1) / math.sqrt(d), np.ones(len(points), dtype=np.int8)

    return f


@pytest.mark.parametrize("b", [2.0, 4.0])
def test_importance_sampling_matches_the_exact_probability(b):
    d = 4
    dists = {f"x{i}": N01 for i in range(d)}
    exact = stats.norm.sf(b)
    est = importance_sampling(linear(d), dists, 1.0 + 0.1 * b, n_stage=400, n_final=800, seed=3)
    assert abs(est.probability - exact) < 3.0 * est.std_error
    assert abs(est.probability / exact - 1.0) < 0.25
    assert est.n_evaluations <= 2400  # brute force would need ~1e6 for 10 % at b = 4
    assert est.levels[-1] == pytest.approx(1.0 + 0.1 * b) and est.reliable


def test_importance_sampling_agrees_with_brute_force_on_the_flight_model():
    """Mach 1.75, 7 km: t_cr ~ 0.1 s, so P(t_cr > 0.1 s) ~ 0.4 can be brute-forced."""
    model = FlightModel(
        launch=Launch(mach=1.75, altitude_m=7000.0),
        load="constant",
        options=FAST,
        check_convergence=False,
    )
    dists = dict(
        parse_input_distribution(t)
        for t in ("mu_s=lognormal:0.35,0.1", "theta0_deg=uniform:86.25,88.25")
    )
    perf = performance(model, Runner(workers=1), "test")
    bf = brute_force(perf, dists, 0.1, samples=600, seed=11)
    est = importance_sampling(perf, dists, 0.1, n_stage=100, n_final=300, seed=12)
    assert 0.2 < bf.probability < 0.6
    z = (est.probability - bf.probability) / math.hypot(est.std_error, bf.std_error)
    assert abs(z) < 3.0
    # independent check: t_cr ~ 1/mu_s near the median, so p ~ P(mu_s < mu_crit)
    assert bf.ci_low < est.ci_high and est.ci_low < bf.ci_high


def test_clopper_pearson_matches_scipy():
    for k, n in ((0, 50), (7, 50), (50, 50)):
        ci = stats.binomtest(k, n).proportion_ci(0.95, method="exact")
        assert clopper_pearson(k, n) == pytest.approx((ci.low, ci.high), abs=1e-12)


def test_ppf_matches_scipy():
    z = np.array([-2.5, -0.3, 0.0, 1.7])
    u = stats.norm.cdf(z)
    cases = [
        ("normal:2,0.5", stats.norm(2, 0.5)),
        ("uniform:1,3", stats.uniform(1, 2)),
        ("lognormal:0.35,0.1", stats.lognorm(0.1, scale=0.35)),
        ("truncnormal:1,2,0,3", stats.truncnorm(-0.5, 1.0, loc=1, scale=2)),
    ]
    for text, ref in cases:
        # an input whose range ([-90, 90] deg) holds every support here (issue 46)
        _, dist = parse_input_distribution(f"elevation_deg={text}")
        np.testing.assert_allclose(ppf(dist, z), ref.ppf(u), rtol=1e-10)
    pts = points_from_normal({"mu_s": dist}, z[:, None])
    assert len(pts) == 4 and set(pts[0]) == {"mu_s"}


def test_input_validation():
    with pytest.raises(InputError, match="^vary:.*unknown input"):
        parse_input_distribution("colour=normal:1,2")
    with pytest.raises(InputError, match="^mu_s:"):
        parse_input_distribution("mu_s=uniform:3,1")
    with pytest.raises(InputError, match="^sigma_floor:"):
        importance_sampling(linear(1), {"x0": N01}, 1.2, sigma_floor=0.5)
    with pytest.raises(InputError, match="^requirement:"):
        brute_force(linear(1), {"x0": N01}, -1.0)


def test_sobol_additive_linear_model():
    """Y = sum c_i X_i, X_i ~ U(0, 1): S1_i = ST_i = c_i^2 / sum c^2."""
    c = np.array([1.0, 2.0, 3.0])
    dists = {f"x{i}": Distribution("uniform", (0.0, 1.0)) for i in range(3)}

    def f(points):
        x = np.array([[p[f"x{i}"] for i in range(3)] for p in points])
        return x @ c, np.ones(len(points), dtype=np.int8)

    ds = sobol_indices(f, dists, 512, seed=2, resamples=200)
    exact = c**2 / (c**2).sum()
    np.testing.assert_allclose(ds["S1"].values, exact, atol=0.03)
    np.testing.assert_allclose(ds["ST"].values, exact, atol=0.03)
    assert ds.attrs["n_evaluations"] == 512 * 5


def test_sobol_ishigami():
    a, b = 7.0, 0.1
    dists = {f"x{i}": Distribution("uniform", (-math.pi, math.pi)) for i in range(3)}

    def f(points):
        x = np.array([[p[f"x{i}"] for i in range(3)] for p in points])
        y = np.sin(x[:, 0]) + a * np.sin(x[:, 1]) ** 2 + b * x[:, 2] ** 4 * np.sin(x[:, 0])
        return y, np.ones(len(points), dtype=np.int8)

    v1 = 0.5 * (1 + b * math.pi**4 / 5) ** 2
    v2 = a**2 / 8
    v13 = b**2 * math.pi**8 * (1 / 18 - 1 / 50)
    v = v1 + v2 + v13
    ds = sobol_indices(f, dists, 2048, seed=1, resamples=200)
    np.testing.assert_allclose(ds["S1"].values, [v1 / v, v2 / v, 0.0], atol=0.04)
    np.testing.assert_allclose(ds["ST"].values, [(v1 + v13) / v, v2 / v, v13 / v], atol=0.04)
    assert (ds["ST_conf"].values > 0).all()


def test_sobol_on_the_models():
    runner = Runner(workers=1)
    flight = FlightModel(load="constant", options=FAST, check_convergence=False)
    dists = dict(
        parse_input_distribution(t) for t in ("mu_s=uniform:0.25,0.45", "density=uniform:7600,7700")
    )
    ds = sobol_indices(performance(flight, runner, "t"), dists, 16, resamples=50)
    assert ds["ST"].sel(input="mu_s") > 0.9 > ds["ST"].sel(input="density")
    rig = RigModel(("spin_rate", "density"), options=FAST, check_convergence=False)
    rdists = dict(
        parse_input_distribution(t, ("spin_rate", "density"))
        for t in ("spin_rate=uniform:300,500", "density=uniform:7600,7700")
    )
    ds = sobol_indices(performance(rig, runner, "t"), rdists, 8, resamples=50)
    assert ds["S1"].sel(input="spin_rate") > 0.8
    with pytest.raises(InputError, match="^n_base:"):
        sobol_indices(performance(rig, runner, "t"), rdists, 12)


def test_sobol_intervals_are_reproducible_at_seed_0():
    """The default seed 0 gives the same indices and bootstrap intervals twice."""
    import numpy as np

    from obturator.envelope.sensitivity import sobol_indices
    from obturator.envelope.uncertain import parse_input_distribution

    dists = dict(parse_input_distribution(t, ("mu_s", "gap")) for t in
                 ("mu_s=uniform:0.3,0.4", "gap=uniform:4e-5,6e-5"))  # fmt: skip

    def f(points):
        y = np.array([p["mu_s"] + 1e3 * p["gap"] for p in points])
        return y, np.ones(len(points), dtype=np.int8)

    a = sobol_indices(f, dists, 16, seed=0, resamples=50)
    b = sobol_indices(f, dists, 16, seed=0, resamples=50)
    np.testing.assert_array_equal(a["ST_conf"].values, b["ST_conf"].values)
    np.testing.assert_array_equal(a["S1_conf"].values, b["S1_conf"].values)
