"""A validation fit the runs cannot identify is never reported as a success (issue 46).

Runs at 300-380 rad/s open after about 0.2 s on the thesis's rig (Appendix B); with a
horizon of 0.05 s the model opens none of them, every run is censored, and no
parameter is identified.
"""

from __future__ import annotations

import numpy as np

from obturator.validation import CANDIDATES
from obturator.validation.fit import fit_candidate


def test_every_run_censored_is_not_a_success():
    w = np.array([300.0, 320.0, 340.0, 360.0, 380.0])
    y = np.array([0.20, 0.21, 0.22, 0.23, 0.24])
    fit = fit_candidate(CANDIDATES["mu"], w, y, t_max=0.05, spin_sd=0.0, noise="pooled")
    assert not np.any(np.isfinite(fit.model))
    assert fit.success is False
    assert fit.message.startswith("not identified: the model opens none of the 5 runs")
