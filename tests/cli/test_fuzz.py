"""Fuzzing the command line, config files, data files and the Python API.

The rule under test (not a list of cases): every input gives either a result or one
line ``obturator: error: <field>: ...`` with exit code 2 (3 for a solver failure on
valid input), never a traceback and never a hang; accepted inputs give finite,
in-range results; the API raises only InputError (a ValueError) for bad input.
Every run is bounded: --t-max 0.005 s of simulated time (0.05 s in sweeps).
"""

from __future__ import annotations

import contextlib
import io
import json
import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from obturator.cli import main
from obturator.errors import InputError

EXTREMES = [
    "0", "-1", "-0", "nan", "NaN", "inf", "-inf", "1e308", "-1e308", "1e-308", "1e-320",
    "1e999", "", " ", "abc", "1,5", "0x10", "1_000", "--", "30 deg", "30 Hz", "12 kg",
    "1 rad", "9**9**9", "1e6", "1e-12", "0.5", "87.25 deg", "200 rad/s", "7.899 mm",
    "\u00b5", "1 2", "()", "'", "2e-7 m",
]  # fmt: skip
VALUES = st.one_of(
    st.sampled_from(EXTREMES),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(min_value=-(10**20), max_value=10**20).map(str),
    st.text(max_size=24),
)
FAST = settings(
    max_examples=60,
    deadline=None,
    derandomize=True,  # reproducible examples (and run time) in CI
    suppress_health_check=[HealthCheck.function_scoped_fixture],
)


def _run(args: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = main(args)
        except SystemExit as exc:  # argparse usage errors
            rc = int(exc.code or 0)
    return rc, out.getvalue(), err.getvalue()


def _check(rc: int, out: str, err: str) -> None:
    assert "Traceback" not in out + err
    assert rc in (0, 2, 3), (rc, err)
    if rc == 2:  # one line naming the field
        assert err.startswith("obturator: error:") and err.count("\n") == 1, err
    if rc == 3:
        assert err.startswith("obturator: solver failure:") and err.count("\n") == 1, err


def _strict_json(text: str):
    def reject(token: str):
        raise ValueError(token)

    return json.loads(text, parse_constant=reject)


SIMULATE_FLAGS = [
    "--spin-rate", "--mu-s", "--theta0-deg", "--mach", "--altitude-m", "--rtol",
    "--friction-width", "--t-max", "--patch-radius", "--friction-family", "--torque-model",
    "--spin-mode", "--case", "--formulation",
]  # fmt: skip


@FAST
@given(
    flag=st.sampled_from(SIMULATE_FLAGS), value=VALUES, case=st.sampled_from(["spin-rig", "flight"])
)
def test_simulate_flags(flag, value, case):
    args = ["simulate", "--case", case, flag, value, "--no-check", "--json"]
    if flag != "--t-max":
        args += ["--t-max", "0.005"]
    if flag == "--patch-radius":
        args += ["--torque-model", "coulomb"]
    rc, out, err = _run(args)
    _check(rc, out, err)
    if rc == 0:
        res = _strict_json(out)
        assert res["t_cr_s"] is None or (math.isfinite(res["t_cr_s"]) and res["t_cr_s"] > 0)
        assert 0 < res["spin_rate_rad_s"] <= 1e6


CONFIG_KEYS = {
    "": ["case", "spin_rate", "mu_s", "theta0", "torque_model", "spin_mode", "t_max"],
    "ball": ["radius", "hole_radius", "density"],
    "gap": ["width", "viscosity"],
    "rig": ["weight"],
    "contact": ["patch_radius"],
    "flight": ["mach", "p1", "altitude", "n_contacts", "bore_radius"],
    "solver": ["rtol", "atol", "friction_width", "friction_family", "method", "formulation"],
    "bogus": ["x"],
}
TOML_VALUES = st.one_of(
    st.sampled_from(EXTREMES).map(lambda v: json.dumps(v)),
    st.floats(allow_nan=False, allow_infinity=False).map(repr),
    st.integers(min_value=-(10**6), max_value=10**6).map(str),
    st.sampled_from(["true", "[1, 2]", "{a = 1}", '"thesis"', '"coulomb"', '"flight"']),
)


@FAST
@given(
    section=st.sampled_from(list(CONFIG_KEYS)),
    data=st.data(),
    value=TOML_VALUES,
)
def test_config_files(tmp_path_factory, section, data, value):
    key = data.draw(st.sampled_from(CONFIG_KEYS[section]))
    body = f"{key} = {value}\n" if not section else f"[{section}]\n{key} = {value}\n"
    path = tmp_path_factory.mktemp("cfg") / "run.toml"
    path.write_text(body, encoding="utf-8")
    # --t-max on the command line wins over the config: every run stays short
    rc, out, err = _run(["simulate", "--config", str(path), "--no-check", "--t-max", "0.005"])
    _check(rc, out, err)


SWEEP_FLAGS = ["--spin-rate", "--mu-s", "--theta0-deg", "--density", "--hole-radius", "--gap"]


@settings(max_examples=25, deadline=None, derandomize=True)
@given(flag=st.sampled_from(SWEEP_FLAGS), value=VALUES)
def test_sweep_axes(tmp_path_factory, flag, value):
    out_nc = tmp_path_factory.mktemp("sw") / "s.nc"
    args = ["sweep", flag, value, "--out", str(out_nc), "--workers", "1", "--t-max", "0.05"]
    rc, out, err = _run([*args, "--no-progress"])
    _check(rc, out, err)


@settings(max_examples=25, deadline=None, derandomize=True)
@given(
    name=st.sampled_from(["mu_s", "theta0_deg", "spin_rate", "gap", "density"]),
    kind=st.sampled_from(["normal", "uniform", "lognormal", "truncnormal", "bogus"]),
    params=st.lists(st.sampled_from(EXTREMES[:30]), min_size=0, max_size=5),
)
def test_montecarlo_distributions(tmp_path_factory, name, kind, params):
    vary = f"{name}={kind}:{','.join(params)}"
    args = ["montecarlo", "--vary", vary, "--samples", "3", "--workers", "1", "--t-max", "0.05"]
    rc, out, err = _run([*args, "--no-progress"])
    _check(rc, out, err)


CSV_LINES = st.lists(
    st.one_of(
        st.sampled_from(
            [
                "spin_rate_rad_s,t_cr_s,starred",
                "readout_hz,t_cr_s",
                "300,0.27,1",
                "nan,0.2,1",
                "300,-1,1",
                "300,1e308,1",
                "1e308,0.2,0",
                "a,b,c",
                "",
                "300,0.27",
                "300,0.27,1,9",
            ]
        ),
        st.text(max_size=30),
    ),
    max_size=6,
)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(lines=CSV_LINES)
def test_calibration_csv_loader(tmp_path_factory, lines):
    from obturator.calibration import load_spin_rig_csv

    path = tmp_path_factory.mktemp("csv") / "runs.csv"
    path.write_text("\n".join(lines), encoding="utf-8")
    try:
        data = load_spin_rig_csv(path)
    except InputError:
        return
    assert all(math.isfinite(x) and x > 0 for x in data.spin_rate)
    assert all(math.isfinite(x) and x > 0 for x in data.opening_time)


@settings(max_examples=15, deadline=None, derandomize=True)
@given(lines=CSV_LINES)
def test_calibrate_cli_on_bad_files(tmp_path_factory, lines):
    path = tmp_path_factory.mktemp("csv") / "runs.csv"
    path.write_text("\n".join(lines), encoding="utf-8")
    rc, out, err = _run(["calibrate", str(path), "--bootstrap", "0", "--min-spin", "1e5"])
    _check(rc, out, err)


FLOATS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from([0.0, -0.0, 1e308, -1e308, 5e-324, 1e-308]),
)


