"""The fit engine and the fit-parameter registry (obturator.fitting, params.FIT_SPECS).

Reference values are closed forms: ordinary least squares of a straight line
(normal equations, sigma^2 (X^T X)^-1), the Student-t interval, a quadratic
profile likelihood whose 95 % limits are x0 +- sqrt(chi2_1(0.95)) s.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import stats

from obturator.errors import InputError
from obturator.fitting import (
    CHI2_95,
    FIT_PARAMETERS,
    FitParameter,
    LeastSquaresSettings,
    ParameterSet,
    central_jacobian,
    covariance_internal,
    minimize_bounded_scalar,
    minimize_least_squares,
    profile_limit,
    registered,
    wald,
)
from obturator.params import FIT_PARAMS, FIT_SPECS, PARAMS

# ----------------------------------------------------------------------------- registry


def test_one_row_per_parameter_each_bound_argued():
    assert set(FIT_SPECS) == set(FIT_PARAMS) == set(FIT_PARAMETERS)
    for name, spec in FIT_SPECS.items():
        lo, hi = spec.bounds
        assert lo < hi, name
        assert lo <= spec.plausible[0] <= spec.plausible[1] <= hi, name
        assert lo <= spec.start <= hi, name
        # every reason cites the thesis (chapter, equation, table, figure or appendix)
        assert any(w in spec.reason for w in ("chapter", "Eq.", "Table 1", "Fig.", "Appendix")), (
            name
        )
        if spec.transform == "log10":
            assert lo > 0.0, name
        p = FIT_PARAMETERS[name]
        assert (p.unit, p.bounds, p.value) == (PARAMS[name].unit, spec.bounds, spec.start)
        # the physical input range (sweeps, config) admits every fitted value
        if PARAMS[name].range is not None:
            assert PARAMS[name].range.contains(lo) or lo == PARAMS[name].range.lo, name


def test_patch_radius_start_is_the_hertz_radius():
    """The registry writes the Hertz radius as a number (params is vocabulary);
    it must stay the model's value for the Table 1 rig."""
    from obturator.model.torques import hertz_patch_radius
    from obturator.reference import TABLE1

    a = hertz_patch_radius(
        TABLE1["rig_weight"], TABLE1["ball_radius"], TABLE1["gap"], seat_material="lucite"
    )
    assert FIT_SPECS["patch_radius"].start == pytest.approx(a, rel=1e-15)


def test_calibration_and_validation_read_the_same_rows():
    from obturator.validation.candidates import PARAMETERS

    for k, p in PARAMETERS.items():
        assert p == FIT_PARAMETERS[k]
    with pytest.raises(InputError, match="^fit: 'bogus'; allowed: mu_s"):
        registered("bogus")


def test_validation_parameter_is_a_deprecated_alias():
    import obturator.validation as v

    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        assert v.Parameter is FitParameter
    assert any(issubclass(x.category, DeprecationWarning) for x in w)


@given(st.sampled_from(sorted(FIT_PARAMETERS)), st.floats(0.0, 1.0))
def test_transform_round_trip_and_derivative(name, u):
    p = FIT_PARAMETERS[name]
    lo, hi = p.internal_bounds()
    x = lo + u * (hi - lo)
    assert p.to_internal(p.from_internal(x)) == pytest.approx(x, rel=1e-12, abs=1e-12)
    h = 1e-6 * max(abs(x), 1.0)
    fd = (p.from_internal(x + h) - p.from_internal(x - h)) / (2 * h)
    assert p.derivative(x) == pytest.approx(fd, rel=1e-6)


# ----------------------------------------------------------------------------- engine


def _line_problem():
    rng = np.random.default_rng(5)
    t = np.linspace(0.0, 1.0, 25)
    y = 0.3 + 1.7 * t + 0.05 * rng.standard_normal(t.size)
    params = ParameterSet(
        (
            FitParameter("a", 0.0, bounds=(-10.0, 10.0)),
            FitParameter("b", 1.0, bounds=(-10.0, 10.0), scale=2.0),
        )
    )
    return t, y, params


def test_least_squares_line_matches_normal_equations_and_student_t():
    t, y, params = _line_problem()

    def resid(x):
        a, b = params.from_internal(x)
        return a + b * t - y

    box = params.internal_bounds()
    best = minimize_least_squares(resid, params.start([0.0, 1.0]), box, LeastSquaresSettings())
    X = np.column_stack([np.ones_like(t), t])
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    assert best.success
    assert params.from_internal(best.x) == pytest.approx(coef, abs=1e-9)
    jac = central_jacobian(resid, best.x, box, 1e-4)
    r = resid(best.x)
    dof = t.size - 2
    redchi = float(r @ r) / dof
    est = wald(params, best.x, covariance_internal(jac, redchi), dof)
    cov = redchi * np.linalg.inv(X.T @ X)
    np.testing.assert_allclose(est.covariance, cov, rtol=1e-7)
    tq = stats.t.ppf(0.975, dof)
    for j, k in enumerate(("a", "b")):
        se = math.sqrt(cov[j, j])
        assert est.stderr[k] == pytest.approx(se, rel=1e-7)
        assert est.ci95[k] == pytest.approx((coef[j] - tq * se, coef[j] + tq * se), rel=1e-7)
    assert est.correlation[0, 1] == pytest.approx(cov[0, 1] / math.sqrt(cov[0, 0] * cov[1, 1]))


