"""A synthetic campaign at the designed settings, fed to ``obturator validate`` beside the
Appendix B runs: the evidence must move toward the model that generated it.

The campaign is the plan ``obturator design-experiment`` recommended with its defaults
before its feasibility check (8 runs at 200 rad/s released at 70 deg with a 5.58 mm hole,
which the rig cannot hold, 2 at 225.8 rad/s with a 3.75 mm hole), kept as a synthetic
test of the validation's model choice; its times made by the package's exact model of the
generating candidate plus the replicate noise of the run's spin band (thesis Appendix B
replicates). The data go through the CSV reader and the command line as a user's would
(per-run ``theta0_deg`` and ``hole_radius_mm`` columns). Seeded; about 45 s, so marked
slow (CI runs it).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from obturator.calibration.data import readout_to_spin_rate
from obturator.cli import main
from obturator.design import Setting
from obturator.design.noise import ReplicateNoise
from obturator.design.surrogate import opening_time_table

pytestmark = pytest.mark.slow

APPENDIX_B = Path(__file__).parents[2] / "src/obturator/reference/bloomer1980_appendix_b.csv"
#: Replicate SD per spin band [s] (pooled pure error of Appendix B's replicate clusters).
BANDS = {"<120": 0.104, "120-200": 0.0121, "200-300": 0.0127, ">300": 0.0385}
PLAN = [Setting(200.0, 70.0, 5.58e-3)] * 8 + [Setting(225.8, 87.25, 3.75e-3)] * 2
#: Each generating model at (about) its all-run fit to Appendix B.
TRUTHS = {
    "strengthening": {"mu_s": 0.765, "speed_ratio": 0.270, "slip_speed": 0.127},
    "theta0": {"mu_s": 0.52, "theta0_deg": 85.3},
}
MODELS = "strengthening,theta0"


def _write_runs(path: Path, campaign_of: str | None, seed: int = 7) -> Path:
    """Appendix B's 54 runs, then (if given) ten synthetic runs of the generating model."""
    rows = ["spin_rate_rad_s,t_cr_s,starred,theta0_deg,hole_radius_mm"]
    for line in APPENDIX_B.read_text().splitlines():
        if line and not line.startswith(("#", "readout")):
            hz, t_cr, _, starred = line.split(",")
            rows.append(f"{float(readout_to_spin_rate(float(hz))):.6f},{t_cr},{starred},,")
    if campaign_of is not None:
        task = {
            "model": campaign_of,
            "values": [TRUTHS[campaign_of]],
            "settings": [s.to_dict() for s in PLAN],
            "t_max": 20.0,
        }
        (row,) = opening_time_table(task)
        t = np.array(row, dtype=float)
        w = np.array([s.spin_rate for s in PLAN])
        y = t + np.random.default_rng(seed).standard_normal(t.size) * ReplicateNoise(
            BANDS, {}, 0.05
        ).at(w, t)
        rows += [
            f"{s.spin_rate},{v:.5f},0,{s.theta0_deg},{s.hole_radius * 1e3:.2f}"
            for s, v in zip(PLAN, y, strict=True)
        ]
    path.write_text("\n".join(rows) + "\n")
    return path


def _validate(path: Path, capsys) -> tuple[str, float]:
    """(recommended model, AIC of theta0 minus AIC of strengthening) from the CLI's JSON."""
    argv = ["validate", "--data", str(path), "--models", MODELS, "--no-profile", "--json"]
    assert main([*argv, "--no-progress"]) == 0
    out = json.loads(capsys.readouterr().out)
    aic = {m["name"]: m["aic"] for m in out["models"]}
    assert out["models"][0]["ndata"] == (54 if "none" in path.name else 64)
    return out["recommended"], aic["theta0"] - aic["strengthening"]


def test_a_designed_campaign_moves_validate_to_the_generating_model(tmp_path, capsys):
    _, before = _validate(_write_runs(tmp_path / "none.csv", None), capsys)
    rec_s, after_s = _validate(_write_runs(tmp_path / "s.csv", "strengthening"), capsys)
    rec_t, after_t = _validate(_write_runs(tmp_path / "t.csv", "theta0"), capsys)
    # strengthening generated: recovered, and its lead grows by more than a decisive margin
    # (2 ln 10 = 4.6 AIC units is a likelihood ratio of 10)
    assert rec_s == "strengthening"
    assert after_s - before > 4.6
    # theta0 generated: ten designed runs take back more than 4 x that margin of the lead
    # strengthening holds on Appendix B alone
    assert before - after_t > 4 * 4.6
    # and the two worlds end far apart: the campaign decides between them
    assert after_s - after_t > 6 * 4.6