@settings(max_examples=150, deadline=None)
@given(
    factory=st.sampled_from(["rig", "flight", "options", "ball"]),
    field=st.sampled_from(
        ["spin_rate", "mu_s", "theta0_deg", "t_max", "gap", "rtol", "friction_width", "density"]
    ),
    value=FLOATS,
)
def test_python_api_raises_only_input_error(factory, field, value):
    from obturator import SolverOptions, flight_case, rig_case
    from obturator.model.geometry import BoredBall

    calls = {
        "rig": lambda: rig_case(**{field: value}),
        "flight": lambda: flight_case(**{field: value}),
        "options": lambda: SolverOptions(**{field: value}),
        "ball": lambda: BoredBall(7.899e-3, 4.72e-3, value),
    }
    try:
        calls[factory]()
    except InputError:
        pass
    except TypeError as exc:  # only for keyword names a factory does not take
        assert "unexpected keyword argument" in str(exc)


@pytest.mark.parametrize(
    "args",
    [
        ["simulate", "--spin-rate", "1e308"],
        ["simulate", "--plot", "x.unknownext", "--no-check"],
        ["simulate", "--csv", "/nonexistent-dir/x.csv", "--no-check"],
        ["sweep", "--spin-rate", "100:200:3", "--out", ""],
        ["gasdyn", "start", "--area-ratio", "1e308"],
        ["gasdyn", "normal-shock", "--mach", "1e308"],
        ["simulate", "--config", "/dev/zero"],
        ["montecarlo", "--vary", "theta0_deg=uniform:10,20", "--samples", "5"],
        ["simulate", "--rtol", "1e-13"],
        ["simulate", "--t-max", "1e308"],
    ],
)
def test_issue_cases_are_one_line_exit_2(args):
    rc, out, err = _run(args)
    assert rc == 2, err
    assert err.count("\n") == 1 and err.startswith("obturator: error:")


def test_fifo_config_does_not_block(tmp_path):
    import os

    fifo = tmp_path / "cfg.toml"
    os.mkfifo(fifo)
    rc, out, err = _run(["simulate", "--config", str(fifo)])
    assert rc == 2 and "not a regular file" in err
