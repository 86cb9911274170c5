"""Tests of the Appendix B data, the CSV loader and the chapter IV calibration."""

from __future__ import annotations

import csv
import dataclasses
import math
from importlib.resources import files
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from obturator.calibration import (
    PRINTED_SUMS_OMITTED_RUNS,
    THESIS_FIT_MIN_SPIN,
    THESIS_THETA0,
    SpinRigData,
    compare_with_thesis,
    format_comparison,
    load_spin_rig_csv,
    load_thesis_data,
    printed_thesis_sums,
    readout_to_spin_rate,
    search_printed_sums_subsets,
    thesis_least_squares,
)
from obturator.errors import InputError

CSV_PATH = files("obturator.reference").joinpath("bloomer1980_appendix_b.csv")


def _raw_rows() -> list[dict[str, str]]:
    """The packaged CSV as strings, read with the csv module (independent of the loader)."""
    lines = [ln for ln in CSV_PATH.read_text().splitlines() if not ln.startswith("#")]
    return list(csv.DictReader(lines))


@pytest.fixture(scope="module")
def data() -> SpinRigData:
    return load_thesis_data()


@pytest.fixture(scope="module")
def raw() -> list[dict[str, str]]:
    return _raw_rows()


def _plain_sums(t: np.ndarray, w: np.ndarray) -> tuple[float, float, float]:
    return float(np.sum(t**2)), float(np.sum(w**2)), float(np.sum(t * w))


# --- the transcription -------------------------------------------------------------------------


def test_packaged_csv_shape(raw):
    assert len(raw) == 54
    assert list(raw[0]) == ["readout_hz", "t_cr_s", "omega_p_printed_rad_s", "starred"]
    starred = [r["starred"] == "1" for r in raw]
    # Left column group: runs 1-3 and 30-36 starred; right group (37-54): all starred.
    assert [i + 1 for i, s in enumerate(starred[:36]) if s] == [1, 2, 3, 30, 31, 32, 33, 34, 35, 36]
    assert all(starred[36:])
    assert sum(starred) == 28
    # Spot checks against Appendix B (first and last row of each column group).
    assert raw[0] == {
        "readout_hz": "776",
        "t_cr_s": "0.274",
        "omega_p_printed_rad_s": "270.88",
        "starred": "1",
    }
    assert (raw[35]["readout_hz"], raw[35]["t_cr_s"], raw[35]["omega_p_printed_rad_s"]) == (
        "921",
        "0.3022",
        "321.49",
    )
    assert (raw[36]["readout_hz"], raw[36]["t_cr_s"]) == ("880", "0.2717")
    assert (raw[53]["readout_hz"], raw[53]["t_cr_s"]) == ("1158", "0.281")


def test_printed_precision_of_time_is_kept(raw):
    # Appendix B prints t with 3 or 4 decimals (.230, .2530): trailing zeros are kept.
    decimals = {len(r["t_cr_s"].split(".")[1]) for r in raw}
    assert decimals == {3, 4}
    assert raw[13]["t_cr_s"] == "0.230" and raw[44]["t_cr_s"] == "0.2530"


def test_starred_means_printed_spin_at_least_235_97(raw):
    for r in raw:
        assert (r["starred"] == "1") == (float(r["omega_p_printed_rad_s"]) >= 235.97)


def test_printed_omega_is_f_pi_over_9_to_printed_precision(raw):
    # Independent: f pi / 9 rounded to the number of decimals printed in each row.
    disagree = []
    for i, r in enumerate(raw, start=1):
        printed = r["omega_p_printed_rad_s"]
        dec = len(printed.split(".")[1])
        if round(int(r["readout_hz"]) * math.pi / 9, dec) != float(printed):
            disagree.append(i)
    # Every one of the 54 printed values agrees (runs 1, 24, 25, 46, 49 come within
    # 5 % of a rounding boundary, e.g. 776 Hz -> 270.8751 printed 270.88).
    assert disagree == []


def test_load_thesis_data(data, raw):
    assert len(data) == 54 and data.starred.sum() == 28
    f = np.array([float(r["readout_hz"]) for r in raw])
    np.testing.assert_array_equal(data.readout_hz, f)
    np.testing.assert_allclose(data.spin_rate, f * np.pi / 9, rtol=1e-15)
    np.testing.assert_array_equal(
        data.spin_rate_printed, [float(r["omega_p_printed_rad_s"]) for r in raw]
    )
    np.testing.assert_array_equal(data.opening_time, [float(r["t_cr_s"]) for r in raw])
    np.testing.assert_array_equal(data.run, np.arange(1, 55))
    assert "bloomer1980_appendix_b.csv" in data.source


