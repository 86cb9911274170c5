"""Start-up: the command line imports only what the named command needs."""

from __future__ import annotations

import argparse
import importlib
import subprocess
import sys

import pytest

from obturator.cli import _COMMANDS


@pytest.mark.parametrize("name", list(_COMMANDS))
def test_module_registers_the_listed_help(name):
    module_name, text = _COMMANDS[name]
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers(dest="command")
    importlib.import_module(module_name).register(sub)
    assert name in sub.choices
    helps = {a.dest: a.help for a in sub._choices_actions}
    assert helps[name] == text


def _modules_after(argv: list[str], dotted: bool = False) -> set[str]:
    keep = "True" if dotted else "'.' not in m"
    code = (
        "import sys, contextlib, io\n"
        "from obturator.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    try:\n"
        f"        main({argv!r})\n"
        "    except SystemExit:\n"
        "        pass\n"
        f"print(','.join(sorted(m for m in sys.modules if {keep})))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return set(out.stdout.strip().splitlines()[-1].split(","))


def test_top_level_help_imports_no_numeric_stack():
    mods = _modules_after(["--help"])
    assert not mods & {"numba", "scipy", "xarray", "matplotlib", "pint", "dask"}


def test_simulate_help_imports_no_output_stack():
    mods = _modules_after(["simulate", "--help"])
    assert not mods & {"xarray", "matplotlib", "dask", "distributed"}


def test_simulate_loads_no_scipy_solver_it_does_not_use():
    """A simulation inverts no flow relation and fits nothing: scipy.optimize,
    scipy.integrate and scipy.stats (0.3-0.4 s of start-up each) stay unloaded; the
    flow relations and the fits import them on first use."""
    mods = _modules_after(["simulate", "--case", "spin-rig"], dotted=True)
    assert "obturator.solve" in mods  # it did run
    assert not mods & {"scipy.optimize", "scipy.integrate", "scipy.stats"}


def test_unknown_command_is_one_line_with_the_choices():
    out = subprocess.run(
        [sys.executable, "-m", "obturator", "simulat"], capture_output=True, text=True
    )
    assert out.returncode == 2
    assert len(out.stderr.strip().splitlines()) == 1
    assert "invalid choice" in out.stderr and "simulate" in out.stderr


@pytest.mark.slow  # compiles every integrator afresh: ~90 s
def test_warmup_fills_an_empty_cache_and_later_runs_load_it(tmp_path):
    """``obturator warmup`` into an empty NUMBA_CACHE_DIR writes the integrators'
    machine code; a later process finds them there (index files for both methods)."""
    import json
    import os

    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    out = subprocess.run(
        [sys.executable, "-m", "obturator", "warmup", "--json"],
        capture_output=True, text=True, env=env, check=True,
    )  # fmt: skip
    rec = json.loads(out.stdout)
    expected = {"dop853", "radau", "lanes", "radau-lanes", "set-valued"}
    assert set(rec["time_s"]) == expected and rec["wall_s"] > 0
    assert all(rec["compiled"].values()) and rec["cache_directory"] == str(tmp_path)
    assert rec["obturator_version"]
    names = {p.name for p in tmp_path.rglob("*.nbi")}
    assert any(n.startswith("dop853.integrate") for n in names)
    assert any(n.startswith("radau.integrate") for n in names)
    assert any(n.startswith("dop853.integrate_lanes") for n in names)  # lanes/dop853.py
    assert any(n.startswith("stick_slip._integrate") for n in names)  # the default's low spins
    assert any(n.startswith("stick_slip_map.iterate") for n in names)  # a study's shared maps
    # a study after the warm-up compiles nothing: set-valued points with shared maps,
    # and lane points (a compile there would also round differently)
    study = (
        "import numpy as np; from obturator.model.cases import rig_case; "
        "from obturator.solve import opening_times; from obturator.warmup import "
        "_compiled_anything as c; opening_times([rig_case(w, 0.5473) for w in "
        "np.linspace(60, 400, 12)]); print(c())"
    )
    after = subprocess.run(
        [sys.executable, "-c", study], capture_output=True, text=True, env=env, check=True
    )
    assert after.stdout.strip() == "False"
    again = subprocess.run(
        [sys.executable, "-m", "obturator", "warmup"],
        capture_output=True, text=True, env=env, check=True,
    )  # fmt: skip
    # says truthfully that nothing was compiled the second time, and where the cache is
    assert again.stdout.startswith("loaded from the cache in ")
    assert "compiled" not in again.stdout and again.stdout.rstrip().endswith(str(tmp_path))


def test_warmup_refuses_zero_jobs():
    out = subprocess.run(
        [sys.executable, "-m", "obturator", "warmup", "--jobs", "0"], capture_output=True, text=True
    )
    assert out.returncode == 2
    assert out.stderr.strip() == "obturator: error: --jobs: 0 is outside the allowed range [1, 64]"
