"""The examples of the input-contract issue, each one line and exit 2 or the right value.

Units on every dimensional flag, a unit after a list applied to every value,
bounds on dimensionless inputs and on counts, one ``--config`` schema that a
command uses or refuses key by key, one file reader, checked environment
variables, and no hangs on FIFOs or empty names.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import subprocess
import sys
import time

import pytest

from obturator.cli import main


def _run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(argv)
    return rc, out.getvalue(), err.getvalue()


def _refused(argv: list[str], fragment: str) -> str:
    rc, _, err = _run(argv)
    assert rc == 2, err
    assert err.startswith("obturator: error: ") and err.count("\n") == 1, err
    assert fragment in err, err
    return err


@pytest.mark.parametrize(
    ("text", "metres"),
    [("11 km", 11_000.0), ("36089 ft", 36_089 * 0.3048), ("11000", 11_000.0)],
)
def test_atmosphere_altitude_takes_units(text, metres):
    rc, out, err = _run(["gasdyn", "atmosphere", "--altitude-m", text, "--json"])
    assert rc == 0, err
    assert json.loads(out)["altitude_m"] == pytest.approx(metres, rel=1e-12)


def test_envelope_altitude_list_takes_a_unit_for_every_value():
    from obturator.cli import build_parser

    args = build_parser("envelope").parse_args(
        ["envelope", "--mach", "3", "--altitude-m", "0,1 km", "--out", os.devnull]
    )
    from obturator.sweeps import parse_axis

    assert parse_axis(args.grid_altitude, "--altitude-m", "m").tolist() == [0.0, 1000.0]


def test_unit_after_a_list_applies_to_every_value(tmp_path):
    rc, out, err = _run(
        [
            "sweep", "--spin-rate", "1000,2000 rpm", "--t-max", "0.001", "--workers", "1",
            "--no-progress", "--json", "--out", str(tmp_path / "s.nc"),
        ]
    )  # fmt: skip
    assert rc == 0, err
    spins = json.loads(out)["settings"]["axes"]["spin_rate"]
    assert spins == pytest.approx([1000 * math.pi / 30, 2000 * math.pi / 30], rel=1e-12)


def test_study_config_takes_solver_settings(tmp_path):
    """A sweep's ``[solver]`` section sets its options (it replaced the whole section by
    its last value, and the sweep failed with an internal error)."""
    cfg = tmp_path / "c.toml"
    cfg.write_text('[solver]\nmethod = "regularised"\nrtol = 1e-9\n', encoding="utf-8")
    argv = ["sweep", "--spin-rate", "300,400", "--config", str(cfg), "--workers", "1"]
    rc, out, err = _run([*argv, "--no-progress", "--json", "--out", str(tmp_path / "s.nc")])
    assert rc == 0, err
    options = json.loads(out)["settings"]["options"]
    assert options["method"] == "regularised" and options["rtol"] == 1e-9


@pytest.mark.parametrize("text", ["1000 rpm,2000", "1000,2000 rpm,3000 rpm"])
def test_a_list_that_mixes_units_is_refused(tmp_path, text):
    _refused(["sweep", "--spin-rate", text, "--out", str(tmp_path / "s.nc")], "mixes values")


def test_gamma_has_a_range():
    _refused(["gasdyn", "normal-shock", "--mach", "2", "--gamma", "1e300"], "--gamma: 1e+300")


@pytest.mark.parametrize(
    ("body", "fragment"),
    [
        ('case = "spin-rig"\n', "case: obturator trajectory runs the flight case"),
        ('spin_mode = "free"\n', "spin_mode: the trajectory sets the spin"),
        ('[friction]\nspeed_law = "strengthening"\n', "speed_law: applies to the spin rig only"),
        ('[flight]\np1 = "0.099 MPa"\n', "p1: the trajectory takes the pressure from the altitude"),
        ('[flight]\nmach = "bogus"\n', "flight.mach: 'bogus' is not a number"),
        ('[solver]\nmethod = "bogus"\n', "solver.method: 'bogus'; allowed"),
        ("colour = 1\n", "colour: unknown key"),
        ('[launch]\nsegment = "1e-9 s"\n', "segment: 1e-09 s is outside"),
        ("a = " + "[" * 5000 + "]" * 5000 + "\n", "nested too deeply"),
    ],
)
def test_trajectory_config_keys_are_used_or_refused(tmp_path, body, fragment):
    cfg = tmp_path / "c.toml"
    cfg.write_text(body, encoding="utf-8")
    _refused(["trajectory", "--config", str(cfg)], fragment)


def test_trajectory_config_uses_mach_altitude_and_solver(tmp_path):
    cfg = tmp_path / "c.toml"
    cfg.write_text(
        '[flight]\nmach = 2.5\naltitude = "1 km"\n[solver]\nmethod = "radau"\n'
        'friction_width = 1e-6\n[launch]\nsegment = "5 ms"\n',
        encoding="utf-8",
    )
    argv = ["trajectory", "--config", str(cfg), "--t-max", "0.002", "--no-convergence-check"]
    rc, out, err = _run([*argv, "--json"])
    assert rc == 0, err
    got = json.loads(out)
    assert got["mach"] == 2.5 and got["altitude_m"] == 1000.0 and got["segment_s"] == 0.005


@pytest.mark.parametrize(
    ("content", "fragment"),
    [
        ("mach,cd\n3,\u00e9\n".encode("latin-1"), "not UTF-8 text"),
        (b"mach,cd\n3," + b"1" * (200 * 1024) + b"\n", "not a CSV table"),
    ],
)
def test_drag_tables_go_through_the_shared_reader(tmp_path, content, fragment):
    table = tmp_path / "cd.csv"
    table.write_bytes(content)
    _refused(["trajectory", "--drag", str(table), "--t-max", "0.002"], fragment)


@pytest.mark.parametrize(
    ("argv", "fragment"),
    [
        (["trajectory", "--drag", "/dev/zero"], "not a regular file"),
        (["trajectory", "--segment", "1e-9"], "--segment: 1e-09 s is outside"),
        (["montecarlo", "--samples", "100000000", "--vary", "mu_s=normal:0.5,0.01"], "100000"),
        (
            ["montecarlo", "--samples", "5", "--vary", "mu_s=lognormal:0.5,1000"],
            "SIGMA_LN must be <= 5",
        ),
        (["simulate", "--spin-rate", "1e-6"], "--spin-rate: 1e-06 rad/s is outside"),
    ],
)
def test_bounds_on_sizes_counts_and_distributions(argv, fragment):
    _refused(argv, fragment)


def test_calibration_rows_cells_and_times(tmp_path):
    csv = tmp_path / "runs.csv"
    csv.write_text("spin_rate_rad_s,t_cr_s\n300,1e-300\n400,0.2\n", encoding="utf-8")
    _refused(["calibrate", str(csv), "--bootstrap", "0"], "1e-300 s is outside")
    csv.write_text("spin_rate_rad_s,t_cr_s\n300," + "1" * 140_000 + "\n", encoding="utf-8")
    _refused(["calibrate", str(csv)], "longer than")
    rows = "".join(f"{300 + k * 1e-3:.3f},0.2\n" for k in range(100_000))
    csv.write_text("spin_rate_rad_s,t_cr_s\n" + rows, encoding="utf-8")
    t0 = time.perf_counter()
    _refused(["calibrate", str(csv)], "larger than")  # 100,000 rows: over 1 MiB
    csv.write_text("spin_rate_rad_s,t_cr_s\n" + "300,0.2\n" * 3000, encoding="utf-8")
    _refused(["calibrate", str(csv)], "more than 2000 runs")
    assert time.perf_counter() - t0 < 10


def test_fifos_and_empty_names_do_not_hang(tmp_path):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    t0 = time.perf_counter()
    _refused(["calibrate", str(fifo)], "not a regular file")
    _refused(["reproduce", "--out", ""], "empty folder name")
    _refused(["trajectory", "--config", str(fifo)], "not a regular file")
    assert time.perf_counter() - t0 < 10


@pytest.mark.parametrize(
    ("variable", "value"),
    [
        ("NUMBA_NUM_THREADS", "0"),
        ("NUMBA_OPT", "abc"),
        ("NUMBA_DISABLE_JIT", "x"),
        ("OBTURATOR_DEBUG", "yes"),
        ("OBTURATOR_LANES", "0"),  # retired: a solver path is an option, never a variable
        ("OBTURATOR_SLIP_LANES", "1"),
    ],
)
def test_environment_variables_are_checked_at_start_up(variable, value):
    env = {**os.environ, variable: value}
    done = subprocess.run(
        [sys.executable, "-m", "obturator", "gasdyn", "atmosphere", "--altitude-m", "1"],
        capture_output=True,
        text=True,
        timeout=120,
        env=env,
    )
    assert done.returncode == 2
    assert done.stderr.startswith(f"obturator: error: {variable}: ")
    assert done.stderr.count("\n") == 1 and "Traceback" not in done.stderr