def test_fit_subset(data):
    star = data.fit_subset()
    assert len(star) == 28 and star.starred.all()
    # The 676 Hz run computes to 235.9685 rad/s, just under the printed 235.97:
    # a threshold on the computed spin rate drops it.
    assert len(data.fit_subset(THESIS_FIT_MIN_SPIN)) == 27
    assert len(data.fit_subset(235.96)) == 28
    assert len(data.with_printed_spin_rate().fit_subset(THESIS_FIT_MIN_SPIN)) == 28


def test_data_is_frozen_and_read_only(data):
    with pytest.raises(dataclasses.FrozenInstanceError):
        data.source = "x"  # type: ignore[misc]
    with pytest.raises(ValueError):
        data.spin_rate[0] = 1.0


def test_to_dataframe(data):
    df = data.to_dataframe()
    assert list(df.columns) == [
        "readout_hz",
        "spin_rate_rad_s",
        "omega_p_printed_rad_s",
        "t_cr_s",
        "starred",
    ]
    assert df.index.name == "run" and len(df) == 54
    assert df.loc[2, "omega_p_printed_rad_s"] == 235.97


def test_readout_conversion():
    assert readout_to_spin_rate(9.0) == pytest.approx(math.pi)
    assert readout_to_spin_rate(36.0, teeth=36) == pytest.approx(2 * math.pi)


# --- chapter IV sums -------------------------------------------------------------------------


def test_starred_runs_do_not_reproduce_printed_sums(data, raw):
    # Independent: plain numpy on the csv-module rows.
    sel = [r for r in raw if r["starred"] == "1"]
    t = np.array([float(r["t_cr_s"]) for r in sel])
    w = np.array([float(r["readout_hz"]) for r in sel]) * np.pi / 9
    stt, sww, stw = _plain_sums(t, w)
    res = thesis_least_squares(data.fit_subset())
    assert res.n == 28
    assert res.sum_t2 == pytest.approx(stt, rel=1e-14)
    assert res.sum_omega2 == pytest.approx(sww, rel=1e-14)
    assert res.sum_t_omega == pytest.approx(stw, rel=1e-14)
    assert res.t2 == pytest.approx(stt / stw, rel=1e-14)
    assert stt == pytest.approx(2.5030002, abs=1e-9)
    # The printed sums are about 16 % smaller than these (documented mismatch).
    printed = printed_thesis_sums()
    assert stt / printed["sum_t2"] == pytest.approx(1.1893, abs=1e-3)
    assert sww / printed["sum_omega2"] == pytest.approx(1.1950, abs=1e-3)
    assert stw / printed["sum_t_omega"] == pytest.approx(1.1915, abs=1e-3)
    # ... yet T2 differs by only 0.19 % and mu_s by 0.16 %.
    assert res.t2 == pytest.approx(8.6437e-4, rel=1e-4)
    assert res.mu_s == pytest.approx(0.5482, abs=1e-4)


def test_subset_reproducing_printed_sums(data, raw):
    # Runs 40, 41, 45, 51 left out, printed omega used: every printed digit of the
    # three sums and of T2 is reproduced; N = 24.
    sel = [
        r for i, r in enumerate(raw, start=1) if r["starred"] == "1" and i not in (40, 41, 45, 51)
    ]
    t = np.array([float(r["t_cr_s"]) for r in sel])
    w = np.array([float(r["omega_p_printed_rad_s"]) for r in sel])
    stt, sww, stw = _plain_sums(t, w)
    assert len(sel) == 24
    assert round(stt, 7) == 2.1046884
    assert round(sww, 1) == 2841371.4
    assert math.floor(stw * 1000) / 1000 == 2430.257  # truncated, not rounded (2430.2577)
    assert round(stt / stw, 11) == 8.6603508e-4

    sub = data.exclude_runs(PRINTED_SUMS_OMITTED_RUNS).fit_subset().with_printed_spin_rate()
    res = thesis_least_squares(sub)
    assert (res.n, res.sum_t2, res.sum_omega2) == (24, pytest.approx(stt), pytest.approx(sww))
    assert res.t2 == pytest.approx(8.6603508e-4, rel=1e-8)
    printed = printed_thesis_sums()
    # sigma^2 and sigma_T^2 agree to 2e-6 and 5e-6: the thesis subtracted with the
    # rounded sum omega^2 = 2841371.4 (see test_printed_values_are_mutually_consistent).
    assert res.sigma2 == pytest.approx(printed["sigma2"], rel=2e-6)
    assert res.sigma_t2 == pytest.approx(printed["sigma_t2"], rel=1e-5)
    # The printed sigma_T = 1.97742e-5 is not the root of the printed sigma_T^2.
    assert res.sigma_t == pytest.approx(1.97942e-5, rel=1e-5)
    assert res.relative_sigma == pytest.approx(0.023, abs=0.0005)
    assert res.mu_bar == pytest.approx(0.35, abs=0.005)
    assert res.mu_s == pytest.approx(0.5471, abs=1e-4)

    # With f pi / 9 instead of the printed omega the sums miss the print.
    res_f = thesis_least_squares(data.exclude_runs(PRINTED_SUMS_OMITTED_RUNS).fit_subset())
    assert res_f.sum_omega2 == pytest.approx(2841415.5, abs=0.1)
    assert abs(res_f.sum_omega2 - printed["sum_omega2"]) > 40


