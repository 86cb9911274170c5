"""Model discrimination study (obturator.validation.study) on a few runs."""

import json
import math

import numpy as np
import pytest

from obturator.calibration import load_thesis_data
from obturator.errors import InputError
from obturator.validation import run_validation


def test_study_schema_ranking_and_out_of_band_on_a_few_runs():
    d = load_thesis_data()
    lo = np.flatnonzero((d.spin_rate > 150.0) & (d.spin_rate < 200.0))[:2]
    hi = np.flatnonzero(d.spin_rate > 250.0)[:3]
    small = d.select(np.sort(np.concatenate([lo, hi])))  # two runs below 200 rad/s, three above
    st = run_validation(small, ["thesis"], t_max=5.0)
    out = json.loads(json.dumps(st.to_dict()))
    assert set(out) >= {"floor_rms_s", "floor_rms_by_band_s", "models"}
    m = out["models"][0]
    assert m["name"] == "thesis" and set(m["params"]) == {"mu_s"}
    assert set(m["params"]["mu_s"]) == {"value", "stderr", "ci95", "unit"}
    # AIC and BIC from the residual sum of squares, by hand
    n, rss = 5, 5 * m["rms_all_s"] ** 2
    assert m["aic"] == pytest.approx(n * math.log(rss / n) + 2)
    assert m["bic"] == pytest.approx(n * math.log(rss / n) + math.log(n))
    assert m["out_of_band_rms_s"]["high_to_low"] is not None
    assert "thesis" in st.table() and "replicate floor" in st.table()


def test_unknown_model_is_an_input_error():
    with pytest.raises(InputError, match="models"):
        run_validation(load_thesis_data(), ["bogus"])


def test_validate_cli_json_plot_and_bad_input(tmp_path, capsys):
    from obturator.cli import main

    csv = tmp_path / "runs.csv"
    csv.write_text(
        "spin_rate_rad_s,t_cr_s,starred\n160,0.20,0\n170,0.21,0\n300,0.27,1\n350,0.30,1\n"
        "400,0.33,1\n"
    )
    png = tmp_path / "v.png"
    args = ["validate", "--data", str(csv), "--models", "thesis", "--workers", "1"]
    assert main([*args, "--json", "--plot", str(png)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["models"][0]["name"] == "thesis" and png.stat().st_size > 1000
    assert main(["validate", "--models", "bogus"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("obturator: error: models:") and err.count("\n") == 1


def test_validate_out_directory_is_created(tmp_path):
    from obturator.cli import main

    csv = tmp_path / "runs.csv"
    csv.write_text("spin_rate_rad_s,t_cr_s\n300,0.27\n301,0.28\n400,0.33\n")
    out = tmp_path / "new"
    assert main(["validate", "--data", str(csv), "--models", "thesis", "--workers", "1",
                 "--out", str(out)]) == 0  # fmt: skip
    assert {p.name for p in out.iterdir()} == {
        "validation.json",
        "validation.txt",
        "validation.png",
    }
