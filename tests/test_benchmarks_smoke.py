"""The benchmark's plain-Python baseline computes the package's model (correctness, not timing)."""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # benchmarks/ lives at the root

from benchmarks.baseline import initial_state, model_from_case, solve_baseline  # noqa: E402
from benchmarks.run import _agreement  # noqa: E402
from obturator.core.dynamics import rhs  # noqa: E402
from obturator.model.case import initial_state as package_initial_state  # noqa: E402
from obturator.model.cases import flight_case, rig_case  # noqa: E402
from obturator.solve import SolverOptions, opening_time, pack_parameters  # noqa: E402

CASES = {
    "rig-200": rig_case(200.0, 0.5473),
    "rig-700": rig_case(700.0, 0.35),
    "flight": flight_case(),
}


def _package_rhs(case, y: np.ndarray) -> np.ndarray:
    p = pack_parameters(case, SolverOptions())
    dy = np.empty(8)
    rhs(0.0, y, p, dy)
    return dy


def _random_states(case, rng: np.random.Generator, n: int, rate_scale: float) -> np.ndarray:
    ys = np.empty((n, 8))
    ys[:, :4] = rng.normal(size=(n, 4)) * rng.uniform(0.5, 2.0, size=(n, 1))  # |q| != 1 too
    ys[:, 4:7] = rng.normal(size=(n, 3)) * rate_scale
    ys[:, 7] = case.spin_rate
    return ys


@pytest.mark.parametrize("name", list(CASES))
@pytest.mark.parametrize("rate_scale", [1e-3, 1.0, 30.0], ids=["slow", "spin", "turbulent"])
def test_baseline_rhs_matches_package(name, rate_scale):
    """Same derivative at random states to 1e-10 relative (per block: attitude, rates)."""
    case = CASES[name]
    model = model_from_case(case)
    rng = np.random.default_rng(20240611)
    for y in _random_states(case, rng, 50, rate_scale * case.spin_rate):
        ref = _package_rhs(case, y)
        got = model.rhs(0.0, y)
        assert got.shape == (8,)
        for block in (slice(0, 4), slice(4, 7)):
            scale = np.max(np.abs(ref[block]))
            np.testing.assert_allclose(got[block], ref[block], rtol=1e-10, atol=1e-10 * scale)
        assert got[7] == ref[7] == 0.0


def test_turbulent_branch_is_exercised():
    case = CASES["flight"]
    model = model_from_case(case)
    assert math.isfinite(model.transition_rate)
    assert 30.0 * case.spin_rate > model.transition_rate  # the "turbulent" states cross it


def test_baseline_initial_state_and_event_match_package():
    for case in CASES.values():
        model = model_from_case(case)
        y0 = initial_state(model)
        np.testing.assert_allclose(y0, package_initial_state(case.theta0, case.spin_rate))
        assert model.nutation(0.0, y0) == pytest.approx(case.theta0 - case.opening_angle)


def test_baseline_covers_only_the_thesis_constant_spin_model():
    with pytest.raises(ValueError):
        model_from_case(rig_case(300.0, 0.5, torque_model="coulomb"))
    with pytest.raises(ValueError):
        model_from_case(rig_case(300.0, 0.5, spin_mode="free"))


def test_baseline_opening_time_agrees_with_package():
    """The LSODA baseline reaches the same t_cr (1e-3 relative, the benchmark's criterion)."""
    case = rig_case(300.0, 0.5473)
    t_base, nfev, sol = solve_baseline(model_from_case(case))
    assert sol.status == 1 and nfev > 0
    assert t_base == pytest.approx(opening_time(case), rel=1e-3)


def test_agreement_summary():
    a = np.array([1.0, 2.0, np.nan, 4.0])
    b = np.array([1.0, 2.002, np.nan, np.nan])
    out = _agreement(a, b)
    assert out["both_opened"] == 2 and out["open_status_mismatches"] == 1
    assert out["max_rel_diff"] == pytest.approx(1 - 2.0 / 2.002)


def test_alternatives_table_has_the_package_row_and_notes_missing_libraries():
    """benchmarks.alternatives runs without the optional libraries (rows skipped, noted)."""
    from benchmarks import alternatives

    rec = alternatives.alternatives(repeat=1, rtols=(1e-6,))
    own = [r for r in rec["rows"] if r["solver"].startswith("obturator")]
    assert len(own) == 1 and abs(own[0]["t_cr_rel_error"]) < 1e-5
    names = " ".join(r["solver"] for r in rec["rows"]) + " ".join(rec["notes"])
    assert "numbalsoda" in names and "diffrax" in names


def test_lanes_benchmark_record():
    """benchmarks.lanes times both paths and checks every point against the scalar one."""
    from benchmarks import lanes

    rec = lanes.measure("flight", 12, 1)
    assert rec["same_nan"] and rec["max_rel_diff_vs_scalar"] < 1e-12  # DOP853 lanes: exact
    assert rec["lanes_points_per_s"] > 0 and rec["scalar_points_per_s"] > 0
    assert rec["stiff_one_by_one_points_per_s"] > 0 and lanes.agrees(rec)
    assert rec["max_rel_error_vs_reference"] < 1e-6
    # a record beyond the stated accuracy is reported as disagreeing
    assert not lanes.agrees(rec | {"tcr_rtol": "1e-6", "max_rel_diff_vs_scalar": 2e-6})