def test_search_finds_the_unique_subset(data):
    hits = search_printed_sums_subsets(data, max_removed=6, max_added=1)
    assert [(h.removed, h.added, h.n) for h in hits] == [((40, 41, 45, 51), (), 24)]
    assert (
        search_printed_sums_subsets(data, max_removed=6, max_added=1, use_printed_spin=False) == []
    )
    # Which runs these are: right-hand column rows 4, 5, 9 and 15.
    df = data.to_dataframe().loc[list(PRINTED_SUMS_OMITTED_RUNS)]
    assert list(df["readout_hz"]) == [936, 983, 1063, 1255]


def test_printed_values_are_mutually_consistent():
    p = printed_thesis_sums()
    # T2 = sum t^2 / sum t omega, to the 3e-7 that truncating sum t omega explains.
    assert p["sum_t2"] / p["sum_t_omega"] == pytest.approx(p["t2"], rel=3e-7)
    # The implied N from sigma^2 = (1/N)(sum w^2 - sum t w / T2) is 24.
    n = (p["sum_omega2"] - p["sum_t_omega"] / p["t2"]) / p["sigma2"]
    assert n == pytest.approx(24.0, abs=0.001)
    # Printed sigma^2 follows from the rounded sum w^2, the unrounded sum t w
    # (2430.257672, subset above) and the printed T2.
    assert (p["sum_omega2"] - 2430.257672 / p["t2"]) / 24 == pytest.approx(p["sigma2"], abs=1e-4)
    # sigma_T^2 = sigma^2 T^4 / sum t^2 within 4e-6 of the print.
    assert p["sigma2"] * p["t2"] ** 4 / p["sum_t2"] == pytest.approx(p["sigma_t2"], rel=4e-6)
    # The printed sigma_T is NOT sqrt(sigma_T^2): 1.97942e-5 vs 1.97742e-5.
    assert math.sqrt(p["sigma_t2"]) == pytest.approx(1.97942e-5, rel=1e-5)
    assert math.sqrt(p["sigma_t2"]) / p["sigma_t"] - 1 == pytest.approx(1.01e-3, abs=1e-5)
    assert math.sqrt(p["sigma_t2"]) / p["t2"] == pytest.approx(p["relative_sigma"], abs=5e-4)
    # mu_bar = 3.03e-4 / 8.66e-4; mu_s = 0.35 / 0.63954, with 0.63954 = (2/pi) 1.00458.
    assert 3.03e-4 / p["t2"] == pytest.approx(p["mu_bar"], abs=0.005)
    assert 2 / math.pi * 1.00458 == pytest.approx(p["mean_arm"], abs=5e-6)
    assert p["mu_bar"] / p["mean_arm"] == pytest.approx(p["mu_s"], abs=5e-5)


def test_compare_with_thesis_table(data):
    res = thesis_least_squares(data.fit_subset())
    rows = compare_with_thesis(res)
    names = [r.name for r in rows]
    assert names == list(printed_thesis_sums())
    row = dict((r.name, r) for r in rows)["sum_t2"]
    assert row.computed == res.sum_t2 and row.printed == 2.1046884
    assert row.relative_difference == pytest.approx(res.sum_t2 / 2.1046884 - 1)
    text = format_comparison(rows)
    assert "sum_t2" in text and "mu_s" in text and len(text.splitlines()) == len(rows) + 1


