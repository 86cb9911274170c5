"""Shared fixtures: the thesis cases and a direct call of one compiled integrator."""

from __future__ import annotations

import math
import os
import shutil

import numpy as np
import pytest

from obturator import Case, SolverOptions
from obturator.core.integrators import Controls, Problem, RawSolution, integrate
from obturator.model.cases import flight_case, rig_case
from obturator.reference import THESIS_MU_S
from obturator.solve import error_scale, max_step_periods, pack_parameters

#: The thesis's cases the integrator tests run: the rig (Table 1 gravitational model) at
#: chapter IV's mu_s over the spin range of Figs. 32-37, the flight case (aerodynamic
#: model), and the exact Coulomb contact variants.
THESIS_CASES: dict[str, Case] = {
    "rig200": rig_case(200, THESIS_MU_S),
    "rig300": rig_case(300, THESIS_MU_S),
    "rig450": rig_case(450, THESIS_MU_S),
    "rig700": rig_case(700, THESIS_MU_S),
    "flight": flight_case(),
    "flight_coulomb": flight_case(torque_model="coulomb"),
    "rig450_coulomb": rig_case(450, THESIS_MU_S, torque_model="coulomb"),
}


def raw_solve(
    case: Case,
    options: SolverOptions,
    *,
    method: str | None = None,
    t_max: float | None = None,
    terminal: bool = True,
    t_eval=None,
    record: bool = False,
    y0=None,
    t0: float = 0.0,
    max_steps: int | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    hand_back: bool = False,
) -> tuple[RawSolution, np.ndarray]:
    """Call one compiled integrator directly (what solve.simulate does); return (raw, p).

    `method` defaults to ``options.method`` and may also be ``"dop853"``; keyword
    overrides replace the options' controls. With `t0` > 0 the run continues a run
    from release (state `y0` at `t0`, parameters packed from the release state).
    """
    release = case.initial_state(options.formulation)
    if y0 is None:
        y0 = release
    y0 = np.asarray(y0, dtype=float)
    p = pack_parameters(case, options, release if t0 > 0.0 else y0)
    period = 2 * math.pi / case.spin_rate
    controls = Controls(
        t_max=float(case.t_max if t_max is None else t_max),
        rtol=options.rtol if rtol is None else rtol,
        atol=options.atol if atol is None else atol,
        h0=1e-4 * period,
        h_max=max_step_periods(case) * period,
        max_steps=int(options.max_steps if max_steps is None else max_steps),
        t_eval=np.empty(0) if t_eval is None else np.asarray(t_eval, float),
        record=record,
        terminal=terminal,
        event_tol=options.event_tol,
        stop_when_sliding=hand_back,
    )
    problem = Problem(y0, p, error_scale(case, options.formulation), t0)
    return integrate(method or options.method, problem, controls), p


@pytest.fixture(scope="session")
def thesis_cases() -> dict[str, Case]:
    """The thesis's cases by name (see :data:`THESIS_CASES`)."""
    return THESIS_CASES


@pytest.fixture(scope="session")
def raw() -> object:
    """:func:`raw_solve`: one compiled integrator called directly."""
    return raw_solve


def _solver_settings() -> dict[str, object]:
    """The module-level dispatch settings of ``obturator.solve`` (thresholds, switches)."""
    import importlib
    import pkgutil

    import obturator.solve

    found = {}
    for info in pkgutil.iter_modules(obturator.solve.__path__, "obturator.solve."):
        module = importlib.import_module(info.name)
        for name, value in vars(module).items():
            if name.isupper() and isinstance(value, int | float | str | bool):
                found[f"{info.name}.{name}"] = value
    return found


_SETTINGS: dict[str, object] = {}


def pytest_runtest_setup(item: pytest.Item) -> None:
    """A test that changes a dispatch threshold in this process (e.g. the Radau lanes'
    minimum batch) without restoring it changes how every later test solves: CI once
    failed on exactly that, order-dependently. Checked before each test, when every
    fixture of the previous one (``monkeypatch`` included) has been torn down."""
    now = _solver_settings()
    previous = _SETTINGS.pop("by", None)
    if _SETTINGS and now != _SETTINGS:
        changed = {k: (_SETTINGS.get(k), v) for k, v in now.items() if v != _SETTINGS.get(k)}
        _SETTINGS.update(now)
        raise AssertionError(f"{previous} left solver settings changed: {changed}")
    _SETTINGS.update(now)
    _SETTINGS["by"] = item.nodeid


@pytest.fixture(autouse=True)
def _pools_even_for_small_studies(monkeypatch: pytest.MonkeyPatch) -> None:
    """Tests of the process pool use small studies, which would otherwise run in
    process (see obturator.runs.runner.POOL_MIN_SERIAL_S; tests/sweeps/test_sweep.py checks
    that choice with the real threshold)."""
    from obturator.runs import runner

    monkeypatch.setattr(runner, "POOL_MIN_SERIAL_S", 0.0)


@pytest.fixture(autouse=True)
def _cli_tests_in_a_tmp_folder(request: pytest.FixtureRequest, monkeypatch) -> None:
    """Command-line tests run in a temporary folder: an output option fuzzed with its
    bare example value (``theta.csv``) must not write into the checkout (other tests get
    no folder they did not ask for)."""
    if request.node.path.parent.name == "cli":
        monkeypatch.chdir(request.getfixturevalue("tmp_path"))


@pytest.fixture(scope="session")
def readme_validate_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[str, object]:
    """``obturator validate --out validation`` as the README runs it, once per session (a
    few minutes): its printed block (tests/test_readme.py) and its output folder (the
    whole-study checks of tests/validation/test_validation.py)."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tools"))
    import readme_blocks as rb

    keep = tmp_path_factory.mktemp("readme")
    return rb.fresh_output("validate", keep), keep / "validate" / "validation"


@pytest.fixture
def chromium() -> str:
    """Path of a headless-capable Chromium; in CI a missing browser fails the test
    (``.ci/run`` installs Debian's ``chromium``), elsewhere it skips."""
    for name in ("chromium", "chromium-browser", "google-chrome"):
        path = shutil.which(name)
        if path:
            return path
    if os.environ.get("CI"):
        pytest.fail("a headless Chromium is required in CI (apt-get install chromium)")
    pytest.skip("no Chromium on this machine")


def pytest_collection_modifyitems(config, items):
    """Run ``tests/sweeps/test_ahead.py`` first: packing ahead needs ``fork``, which the
    pools use only while the process runs no other thread, and tests that start a Dask
    client leave threads behind (:func:`obturator.runs.mp_context`)."""
    first = [it for it in items if it.path.name == "test_ahead.py"]
    if first:
        items[:] = first + [it for it in items if it.path.name != "test_ahead.py"]


@pytest.fixture
def lanes_always(monkeypatch):
    """Every kernel group runs in lanes, however small (the lane tests compare the lanes
    themselves with the scalar path; :func:`obturator.solve.many.lanes_pay_from` would
    send small groups one by one)."""
    from obturator.solve import many

    monkeypatch.setattr(many, "THESIS_LANES_MIN", 1)
    monkeypatch.setattr(many, "GENERIC_LANES_MIN", 1)


@pytest.fixture
def dask_cluster():
    """A local Dask cluster of two one-thread worker processes (skips without
    ``distributed``). Here, not in a sub-folder's conftest: a second module named
    ``conftest`` would shadow this one for the tests that import helpers from it."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None
    ) as cluster:
        yield cluster
