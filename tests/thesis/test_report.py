"""End to end: ``obturator reproduce`` and ``obturator calibrate``."""

from __future__ import annotations

import importlib
import json
import re

import numpy as np
import pytest

from obturator import calibration as cal
from obturator.cli import main
from obturator.thesis.render import to_html, to_markdown
from obturator.thesis.rows import Row

FIGURES = [
    "fig09_couette.png",
    "fig10_couette_scaled.png",
    "fig13_flight.png",
    "fig14_rig.png",
    "fig15_exact_vs_approx.png",
    "fig16_density.png",
    "fig17_hole_radius.png",
    "fig32_rig_40.png",
    "fig33_rig_100.png",
    "fig34_rig_200.png",
    "fig35_rig_500.png",
    "fig36_rig_700.png",
    "fig37_rig_1000.png",
    "fig38_eq92_data.png",
    "fig39_mu_sensitivity.png",
    "fig40_theta0_sensitivity.png",
    "fig41_theta0_data.png",
    "fig42_mu_data.png",
    "fig43_least_squares.png",
    "tcr_minimum.png",
    "calibration_residuals.png",
]
# rows that are expected to differ from the thesis by more than 2 %, and why
EXPECTED_FLAGGED = {
    "sum t^2 [all 28 starred runs]",  # the printed sums omit four starred runs
    "t_cr minimum location, Eq. 92 (mu_s = 0.5473)",  # 125 rad/s
    "t_cr minimum location, exact (mu_s = 0.5473)",  # ~185 rad/s: chapter IV's larger mu_s
    "Fig. 9 shear constant S",  # caption 1.2e-6 vs Eq. 34's 2.1e-8
    "mu_s fitted with the exact model",  # 0.588 vs the linearised 0.547
}


# the module's fixture runs a quick reproduce (~20 s)
pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def reproduced(tmp_path_factory):
    out = tmp_path_factory.mktemp("reproduce")
    rc = main(["reproduce", "--out", str(out), "--quick"])
    return rc, out


def test_reproduce_writes_every_figure_and_report(reproduced):
    rc, out = reproduced
    assert rc == 0
    for name in FIGURES:
        p = out / name
        assert p.is_file(), name
        assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    md = (out / "report.md").read_text()
    html = (out / "report.html").read_text()
    assert "| quantity | thesis value | computed | difference (%) |" in md
    assert "<th>difference (%)</th>" in html
    for text in (md, html):
        for must in ("numpy", "scipy", "numba", "pint", "dask", "rtol", "command: obturator"):
            assert must in text
        assert "friction regularisation width" in text and "family = algebraic" in text
        assert "Thesis Fig. 43 (p. 113)" in text  # captions quote the thesis
        for name in FIGURES:
            assert name in text
        assert "Bootstrap" in text


def _table(md: str) -> dict[str, list[str]]:
    rows = {}
    for line in md.splitlines():
        if line.startswith("| ") and not line.startswith("| quantity"):
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", line)[1:-1]]
            rows[cells[0]] = cells
    return rows


def test_report_table_rows_and_flags(reproduced):
    _, out = reproduced
    rows = _table((out / "report.md").read_text())
    # every SPEC section 2-3 quantity is present
    for q in (
        "C (axial inertia)",
        "A (transverse inertia)",
        "lambda = C/A - 1",
        "W (ball weight)",
        "beta_s = asin(r_s/R_s)",
        "S, Nakabayashi (Eq. 42)",
        "E(87.25 deg)",
        "T2 = sum t^2 / sum t omega [24 runs]",
        "sigma_T [24 runs]",
        "mu_s = mu_bar / ((2/pi) E) [24 runs]",
        "T1 / mu_bar (Eq. 95)",
        "T2 mu_bar (Eq. 95)",
        "F_p = pi r_p^2 (P2 - P1)",
        "normal shock P2/P1, M1 = 3",
        "Fanno choking M, fL/D = 0.102",
        "Fanno M after one f iteration",
        "flight t_cr (Table 1, mu_s = 0.35)",
        "viscous only (Fig. 9) opens within 0.1 s",
    ):
        assert q in rows, q
    flagged = {q for q, c in rows.items() if c[3] not in ("—", "") and abs(float(c[3])) > 2.0}
    assert flagged == EXPECTED_FLAGGED
    assert rows["flight t_cr (Table 1, mu_s = 0.35)"][6] == "pass"
    # Figs. 32-37: the exact model opens at every spin from 40 to 1000 rad/s
    assert rows["exact model opens at every spin 40-1000 rad/s (mu_s = 0.35)"][2] == "yes"
    assert rows["viscous only (Fig. 9) opens within 0.1 s"][2] == "no"
    assert float(rows["F_p = pi r_p^2 (P2 - P1)"][2]) == pytest.approx(64.67, abs=0.01)


