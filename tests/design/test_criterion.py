"""The design criterion against closed forms, and the plan search on problems with a known
optimum (no solver: milliseconds)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from obturator.design import Setting, box_hill, gaussian_kl, greedy_exchange, jeffreys, naive_plan
from obturator.design.campaigns import decision_rates, log_evidence
from obturator.design.surrogate import Surrogate


def kl_1d(m0: float, s0: float, m1: float, s1: float) -> float:
    """KL(N(m0, s0^2) || N(m1, s1^2)), the textbook closed form (Kullback 1959)."""
    return math.log(s1 / s0) + (s0**2 + (m0 - m1) ** 2) / (2.0 * s1**2) - 0.5


def test_kl_of_two_gaussians_is_the_closed_form():
    # 0.2 s vs 0.25 s with SDs 0.013 and 0.02 s (the rig's replicate SD at 120-300 rad/s)
    got = gaussian_kl(0.2, 0.013**2, 0.25, 0.02**2)
    assert got == pytest.approx(kl_1d(0.2, 0.013, 0.25, 0.02), rel=1e-12)
    # equal means, variance ratio 4: ln 2 + 1/8 - 1/2
    assert gaussian_kl(0.0, 1.0, 0.0, 4.0) == pytest.approx(math.log(2.0) + 0.125 - 0.5, rel=1e-12)


def test_kl_of_independent_runs_adds():
    m0, m1 = np.array([0.1, 0.3, 0.5]), np.array([0.12, 0.27, 0.5])
    s0, s1 = np.array([0.01, 0.02, 0.1]), np.array([0.015, 0.02, 0.05])
    joint = gaussian_kl(m0, np.diag(s0**2), m1, np.diag(s1**2))
    assert joint == pytest.approx(sum(map(kl_1d, m0, s0, m1, s1)), rel=1e-12)


def test_box_hill_single_run_is_their_formula():
    """Box and Hill (1967), D for one run and two models with prior P1, P2:
    D = 1/2 P1 P2 [(s1^2 - s2^2)^2 / ((s^2 + s1^2)(s^2 + s2^2))
                   + (y1 - y2)^2 (1/(s^2 + s1^2) + 1/(s^2 + s2^2))]."""
    y1, y2, s, s1, s2, p1 = 0.21, 0.19, 0.0127, 0.004, 0.009, 0.3
    v1, v2 = s**2 + s1**2, s**2 + s2**2
    expected = (
        0.5
        * p1
        * (1 - p1)
        * ((s1**2 - s2**2) ** 2 / (v1 * v2) + (y1 - y2) ** 2 * (1 / v1 + 1 / v2))
    )
    assert box_hill([y1, y2], [v1, v2], [p1, 1 - p1]) == pytest.approx(expected, rel=1e-12)


def test_shared_parameter_uncertainty_makes_replicates_worth_less():
    """Two replicates of one run under models whose mean is uncertain by tau: the
    joint divergence is less than twice the single run's (the runs are correlated)."""
    tau, s, d = 0.02, 0.01, 0.03
    one = jeffreys(0.0, tau**2 + s**2, d, tau**2 + s**2)
    cov = np.full((2, 2), tau**2) + s**2 * np.eye(2)
    two = jeffreys(np.zeros(2), cov, np.full(2, d), cov)
    # closed form: d^2 1^T C^-1 1 = 2 d^2 / (s^2 + 2 tau^2)
    assert two == pytest.approx(2 * d**2 / (s**2 + 2 * tau**2), rel=1e-12)
    assert one < two < 2 * one


@given(st.floats(-1, 1), st.floats(0.01, 1), st.floats(-1, 1), st.floats(0.01, 1))
def test_kl_is_non_negative_and_zero_only_for_equal(m0, s0, m1, s1):
    k = gaussian_kl(m0, s0**2, m1, s1**2)
    assert k >= -1e-12
    assert gaussian_kl(m0, s0**2, m0, s0**2) == pytest.approx(0.0, abs=1e-12)
    if abs(m0 - m1) > 1e-3 or abs(s0 - s1) > 1e-3:
        assert k > 0.0


def _each(value):
    """A value of one plan (a list) as the plan search asks for it: of each row."""
    return lambda plans: np.array([value(list(p)) for p in np.asarray(plans).tolist()])