def test_regression_directions_and_statistics(data):
    sub = data.fit_subset()
    t, w = sub.opening_time, sub.spin_rate
    res = thesis_least_squares(sub)
    # Thesis T2 is the inverse slope of omega regressed on t (residuals in omega).
    slope_w_on_t = np.linalg.lstsq(t[:, None], w, rcond=None)[0][0]
    assert res.t2 == pytest.approx(1 / slope_w_on_t, rel=1e-12)
    # Direct fit t = T2 omega.
    assert res.t2_direct == pytest.approx(np.linalg.lstsq(w[:, None], t, rcond=None)[0][0])
    assert res.t2_direct < res.t2
    # Thesis sigma^2 is the mean squared omega residual (divisor N).
    assert res.sigma2 == pytest.approx(np.mean((w - t / res.t2) ** 2), rel=1e-12)
    assert res.sigma2 == pytest.approx(
        (res.sum_omega2 - res.sum_t_omega / res.t2) / res.n, rel=1e-8
    )
    # Standard errors (N - 1) relate to the thesis's sigma_T by sqrt(N / (N - 1)).
    assert res.t2_stderr == pytest.approx(res.sigma_t * math.sqrt(res.n / (res.n - 1)))
    s_t = math.sqrt(np.sum((t - res.t2_direct * w) ** 2) / (res.n - 1))
    assert res.time_residual_std == pytest.approx(s_t)
    assert res.t2_direct_stderr == pytest.approx(s_t / math.sqrt(np.sum(w**2)))
    assert res.mu_bar == pytest.approx(3.03e-4 / res.t2)
    assert res.mu_s == pytest.approx(res.mu_bar / res.mean_arm)
    assert res.mu_s_direct == pytest.approx(3.03e-4 / res.t2_direct / res.mean_arm)
    assert res.mean_arm == pytest.approx(2 / math.pi * 1.00452, abs=5e-6)
    assert res.theta0 == THESIS_THETA0


@settings(max_examples=50, deadline=None)
@given(
    slope=st.floats(1e-5, 1e-2),
    w=st.lists(st.floats(10.0, 2000.0), min_size=2, max_size=30),
    noise=st.lists(st.floats(-0.3, 0.3), min_size=30, max_size=30),
)
def test_least_squares_invariants(slope, w, noise):
    w = np.array(w)
    t = slope * w * (1 + np.array(noise[: w.size]))
    d = SpinRigData(spin_rate=w, opening_time=t, starred=np.ones(w.size, bool))
    res = thesis_least_squares(d)
    # Cauchy-Schwarz: the omega-residual fit never gives a smaller T2 than the t-residual fit.
    assert res.t2 >= res.t2_direct * (1 - 1e-12)
    assert res.sigma2 >= 0.0
    # Exact data: both directions return the slope and zero scatter.
    exact = thesis_least_squares(
        SpinRigData(spin_rate=w, opening_time=slope * w, starred=np.ones(w.size, bool))
    )
    assert exact.t2 == pytest.approx(slope, rel=1e-12)
    assert exact.t2_direct == pytest.approx(slope, rel=1e-12)
    assert exact.sigma2 == pytest.approx(0.0, abs=1e-18 * np.sum(w**2))


def test_least_squares_needs_two_runs():
    d = SpinRigData(spin_rate=[300.0], opening_time=[0.3], starred=[True])
    with pytest.raises(InputError, match=r"\[2, inf\)"):
        thesis_least_squares(d)


# --- user CSV files --------------------------------------------------------------------------


def _write(tmp_path: Path, text: str, name: str = "rig.csv") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def test_user_csv_with_readout_and_teeth(tmp_path):
    p = _write(
        tmp_path, "# my rig\nreadout_hz,t_cr_s,starred,comment\n720,0.25,1,a\n\n360,0.2,0,b\n"
    )
    d = load_spin_rig_csv(p)
    np.testing.assert_allclose(d.spin_rate, [80 * math.pi, 40 * math.pi])
    np.testing.assert_array_equal(d.starred, [True, False])
    d36 = load_spin_rig_csv(p, teeth=36)
    np.testing.assert_allclose(d36.spin_rate, d.spin_rate / 2)
    assert d.source == str(p)


def test_user_csv_with_spin_rate(tmp_path):
    p = _write(tmp_path, "spin_rate_rad_s,t_cr_s\n300,0.26\n450.5,0.39\n")
    d = load_spin_rig_csv(p)
    assert d.readout_hz is None and not d.starred.any()
    np.testing.assert_array_equal(d.spin_rate, [300.0, 450.5])
    assert len(d.fit_subset(400.0)) == 1
    with pytest.raises(InputError, match="no starred runs"):
        d.fit_subset()
    assert list(d.to_dataframe().columns) == ["spin_rate_rad_s", "t_cr_s", "starred"]


