"""Optional parts and the environment end in one line naming the fix, exit code 2.

* ``--scheduler`` without the ``cluster`` extra: dask.distributed is made missing by a
  ``None`` entry in ``sys.modules`` (what Python does for a module that cannot be
  imported); every command that takes ``--scheduler`` refuses it while parsing.
* numba's variables are checked as numba parses them (it compares ``NUMBA_OPT`` exactly,
  and warns with a traceback on a value it cannot read); ``NUMBA_DISABLE_JIT=1`` is
  refused (the integrators run compiled only).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

import obturator
from obturator.cli import main

_LINE = (
    "obturator: error: --scheduler: needs dask.distributed, which is not installed: "
    'pip install "obturator[cluster]"\n'
)


@pytest.mark.parametrize(
    "argv",
    [
        ["sweep", "--spin-rate", "100:200:3"],
        ["montecarlo", "--samples", "8", "--vary", "mu_s=uniform:0.5,0.6"],
        ["design-experiment"],
        ["envelope"],
        ["probability"],
        ["sensitivity"],
        ["optimize"],
    ],
    ids=lambda a: a[0],
)
def test_scheduler_without_cluster_extra_is_one_line(
    argv: list[str], monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    monkeypatch.setitem(sys.modules, "distributed", None)  # import raises ImportError
    rc = main([*argv, "--scheduler", "tcp://127.0.0.1:1", "--no-progress"])
    err = capsys.readouterr().err
    assert rc == 2
    assert err == _LINE


def test_every_command_with_scheduler_is_covered() -> None:
    from obturator.cli import build_parser

    sub = next(a for a in build_parser()._actions if a.dest == "command")
    with_scheduler = {
        name
        for name, parser in sub.choices.items()
        if any("--scheduler" in a.option_strings for a in parser._actions)
    }
    assert with_scheduler == {
        "sweep", "montecarlo", "design-experiment", "envelope", "probability", "sensitivity",
        "optimize",
    }  # fmt: skip


def test_runner_api_refuses_scheduler_without_cluster_extra(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from obturator.errors import InputError
    from obturator.runs import Runner

    monkeypatch.setitem(sys.modules, "distributed", None)
    with pytest.raises(InputError, match=r"scheduler: .*obturator\[cluster\]"):
        Runner(scheduler="tcp://127.0.0.1:1")


@pytest.mark.parametrize(
    ("variable", "value", "line"),
    [
        ("NUMBA_OPT", "MAX", "NUMBA_OPT: 'MAX'; allowed: 0, 1, 2, 3, max"),
        ("NUMBA_OPT", "", "NUMBA_OPT: ''; allowed: 0, 1, 2, 3, max"),
        ("NUMBA_NUM_THREADS", "", "NUMBA_NUM_THREADS: '' is not a whole number"),
        (
            "NUMBA_DISABLE_JIT",
            "1",
            "NUMBA_DISABLE_JIT: 1 is not supported: obturator runs its integrators compiled "
            "only; allowed: 0 (or unset)",
        ),
        (
            "NUMBA_LOOP_VECTORIZE",
            "yes",
            "NUMBA_LOOP_VECTORIZE: 'yes' is not a value numba can read (its environment "
            "variables: numba.readthedocs.io/en/stable/reference/envvars.html)",
        ),
    ],
)
def test_numba_variables_are_one_line(variable: str, value: str, line: str) -> None:
    # this checkout's package (the CLI tests run in a temporary folder)
    path = os.pathsep.join(
        [str(Path(obturator.__file__).parents[1]), os.environ.get("PYTHONPATH", "")]
    )
    env = {**os.environ, variable: value, "PYTHONPATH": path}
    done = subprocess.run(
        [sys.executable, "-m", "obturator", "simulate", "--case", "spin-rig"],
        capture_output=True,
        text=True,
        timeout=120,
        env=env,
    )
    assert done.returncode == 2, done.stderr
    assert done.stderr == f"obturator: error: {line}\n"
    assert done.stdout == ""


@pytest.mark.parametrize(("variable", "value"), [("NUMBA_OPT", "max"), ("NUMBA_DISABLE_JIT", "0")])
def test_numba_values_numba_reads_pass(variable: str, value: str) -> None:
    from obturator.cli._environment import check_environment

    check_environment({variable: value})
