"""The bookkeeping of the exact-limit check (``benchmarks.exact_limit``): which points
are cross-checked, and how a band's errors are counted against the reference's spread.
No integration here: the numbers are made up so that every count is known."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # benchmarks/ lives at the root

from benchmarks.exact_limit import (  # noqa: E402
    BANDS,
    CHECK_SPINS,
    REGULARISED_DEFAULT,
    SET_VALUED_DEFAULT,
    band_table,
    check_indices,
    with_fields,
)


def test_check_indices_take_the_nearest_point_inside_the_range():
    spins = np.linspace(40.0, 1000.0, 2000)
    idx = check_indices(spins)
    assert idx.size == len(CHECK_SPINS)  # every target is inside 40-1000 and distinct
    assert np.all(np.abs(spins[idx] - np.array(CHECK_SPINS)) <= 0.5 * (spins[1] - spins[0]))
    assert check_indices(np.linspace(100.0, 700.0, 50)).size == sum(
        100 <= t <= 700 for t in CHECK_SPINS
    )


def test_more_checks_where_stick_slip_lasts_longest():
    low = sum(t < 100 for t in CHECK_SPINS)
    assert low / 60.0 > 5 * (len(CHECK_SPINS) - low) / 900.0  # per rad/s: 40-100 vs 100-1000
    for lo, hi in BANDS:  # every band of 40-1000 rad/s has a cross-check
        assert any(lo <= t < hi for t in CHECK_SPINS)


def test_band_counts_errors_over_target_and_over_the_spread():
    spins = np.array([41.0, 45.0, 50.0, 70.0, 80.0, 250.0])
    err = np.array([2e-6, -5e-7, 4e-6, 3e-6, np.nan, 1e-9])
    # the 60-100 band's reference is uncertain to 5e-6, the 40-60 band's to 1e-7
    rows = band_table(spins, {"p": err}, np.array([45.0, 70.0]), np.array([1e-7, 5e-6]))
    by = {r["band"]: r for r in rows}
    assert by["40-60"]["p"]["n_over_1e-6"] == 2 and by["40-60"]["p"]["n_wrong"] == 2
    assert by["40-60"]["p"]["worst"] == pytest.approx(4e-6)
    assert by["60-100"]["p"]["n_over_1e-6"] == 1 and by["60-100"]["p"]["n_wrong"] == 0
    assert by["60-100"]["p"]["n_nan"] == 1
    assert np.isnan(by["210-250"]["reference_spread"]) and by["210-250"]["n_checked"] == 0


def test_with_fields_overrides_the_named_options_only():
    o = with_fields(REGULARISED_DEFAULT, "friction_family=tanh,friction_width=1e-9,rtol=1e-10")
    assert (o.friction_family, o.friction_width, o.rtol) == ("tanh", 1e-9, 1e-10)
    assert o.atol == REGULARISED_DEFAULT.atol and o.method == REGULARISED_DEFAULT.method


def test_the_two_paths_are_the_regularised_and_the_set_valued_law():
    assert SET_VALUED_DEFAULT.method == "set-valued"
    assert REGULARISED_DEFAULT.method != "set-valued"
