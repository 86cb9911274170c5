"""Replicate floor of the spin-rig data (obturator.validation.floor), against hand sums."""

import math

import numpy as np
import pytest

from obturator.calibration import load_thesis_data
from obturator.errors import InputError
from obturator.validation import cluster_runs, replicate_floor


def test_floor_of_a_tiny_data_set_by_hand():
    # clusters {100, 101}, {200, 202, 203.5}, {400} (gaps 1, 2, 1.5 <= 3.5; 99, 196.5 > 3.5)
    w = [100.0, 101.0, 200.0, 202.0, 203.5, 400.0]
    t = [0.30, 0.34, 0.20, 0.21, 0.25, 0.50]
    assert cluster_runs(w).tolist() == [0, 0, 1, 1, 1, 2]
    # SS_w = 2 * 0.02^2 + (0.02^2 + 0.01^2 + 0.03^2) [means 0.32 and 0.22] = 0.0022
    ss = 2 * 0.02**2 + (0.02**2 + 0.01**2 + 0.03**2)
    f = replicate_floor(w, t)
    assert f.df == 6 - 3 and f.n_clusters == 3
    assert f.pooled_sd_s == pytest.approx(math.sqrt(ss / 3), rel=1e-12)
    assert f.rms_about_means_s == pytest.approx(math.sqrt(ss / 6), rel=1e-12)
    sd_low, df_low, n_low = f.by_band["<120"]
    assert (df_low, n_low) == (1, 2) and sd_low == pytest.approx(math.sqrt(2 * 0.02**2))
    assert f.by_band[">300"][1] == 0 and math.isnan(f.by_band[">300"][0])  # a singleton


def test_thesis_data_floor_is_finite_and_every_run_is_counted():
    d = load_thesis_data()
    f = replicate_floor(d.spin_rate, d.opening_time)
    assert f.n_runs == 54 and sum(v[2] for v in f.by_band.values()) == 54
    assert 0.0 < f.rms_about_means_s < f.pooled_sd_s < 0.2
    assert f.df == 54 - f.n_clusters
    assert np.all(np.diff(np.unique(f.labels)) == 1)


def test_bad_input():
    with pytest.raises(InputError, match="spin_rate"):
        cluster_runs([])
    with pytest.raises(InputError, match="opening_time"):
        replicate_floor([100.0, 101.0], [0.2, math.nan])
