"""Compiled code must not depend on the order in which callers compile shared helpers.

numba takes ``fastmath``, ``error_model`` and reference counting that a jitted
function does not state from the first caller that compiles it
(``numba.core.cpu.CPUTargetOptions.finalize``); see :mod:`obturator.core.jit_flags`.
"""

from __future__ import annotations

import importlib
import json
import os
import pkgutil
import subprocess
import sys
import textwrap

import pytest
from numba.core.registry import CPUDispatcher

import obturator.core
from obturator.core.jit_flags import INHERITED_FLAGS


def _core_dispatchers():
    for info in pkgutil.walk_packages(obturator.core.__path__, "obturator.core."):
        module = importlib.import_module(info.name)
        for name, value in vars(module).items():
            if isinstance(value, CPUDispatcher) and value.py_func.__module__ == info.name:
                yield f"{info.name}.{name}", value


def test_every_compiled_function_states_the_inherited_flags():
    """Every ``njit`` in core/ states fastmath, error_model and _nrt itself, unless numba
    inlines it at IR level (then its caller's flags apply by construction)."""
    checked, missing = 0, []
    for name, dispatcher in _core_dispatchers():
        options = dispatcher.targetoptions
        if options.get("inline") == "always":
            continue
        checked += 1
        lacking = [flag for flag in INHERITED_FLAGS if flag not in options]
        if lacking:
            missing.append(f"{name}: {', '.join(lacking)}")
    assert checked > 50  # the walk found the integrators, not an empty package
    assert not missing, "flags left to the first caller:\n" + "\n".join(missing)


def test_no_compiled_function_allows_fast_math():
    """No fast-math flag anywhere in core/ (FMA contraction included): with one, a
    function's rounding depends on where LLVM inlines or vectorises it, and freshly
    compiled, cached and batched code stop agreeing bit for bit."""
    allowing = [
        name
        for name, dispatcher in _core_dispatchers()
        if dispatcher.targetoptions.get("fastmath", False) not in (False, set(), frozenset())
    ]
    assert not allowing, allowing


# Two opposite compile orders, each in a fresh process with an empty cache: (a) the
# Python-side helpers and the Rosenbrock method first (they used to compile the torque
# law without FMA contraction), then the scalar path, then the lanes; (b) the lanes
# first. Every t_cr must agree bit for bit across the two processes and between lanes
# and scalar path in each.
_ORDER_SCRIPT = textwrap.dedent(
    """
    import json, sys
    from obturator import SolverOptions, opening_time, opening_times, rig_case, simulate
    order = sys.argv[1]
    opts = SolverOptions(friction_family="tanh")  # the generic (not thesis) kernel
    cases = [rig_case(w, 0.5473) for w in (250.0, 400.0, 650.0)]
    out = {}
    def scalar():
        out["scalar"] = [opening_time(c, opts).hex() for c in cases]
    def lanes():
        out["lanes"] = [float(t).hex() for t in opening_times(cases, opts)[0]]
    if order == "python-first":
        simulate(rig_case(300.0, 0.5, t_max=1e-3), opts)  # observables compiled first
        opening_time(rig_case(300.0, 0.5, t_max=1e-3), SolverOptions(method="rosenbrock"))
        scalar(); lanes()
    else:
        lanes(); scalar()
    print(json.dumps(out))
    """
)


@pytest.mark.slow
def test_compile_order_does_not_change_results(tmp_path):
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"}
    runs = {}
    procs = {}
    for order in ("python-first", "lanes-first"):
        cache = tmp_path / order
        cache.mkdir()
        procs[order] = subprocess.Popen(
            [sys.executable, "-c", _ORDER_SCRIPT, order],
            env={**env, "NUMBA_CACHE_DIR": str(cache)},
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
    for order, proc in procs.items():
        stdout, stderr = proc.communicate(timeout=900)
        assert proc.returncode == 0, stderr[-2000:]
        runs[order] = json.loads(stdout.strip().splitlines()[-1])
    a, b = runs["python-first"], runs["lanes-first"]
    assert a["scalar"] == b["scalar"]
    assert a["lanes"] == b["lanes"]
    assert a["scalar"] == a["lanes"]
