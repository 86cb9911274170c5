"""A small runs file shared by the validation tests."""

from __future__ import annotations

import numpy as np
import pytest

from obturator.validation import CANDIDATES
from obturator.validation.evaluate import ModelEvaluator


@pytest.fixture(scope="session")
def tiny_csv(tmp_path_factory):
    """Eight runs made with the "mu" candidate at mu_s = 0.55 plus millisecond noise."""
    d = tmp_path_factory.mktemp("val")
    w = np.array([150.0, 151.0, 180.0, 230.0, 231.0, 300.0, 302.0, 400.0])
    ev = ModelEvaluator(CANDIDATES["mu"], 5.0)
    t = ev.opening_times([0.55], w) + np.array([3, -2, 1, -4, 2, 5, -3, 1]) * 1e-3
    path = d / "runs.csv"
    lines = ["spin_rate_rad_s,t_cr_s,starred"] + [
        f"{a},{b:.5f},{int(a > 200)}" for a, b in zip(w, t, strict=True)
    ]
    path.write_text("\n".join(lines) + "\n")
    return path