def test_row_difference_and_escaping():
    r = Row("x", 2.0, 2.1, "m")
    assert r.difference == pytest.approx(5.0)
    assert Row("y", None, 1.0).difference is None
    assert Row("z", "< 0.1 s", 0.02).difference is None
    ctx = {
        "rows": [Row("a|b <c>", 1.0, 1.0)],
        "flagged": [],
        "fit_text": "<fit>",
        "figures": [("f.png", "F", "caption <x>")],
        "versions": {"numpy": "1"},
        "solver": ["rtol"],
        "provenance": ["command: obturator <y>"],
        "mode": "quick",
        "elapsed": 1.0,
        "images": {},
        "explorer": "",
    }
    assert "a\\|b <c>" in to_markdown(ctx)
    h = to_html(ctx)
    assert "a|b &lt;c&gt;" in h and "&lt;fit&gt;" in h
    assert "caption &lt;x&gt;" in h and "obturator &lt;y&gt;" in h


# ---------------------------------------------------------------------------
# calibrate


@pytest.fixture(scope="module")
def rig_csv(tmp_path_factory):
    spins = np.linspace(240.0, 450.0, 6)
    t = cal.model_opening_times(spins, mu_s=0.5)
    p = tmp_path_factory.mktemp("cal") / "rig.csv"
    rows = "".join(f"{w:.12g},{x:.12g},1\n" for w, x in zip(spins, t, strict=True))
    p.write_text("spin_rate_rad_s,t_cr_s,starred\n" + rows)
    return p


def test_calibrate_cli_json_and_plot(rig_csv, tmp_path, capsys):
    png = tmp_path / "res.png"
    rc = main(["calibrate", str(rig_csv), "--json", "--plot", str(png), "--bootstrap", "0"])
    assert rc == 0
    d = json.loads(capsys.readouterr().out)
    assert d["parameters"]["mu_s"]["value"] == pytest.approx(0.5, abs=1e-3)
    assert d["ndata"] == 6
    assert png.read_bytes()[:4] == b"\x89PNG"


def test_calibrate_cli_text_report(rig_csv, capsys):
    rc = main(["calibrate", str(rig_csv), "--min-spin", "300", "--bootstrap", "0"])
    assert rc == 0
    out = capsys.readouterr().out
    assert "mu_s" in out and "omega_p >= 300 rad/s" in out


@pytest.mark.parametrize(
    ("content", "args"),
    [
        ("readout_hz,time\n700,0.2\n", []),  # missing t_cr_s
        ("readout_hz,t_cr_s\n700,abc\n", []),  # not a number
        ("spin_rate_rad_s,t_cr_s\n300,0.3\n400,0.35\n", ["--min-spin", "350"]),  # 1 run
        ("spin_rate_rad_s,t_cr_s\n300,0.3\n400,0.35\n", ["--theta0-deg", "20"]),  # < beta_s
    ],
)
def test_calibrate_cli_bad_input_is_one_line_exit_2(tmp_path, capsys, content, args):
    p = tmp_path / "bad.csv"
    p.write_text(content)
    assert main(["calibrate", str(p), "--bootstrap", "0", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("obturator: error:")


def test_calibrate_cli_missing_file(tmp_path, capsys):
    assert main(["calibrate", str(tmp_path / "none.csv")]) == 2
    assert capsys.readouterr().err.startswith("obturator: error:")


def test_an_interrupted_reproduce_resumes_its_finished_studies(tmp_path, monkeypatch):
    """The studies finished before an interruption come from report.partial.jsonl (not
    recomputed), equal to what they were; the store goes once the report is written."""
    from obturator.runs import Runner, sidecar_path

    rep = importlib.import_module("obturator.thesis.reproduce")  # the package re-exports
    calls: list[str] = []
    couette, density = rep.couette_study, rep.density_study

    def counted(*args, **kwargs):
        calls.append("couette")
        return couette(*args, **kwargs)

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(rep, "couette_study", counted)
    monkeypatch.setattr(rep, "density_study", interrupted)
    store = tmp_path / "report"
    with pytest.raises(KeyboardInterrupt):
        rep.reproduce(tmp_path, quick=True, validation=False, runner=Runner(store=store))
    assert calls == ["couette", "couette"] and sidecar_path(store).is_file()
    monkeypatch.setattr(rep, "density_study", density)
    runner = Runner(store=store)
    res = rep.reproduce(tmp_path, quick=True, validation=False, runner=runner)
    assert calls == ["couette", "couette"]  # both Couette studies came from the store
    assert runner.n_resumed == 4  # Figs. 9-10, Fig. 9 (caption), Figs. 13-14, Fig. 15
    assert not sidecar_path(store).exists() and res.report_html.is_file()
    # an independent run of the first study: the restored one is the same, to the bit
    fresh = couette(n_points=rep._settings(True)["n_points"])
    assert fresh.identical(res.studies["couette"])
