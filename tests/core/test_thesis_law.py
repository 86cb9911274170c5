"""The thesis's torque law is written once: an edit of it moves every path that integrates.

:mod:`obturator.core.thesis_law` holds the parts of the thesis law (viscous coefficient,
Eqs. 39/41/42; the sliding-friction moment arm, Eq. 61 and Appendix A; the algebraic
regularisation) that both the generic right-hand side
(:func:`obturator.core.dynamics.applied_torque`) and the specialised kernel (the default
path of the scalar DOP853 and Radau IIA and of both lanes) are built from. The test
copies the package, edits the rig's arm weights in that one module (as a contributor
correcting Eq. 61 would), and integrates in a fresh process with a fresh compile cache:
every path must move, and the paths must still agree with each other as documented
(DOP853 lanes = scalar DOP853 bit for bit, Radau lanes within 1e-6 of the scalar
``auto``). The reference is the unedited package itself (same points, this process).
"""

from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import obturator

# the lanes themselves, also for groups lanes_pay_from would run one by one
pytestmark = pytest.mark.usefixtures("lanes_always")

MU_S = 0.5473  # thesis's fitted rig value
SLIDING = (300.0, 450.0, 650.0)  # rig spins DOP853 integrates without stiffness [rad/s]
STICKING = (110.0, 130.0, 150.0)  # near-stick spins DOP853 hands to Radau IIA [rad/s]
#: the edit: the rig's arm weights (b_X, b_Z) = (0, 1) of Eq. (61) become (0, 0.8), a
#: shorter arm for slip about the spin axis (b_X > 0 would let the single bottom contact
#: hold torque about the gravity axis X, and the near-stick points then never open)
RIG_ARM = ("        return 0.0, 1.0\n", "        return 0.0, 0.8\n")


def measure() -> dict[str, object]:
    """t_cr [s] of the rig points along every path (run in this or a fresh process)."""
    from obturator.model.cases import rig_case
    from obturator.solve import SolverOptions, many, opening_time

    def t_cr(spins, method="regularised", **options):
        opts = SolverOptions(method=method, **options)
        return [opening_time(rig_case(w, MU_S), opts) for w in spins]

    # the Radau IIA lanes take every stiff point (radau_lanes, the default)
    cases = [rig_case(w, MU_S) for w in SLIDING + STICKING]
    lanes, _, stats = many.opening_times(cases, SolverOptions(method="regularised"))
    return {
        "scalar_radau": t_cr(SLIDING + STICKING, method="radau"),
        # regularised: DOP853 alone on the sliding points, handing over to Radau IIA on the
        # others (the default auto gives the sticking ones to the set-valued solver)
        "scalar_auto": t_cr(SLIDING + STICKING),
        "generic_tanh": t_cr(SLIDING, friction_family="tanh"),
        "lanes_dop853": [float(t) for t in lanes[: len(SLIDING)]],
        "lanes_radau": [float(t) for t in lanes[len(SLIDING) :]],
        "n_stiff": stats["n_stiff"],
    }


def _measure_edited(tmp_path: Path) -> dict[str, object]:
    src = Path(obturator.__file__).resolve().parent
    pkg = tmp_path / "src" / "obturator"
    shutil.copytree(src, pkg, ignore=shutil.ignore_patterns("__pycache__"))
    law = pkg / "core" / "thesis_law.py"
    text = law.read_text(encoding="utf-8")
    assert text.count(RIG_ARM[0]) == 1
    law.write_text(text.replace(*RIG_ARM), encoding="utf-8")
    env = dict(os.environ, PYTHONPATH=f"{tmp_path / 'src'}{os.pathsep}{Path(__file__).parent}")
    env["NUMBA_CACHE_DIR"] = str(tmp_path / "numba")  # compile the edited core afresh
    code = (
        "import json, obturator, test_thesis_law as t; "
        f"assert obturator.__file__.startswith({str(pkg)!r}); print(json.dumps(t.measure()))"
    )
    run = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=3000
    )
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout.strip().splitlines()[-1])


@pytest.mark.slow
def test_an_edit_of_the_law_moves_every_path(tmp_path):
    before = measure()
    after = _measure_edited(tmp_path)
    assert before["n_stiff"] == len(STICKING) and after["n_stiff"] >= 1  # Radau lanes ran
    for path in ("scalar_radau", "scalar_auto", "generic_tanh", "lanes_dop853", "lanes_radau"):
        b, a = np.array(before[path]), np.array(after[path])
        assert np.all(np.isfinite(a)), path
        # an arm up to 10 % shorter moves t_cr by 7e-4 (150 rad/s) to 1.2e-2: far more
        # than the paths' rounding (1e-6 between Radau lanes and scalar, ~1e-8 typical)
        assert np.all(np.abs(a / b - 1.0) > 1e-4), (path, b, a)
    # and the edited paths still agree as documented (docs/architecture.md)
    n = len(SLIDING)
    for state in (before, after):
        assert state["lanes_dop853"] == state["scalar_auto"][:n]  # bit for bit
        np.testing.assert_allclose(state["lanes_radau"], state["scalar_auto"][n:], rtol=1e-6)
        assert all(math.isfinite(t) for t in state["lanes_radau"])