def test_greedy_exchange_finds_the_known_optimum():
    """Value = sum of per-run scores with a diminishing return on repeats: the best plan
    of 3 takes the two best candidates, the best one twice."""
    score = {0: 1.0, 1: 5.0, 2: 3.0, 3: 0.5}

    def value(plan):
        return sum(
            score[c] * (1.0 if k == 0 else 0.5) for c in set(plan) for k in range(plan.count(c))
        )

    plan, v = greedy_exchange(3, list(score), _each(value))
    assert plan == [1, 1, 2]
    assert v == pytest.approx(5.0 + 2.5 + 3.0)


def test_log_evidence_is_the_gaussian_density():
    y = np.array([[0.2, 0.31], [0.25, 0.29]])
    mean, cov = np.array([0.21, 0.3]), np.array([[4e-4, 1e-4], [1e-4, 9e-4]])
    from scipy.stats import multivariate_normal

    expected = multivariate_normal(mean, cov).logpdf(y)
    np.testing.assert_allclose(log_evidence(y, mean, cov), expected, rtol=1e-12)


def test_surrogate_moments_are_exact_for_its_quadratic_form():
    """E and Cov of t0 + g z + c z^2 / 2 with z ~ N(0, I), against Monte Carlo."""
    sur = Surrogate(
        "m",
        np.array([0.2, 0.3]),
        np.array([[0.01, 0.0], [0.005, 0.02]]),
        np.array([[0.004, 0.002], [0.0, 0.006]]),
    )
    z = np.random.default_rng(3).standard_normal((400_000, 2))
    t = sur.at([0, 1], z)
    np.testing.assert_allclose(sur.mean([0, 1]), t.mean(axis=0), atol=1e-4)
    np.testing.assert_allclose(sur.covariance([0, 1]), np.cov(t.T), rtol=2e-2, atol=1e-7)


def test_naive_plan_spreads_the_measured_spins():
    spins = np.arange(1.0, 55.0)  # 54 runs: spin = rank + 1
    # base: 20 runs at ranks floor((j + 1/2) 54 / 20) = 1, 4, 6, 9, 12, 14, ...
    base = [float(int((j + 0.5) * 2.7) + 1) for j in range(20)]
    assert [s.spin_rate for s in naive_plan(20, spins)] == base
    plan = naive_plan(6, spins)  # base entries floor((i + 1/2) 20 / 6) = 1, 5, 8, 11, 15, 18
    assert [s.spin_rate for s in plan] == [5.0, 15.0, 23.0, 32.0, 42.0, 50.0]
    assert all(s.is_nominal_rig for s in plan)
    assert [s.spin_rate for s in naive_plan(22, spins)][-2:] == [2.0, 5.0]  # repeats
    assert Setting(200.0).to_dict()["theta0_set_deg"] == 87.25


def _toy_surrogates(shift: float) -> dict[str, Surrogate]:
    g = np.array([[0.005], [0.004], [0.006]])
    c = np.zeros((3, 1))
    t0 = np.array([0.2, 0.25, 0.3])
    return {"a": Surrogate("a", t0, g, c), "b": Surrogate("b", t0 + shift, g, c)}


def test_campaigns_of_indistinguishable_models_are_never_decisive():
    """Two models with the same predictive distribution: Bayes factors are exactly 1."""
    sur = _toy_surrogates(0.0)
    rng = np.random.default_rng(0)
    exact = {m: s.at([0, 1, 2], rng.standard_normal((300, 1))) for m, s in sur.items()}
    rates = decision_rates(exact, [0, 1, 2], sur, np.full(3, 0.01), rng)
    assert all(r.p_decisive == 0.0 and r.p_misleading == 0.0 for r in rates.values())


