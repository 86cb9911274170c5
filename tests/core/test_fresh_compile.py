"""Freshly compiled and cached machine code give the same t_cr, bit for bit.

A process that compiles the integrators and one that loads them from numba's cache run
the same points; so does this test's process, whose code was loaded from the cache
``obturator warmup`` filled. The core's compile flags allow no operation that rounds
differently by context (:mod:`obturator.core.jit_flags`), so every t_cr must agree to
the bit: the reference is the same computation in a process with other compiled code,
not a stored number.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

SCRIPT = textwrap.dedent(
    """
    import json
    from obturator import SolverOptions
    from obturator.model.cases import flight_case, rig_case
    from obturator.model.torques import SlipSpeedLaw
    from obturator.solve import opening_times

    cases = [rig_case(w, 0.5473) for w in (40.0, 61.3, 88.02, 112.04, 150.0, 300.0, 700.0)]
    cases += [flight_case(mach=1.5), rig_case(150.0, 0.5473, torque_model="coulomb")]
    law = SlipSpeedLaw("strengthening", 0.3, 0.13)
    cases += [rig_case(w, 0.5473, speed_law=law) for w in (90.0, 200.0)]
    out = {}
    for name, opts in {
        "default": SolverOptions(),
        "shared maps": SolverOptions(shared_maps=True),
        "regularised": SolverOptions(method="regularised"),
    }.items():
        t, s, _ = opening_times(cases, opts)
        out[name] = [float(x).hex() for x in t]
    print(json.dumps(out))
    """
)


def _run(env: dict[str, str]) -> dict[str, list[str]]:
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT], capture_output=True, text=True, env=env, timeout=3000
    )
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.mark.slow
def test_fresh_and_cached_code_give_the_same_bits(tmp_path):
    fresh_env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "numba")}
    fresh = _run(fresh_env)  # compiles everything into an empty cache
    cached = _run(fresh_env)  # loads all of it from that cache
    warm = _run(dict(os.environ))  # the cache obturator warmup built
    assert fresh == cached == warm
    assert np.all(np.isfinite([float.fromhex(x) for x in fresh["default"]]))