def test_dataframe_round_trip(tmp_path, data):
    p = tmp_path / "out.csv"
    data.to_dataframe()[["spin_rate_rad_s", "t_cr_s", "starred"]].to_csv(p, index=False)
    back = load_spin_rig_csv(p)
    np.testing.assert_allclose(back.spin_rate, data.spin_rate, rtol=1e-15)
    np.testing.assert_array_equal(back.opening_time, data.opening_time)
    np.testing.assert_array_equal(back.starred, data.starred)


@pytest.mark.parametrize(
    ("text", "pattern"),
    [
        ("", r"^file: .*rig\.csv: empty file"),
        ("# only a comment\n\n", r"^file: .*rig\.csv: empty file"),
        ("readout_hz,t_cr_s\n", r"^file: .*rig\.csv: no data rows after the header at line 1"),
        ("readout_hz,comment\n700,a\n", r"^t_cr_s: .*rig\.csv, line 1: missing column 't_cr_s'"),
        # an unknown column is named with the closest known one (issue 46)
        ("readout_hz,time\n700,0.2\n", r"^time: .*line 1: unknown column 'time' \(closest known"),
        ("t_cr_s\n0.2\n", r"^spin_rate_rad_s: .*line 1: need exactly one of"),
        (
            "readout_hz,spin_rate_rad_s,t_cr_s\n700,244,0.2\n",
            r"^readout_hz: .*line 1: need exactly one of .* found both",
        ),
        (
            "readout_hz,t_cr_s\n700,0.2\n710,abc\n",
            r"^t_cr_s: .*rig\.csv, line 3: 'abc' is not a number "
            r"\(allowed range \(1e-06, 1e\+06\] s\)",
        ),
        (
            "readout_hz,t_cr_s\n700,0.2\n710,-0.1\n",
            r"^t_cr_s: .*line 3: -0\.1 s is outside the allowed range \(1e-06, 1e\+06\] s",
        ),
        (
            "readout_hz,t_cr_s\n# c\n0,0.2\n",
            r"^readout_hz: .*line 3: 0 Hz is outside the allowed range \(0, 1e\+07\] Hz",
        ),
        (
            "spin_rate_rad_s,t_cr_s\n0,0.2\n",
            r"^spin_rate_rad_s: .*line 2: 0 rad/s is outside the allowed range \(0, 1e\+06\] rad/s",
        ),
        (
            "spin_rate_rad_s,t_cr_s\nnan,0.2\n",
            r"^spin_rate_rad_s: .*line 2: 'nan' is not a number",
        ),
        ("spin_rate_rad_s,t_cr_s\n,0.2\n", r"^spin_rate_rad_s: .*line 2: '' is not a number"),
        (
            "readout_hz,t_cr_s\n700,0.2\nreadout_hz,t_cr_s\n710,0.3\n",
            r"^readout_hz: .*line 3: duplicated header \(first at line 1\)",
        ),
        (
            "readout_hz,t_cr_s,t_cr_s\n700,0.2,0.3\n",
            r"^t_cr_s: .*line 1: column 't_cr_s' appears twice",
        ),
        ("readout_hz,t_cr_s\n700\n", r"^readout_hz: .*line 2: 1 fields, expected 2"),
        (
            "readout_hz,t_cr_s,starred\n700,0.2,maybe\n",
            r"^starred: .*line 2: 'maybe' is not a flag",
        ),
    ],
)
def test_malformed_user_csv(tmp_path, text, pattern):
    with pytest.raises(InputError, match=pattern):
        load_spin_rig_csv(_write(tmp_path, text))


def test_missing_file_and_bad_teeth(tmp_path):
    with pytest.raises(InputError, match=r"^path: cannot read .*nope\.csv': No such file"):
        load_spin_rig_csv(tmp_path / "nope.csv")
    with pytest.raises(InputError, match=r"^path: .* is not a regular file"):
        load_spin_rig_csv(tmp_path)
    p = _write(tmp_path, "readout_hz,t_cr_s\n700,0.2\n")
    with pytest.raises(InputError, match=r"^teeth: .*allowed range \[1, inf\)"):
        load_spin_rig_csv(p, teeth=0)
    with pytest.raises(InputError, match=r"^teeth: 18\.5 is not a whole number"):
        load_spin_rig_csv(p, teeth=18.5)  # type: ignore[arg-type]


def test_direct_construction_validates():
    with pytest.raises(InputError, match="opening_time"):
        SpinRigData(spin_rate=[1.0, 2.0], opening_time=[0.1], starred=[True, True])
    with pytest.raises(InputError, match=r"opening_time\[1\].*allowed range \(0, inf\) s"):
        SpinRigData(spin_rate=[1.0, 2.0], opening_time=[0.1, -1.0], starred=[True, True])