def test_campaigns_of_separated_models_are_decisive_as_predicted():
    """Means 0.05 s apart, noise 0.01 s, parameter SD ~0.005 s: one run's log Bayes factor
    has mean KL ~ 10 nats > ln 10, so nearly every campaign is decisive; the rates
    follow the closed-form Gaussian (linear model: exact)."""
    sur = _toy_surrogates(0.05)
    rng = np.random.default_rng(1)
    exact = {m: s.at([0], rng.standard_normal((2000, 1))) for m, s in sur.items()}
    rates = decision_rates(exact, [0], sur, np.full(3, 0.01), rng)
    # closed form: y ~ N(m_a, v), log BF = (m_b - m_a)(2 y - m_a - m_b) / (2 v) with equal
    # variances v; decisive when log BF > ln 10, i.e. y on the far side of a threshold
    v = 0.005**2 + 0.01**2
    from scipy.stats import norm

    z = (math.log(10.0) * v / 0.05 - 0.025) / math.sqrt(v)
    expected = float(norm.cdf(-z))  # P(log BF_a > ln 10) under a
    assert rates["a"].p_decisive == pytest.approx(expected, abs=0.02)
    assert rates["b"].p_decisive == pytest.approx(expected, abs=0.02)


def test_greedy_exchange_reports_every_step():
    # the progress display is told n_runs * (1 + passes) steps whatever pass the search
    # stops at (a separable value: the exchange passes end after the first)
    from obturator.design.criterion import EXCHANGE_PASSES

    steps: list[int] = []
    score = {0: 1.0, 1: 3.0, 2: 2.0}
    plan, _ = greedy_exchange(
        4, list(score), _each(lambda p: sum(score[i] for i in p)), advance=steps.append
    )
    assert plan == [1, 1, 1, 1]  # the best candidate, 4 times: by hand
    assert sum(steps) == 4 * (1 + EXCHANGE_PASSES)


def test_plan_search_shows_progress_lines(capsys):
    # the plan search of design-experiment reports through the runner's one display
    from obturator.design.study import _best_plans
    from obturator.runs import Progress, Runner

    score = {0: 1.0, 1: 3.0, 2: 2.0}
    settings = [Setting(100.0), Setting(200.0), Setting(300.0)]
    runner = Runner(workers=1, progress=Progress("lines", interval_s=0.0))
    value = _each(lambda p: sum(score[i] for i in p))
    plans = _best_plans([2, 3], list(score), value, settings, runner)
    assert sorted(plans) == [2, 3]
    lines = [ln for ln in capsys.readouterr().err.splitlines() if "plan search" in ln]
    assert lines and all(ln.startswith("obturator: design: plan search: ") for ln in lines)


@pytest.mark.parametrize("n", [1, 2, 5, 12, 20])
def test_jeffreys_is_the_sum_of_both_directions(n):
    """The symmetric divergence, computed from the two Cholesky factors with the log
    determinants cancelled, against KL(0||1) + KL(1||0) each in closed form."""
    rng = np.random.default_rng(n)
    for _ in range(20):
        a, b = rng.normal(size=(n, n)), rng.normal(size=(n, n))
        s0, s1 = a @ a.T + n * np.eye(n), b @ b.T + 0.1 * np.eye(n)
        m0, m1 = rng.normal(size=n), rng.normal(size=n)
        both = gaussian_kl(m0, s0, m1, s1) + gaussian_kl(m1, s1, m0, s0)
        assert jeffreys(m0, s0, m1, s1) == pytest.approx(both, rel=1e-12)


def test_plan_values_of_stacked_plans_are_box_hill_of_each():
    """The stacked evaluation of the plan search against :func:`box_hill` of each plan's
    means and covariances built one plan at a time (Surrogate.mean, Surrogate.covariance
    plus the noise): 3 models, 2 parameters, 12 settings, plans of 1-6 runs with repeats."""
    from obturator.design.criterion import plan_value, plan_values

    rng = np.random.default_rng(5)
    sur = [
        Surrogate(
            m, rng.uniform(0.2, 0.6, 12), rng.normal(0, 0.01, (12, 2)), rng.normal(0, 1e-3, (12, 2))
        )
        for m in "abc"
    ]
    noise = rng.uniform(0.005, 0.02, 12)
    for n in (1, 2, 3, 6):
        plans = rng.integers(0, 12, (40, n))
        got = plan_values(sur, noise, plans)
        for plan, v in zip(plans, got, strict=True):
            cov_noise = np.diag(noise[plan] ** 2)
            one = box_hill(
                [s.mean(plan) for s in sur], [s.covariance(plan) + cov_noise for s in sur]
            )
            assert v == pytest.approx(one, rel=1e-12)
            assert plan_value(sur, noise, list(plan)) == pytest.approx(one, rel=1e-12)