def test_evaluation_budget_is_reported_as_exhausted_and_the_cost_is_half_the_squares():
    """Rosenbrock's valley (minimum 0 at (1, 1), closed form): a budget of 5 evaluations
    stops short and says so; without one the optimiser reaches the minimum."""

    def resid(x):
        return np.array([10.0 * (x[1] - x[0] ** 2), 1.0 - x[0]])

    box = (np.array([-3.0, -3.0]), np.array([3.0, 3.0]))
    x0 = np.array([-1.2, 1.0])
    short = minimize_least_squares(resid, x0, box, LeastSquaresSettings(max_nfev=5))
    assert short.exhausted and not short.success and short.nfev == 5
    assert short.cost == pytest.approx(0.5 * float(np.sum(resid(short.x) ** 2)), rel=1e-12)
    full = minimize_least_squares(resid, x0, box, LeastSquaresSettings())
    assert full.success and not full.exhausted
    np.testing.assert_allclose(full.x, [1.0, 1.0], atol=1e-6)
    assert full.cost < 1e-12 < short.cost


def test_wald_interval_is_clipped_to_the_bounds_and_uses_the_log_scale():
    p = ParameterSet((FitParameter("v", 0.1, "m/s", bounds=(1e-3, 5.0), transform="log10"),))
    x = p.to_internal([0.1])
    # se of 0.5 decades: the upper limit 0.1 x 10^(t 0.5) stays inside, the lower too
    est = wald(p, x, np.array([[0.25]]), dof=10)
    tq = stats.t.ppf(0.975, 10)
    assert est.ci95["v"] == pytest.approx((0.1 * 10 ** (-tq * 0.5), 0.1 * 10 ** (tq * 0.5)))
    assert est.stderr["v"] == pytest.approx(0.1 * math.log(10) * 0.5)  # delta method
    # two decades: both sides reach the bounds (not identified there)
    est = wald(p, x, np.array([[4.0]]), dof=10)
    assert est.ci95["v"] == pytest.approx((1e-3, 5.0))


def test_central_jacobian_steps_stay_inside_the_bounds():
    seen = []

    def f(x):
        seen.append(float(x[0]))
        return np.array([x[0] ** 2])

    jac = central_jacobian(f, np.array([1.0]), (np.array([0.0]), np.array([1.0])), 1e-3)
    assert max(seen) <= 1.0
    assert jac[0, 0] == pytest.approx(2.0, rel=1e-3)  # one-sided at the bound


@pytest.mark.parametrize("jac", ["2-point", "3-point"])
def test_prefetch_sees_every_jacobian_point_first_and_changes_nothing(jac):
    # A nonlinear problem (exponential decay, three parameters): with a prefetch that
    # records the points it is handed, every point the finite differences then evaluate
    # was handed over before (so a batched model answers them from its cache), and the
    # optimum, its evaluation count and the central Jacobian are the same to the bit.
    t = np.linspace(0.0, 3.0, 20)
    y = 2.0 * np.exp(-1.3 * t) + 0.1 + 0.01 * np.sin(7.0 * t)

    def resid(x):
        a, b, c = x
        return a * np.exp(-b * t) + c - y

    box = (np.array([0.0, 0.0, -1.0]), np.array([10.0, 10.0, 1.0]))
    x0 = np.array([1.0, 0.5, 0.0])
    settings = LeastSquaresSettings(jac)
    handed: list[tuple[float, ...]] = []
    batches: list[int] = []

    def prefetch(points):
        batches.append(len(points))
        handed.extend(tuple(p) for p in points)

    evaluated: list[tuple[float, ...]] = []

    def recording(x):
        evaluated.append(tuple(x))
        return resid(x)

    plain = minimize_least_squares(resid, x0, box, settings)
    fetched = minimize_least_squares(recording, x0, box, settings, prefetch=prefetch)
    np.testing.assert_array_equal(plain.x, fetched.x)
    assert plain.nfev == fetched.nfev
    assert batches and set(batches) == {3 if jac == "2-point" else 6}
    assert set(handed) <= set(evaluated)
    assert len(evaluated) - len(handed) == fetched.nfev  # the rest: the optimiser's steps
    handed.clear()
    j0 = central_jacobian(resid, plain.x, box, 1e-3)
    j1 = central_jacobian(resid, plain.x, box, 1e-3, prefetch=prefetch)
    np.testing.assert_array_equal(j0, j1)
    assert len(handed) == 6


def test_profile_limit_of_a_quadratic_likelihood():
    x0, s = 2.0, 0.3

    def signed_root(x):  # 2 delta nll = ((x - x0)/s)^2
        return (x - x0) / s

    z = math.sqrt(CHI2_95)
    lo = profile_limit(signed_root, x0, -1, (-10.0, 10.0), x0 - 1.5 * s)
    hi = profile_limit(signed_root, x0, 1, (-10.0, 10.0), math.nan)
    assert lo == pytest.approx(x0 - z * s, rel=1e-12)
    assert hi == pytest.approx(x0 + z * s, rel=1e-12)
    # a bound before the threshold: the bound
    assert profile_limit(signed_root, x0, 1, (-10.0, 2.2), x0 + s) == 2.2


def test_bounded_scalar_minimum():
    x, f = minimize_bounded_scalar(lambda v: (v - 0.37) ** 2 + 1.0, (0.0, 1.0), 1e-10)
    assert x == pytest.approx(0.37, abs=1e-8) and f == pytest.approx(1.0)
