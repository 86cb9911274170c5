"""The curated public API: a snapshot of ``obturator.__all__``, resolvable and lazy."""

from __future__ import annotations

import subprocess
import sys

import obturator

PUBLIC = [
    "ApproximateSolution",
    "BoredBall",
    "Case",
    "ClusterError",
    "ConvergenceCheck",
    "CouetteViscous",
    "CoulombContactFriction",
    "Distribution",
    "ExactFit",
    "FitParameter",
    "InputError",
    "NakabayashiViscous",
    "NutationResult",
    "Runner",
    "SlipSpeedLaw",
    "SolverError",
    "SolverOptions",
    "SpinRigData",
    "Status",
    "SweepSpec",
    "TABLE1",
    "ThesisFlightFriction",
    "ThesisRigFriction",
    "TorqueModel",
    "__version__",
    "case_from_settings",
    "convergence_check",
    "couette_case",
    "design_experiment",
    "fit_exact",
    "flight_case",
    "initial_state",
    "load_config",
    "load_spin_rig_csv",
    "load_thesis_data",
    "monte_carlo",
    "normal_shock",
    "opening_time",
    "opening_times",
    "parse_quantity",
    "reproduce",
    "rig_approximation",
    "rig_case",
    "run_sweep",
    "simulate",
    "standard_atmosphere",
    "table1_ball",
]


def test_all_is_the_curated_list() -> None:
    assert sorted(obturator.__all__) == PUBLIC
    assert sorted(dir(obturator)) == PUBLIC


def test_every_public_name_resolves() -> None:
    for name in obturator.__all__:
        assert getattr(obturator, name) is not None, name


def test_import_is_lazy() -> None:
    """``import obturator`` (and the CLI's start) loads neither numba nor scipy."""
    code = "import sys, obturator; print(sorted({'numba', 'scipy', 'xarray'} & set(sys.modules)))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"
