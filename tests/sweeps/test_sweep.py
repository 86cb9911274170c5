"""Parameter sweeps: axis parsing, grid evaluation, parallel and resumable runs, CLI."""

from __future__ import annotations

import json
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import obturator.runs.chunks as run_chunks
import obturator.runs.pools as pools
import obturator.runs.runner as runs_runner
import obturator.runs.store as run_store
import obturator.sweeps.export as export
import obturator.sweeps.job as job_module
from obturator.cli import main
from obturator.errors import InputError
from obturator.model.cases import TABLE1, flight_case, rig_case, table1_ball
from obturator.runs import Runner
from obturator.solve import SolverOptions, opening_time
from obturator.status import Status
from obturator.sweeps import (
    SweepSpec,
    execute_sweep,
    parse_axis,
    run_sweep,
    sidecar_path,
    sweep_summary,
)
from obturator.sweeps.job import LANE_CHUNK, sweep_job

FAST = SolverOptions(rtol=1e-6, atol=1e-8)


def small_spec(**kw: object) -> SweepSpec:
    axes = kw.pop("axes", {"spin_rate": [300.0, 450.0, 600.0], "mu_s": [0.5, 0.6]})
    return SweepSpec("spin-rig", axes, kw.pop("fixed", {}), options=FAST, **kw)  # type: ignore[arg-type]


# --------------------------------------------------------------------------- parse_axis


def test_parse_axis_range_and_list() -> None:
    a = parse_axis("200:700:20", "--spin-rate")
    assert a.size == 20 and a[0] == 200.0 and a[-1] == 700.0
    assert np.allclose(np.diff(a), 500.0 / 19)
    assert parse_axis("700:200:3").tolist() == [700.0, 450.0, 200.0]
    assert parse_axis(" 0.5, 0.6 ,0.55").tolist() == [0.5, 0.6, 0.55]
    assert parse_axis("0.5473").tolist() == [0.5473]
    assert parse_axis("5:5:1").tolist() == [5.0]


@pytest.mark.parametrize(
    "text",
    [
        "",
        "200:700",
        "200:700:20:3",
        "a:700:20",
        "200:700:0",
        "200:700:-3",
        "200:700:2.5",
        "200:700:1",
        "5:5:3",
        "1,1",
        "1,,2",
        "nan",
        "inf:3:4",
        "x",
    ],
)
def test_parse_axis_rejects(text: str) -> None:
    with pytest.raises(InputError) as exc:
        parse_axis(text, "--spin-rate")
    assert exc.value.field == "--spin-rate"


@settings(max_examples=200, deadline=None)
@given(
    start=st.floats(-1e6, 1e6, allow_nan=False),
    stop=st.floats(-1e6, 1e6, allow_nan=False),
    count=st.integers(2, 400),
)
def test_parse_axis_properties(start: float, stop: float, count: int) -> None:
    assume(abs(stop - start) > 1e-6 * max(1.0, abs(start), abs(stop)))
    a = parse_axis(f"{start!r}:{stop!r}:{count}", "x")
    assert a.shape == (count,)
    assert a[0] == start and a[-1] == stop  # both ends included exactly
    d = np.diff(a)
    assert np.all(d > 0) if stop > start else np.all(d < 0)  # strictly monotone


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(-1e9, 1e9, allow_nan=False), min_size=1, max_size=20, unique=True))
def test_parse_axis_list_roundtrip(values: list[float]) -> None:
    text = ",".join(repr(v) for v in values)
    assert parse_axis(text).tolist() == values


# --------------------------------------------------------------------------- SweepSpec


def test_spec_validation() -> None:
    with pytest.raises(InputError, match="unknown parameter"):
        SweepSpec("spin-rig", {"spin": [1.0, 2.0]})
    with pytest.raises(InputError, match="flight case only"):
        SweepSpec("spin-rig", {"mach": [2.0, 3.0]})
    with pytest.raises(InputError, match="both swept and fixed"):
        SweepSpec("spin-rig", {"mu_s": [0.5, 0.6]}, {"mu_s": 0.5})
    with pytest.raises(InputError, match="case"):
        SweepSpec("rig", {})
    with pytest.raises(InputError, match="torque_model"):
        SweepSpec("spin-rig", {}, torque_model="magic")
    # every grid corner is checked before anything runs
    with pytest.raises(InputError, match="theta0"):
        SweepSpec("spin-rig", {"theta0_deg": [80.0, 95.0]})
    with pytest.raises(InputError, match="hole_radius"):
        SweepSpec("spin-rig", {"hole_radius": [3e-3, 6e-3]})
    with pytest.raises(InputError, match="distinct"):
        SweepSpec("spin-rig", {"mu_s": [0.5, 0.5]})


def test_spec_identity_and_shape() -> None:
    a, b = small_spec(), small_spec()
    assert a == b and a.digest() == b.digest() and hash(a) == hash(b)
    c = small_spec(fixed={"theta0_deg": 87.0})
    assert a != c and a.digest() != c.digest()
    assert a.dims == ("spin_rate", "mu_s") and a.shape == (3, 2) and a.n_points == 6
    rows = a.rows(np.arange(6))
    assert rows[:, 0].tolist() == [300.0, 300.0, 450.0, 450.0, 600.0, 600.0]
    assert rows[:, 1].tolist() == [0.5, 0.6] * 3


def test_weight_follows_ball_only_when_geometry_varies() -> None:
    plain = SweepSpec("spin-rig", {"mu_s": [0.5, 0.6]})
    assert not plain.weight_from_ball
    case = plain.build_case({"mu_s": 0.5})
    assert case.torque.friction.weight == TABLE1["rig_weight"]  # type: ignore[union-attr]
    geo = SweepSpec("spin-rig", {"density": [6000.0, 10000.0]})
    assert geo.weight_from_ball
    case = geo.build_case({"density": 6000.0})
    ball = table1_ball(density=6000.0)
    assert case.ball == ball
    assert case.torque.friction.weight == pytest.approx(ball.weight)  # type: ignore[union-attr]
    assert "computed" in geo.weight_model


def test_flight_spec_builds_factory_case() -> None:
    spec = SweepSpec(
        "flight", {"mach": [2.5, 3.0], "altitude_m": [0.0, 3000.0]}, {"mu_s": 0.5}, options=FAST
    )
    got = spec.build_case({"mach": 2.5, "altitude_m": 3000.0})
    want = flight_case(mu_s=0.5, mach=2.5, altitude_m=3000.0)
    assert got == want


# --------------------------------------------------------------------------- evaluation


def reference(spec: SweepSpec) -> np.ndarray:
    """Independent plain loop over opening_time with the case factories."""
    out = np.empty(spec.shape)
    for i, w in enumerate(spec.axes["spin_rate"]):
        for j, mu in enumerate(spec.axes["mu_s"]):
            out[i, j] = opening_time(rig_case(float(w), float(mu)), FAST)
    return out


def test_sweep_equals_plain_loop() -> None:
    spec = small_spec()
    ds = run_sweep(spec, runner=Runner(workers=1))
    assert ds["t_cr"].dims == ("spin_rate", "mu_s")
    np.testing.assert_array_equal(ds["t_cr"].values, reference(spec))
    assert np.all(ds["status"].values == Status.OPENED)
    assert ds["spin_rate"].attrs["units"] == "rad/s"
    assert ds["t_cr"].attrs["units"] == "s"
    assert ds.attrs["torque_model"] == "thesis"
    assert ds.attrs["solver_rtol"] == 1e-6
    assert "obturator_version" in ds.attrs
    # scalar coordinates record what was not swept
    assert float(ds["theta0_deg"]) == TABLE1["theta0_deg"]
    # t_cr rises with spin and falls with friction at these spins
    t = ds["t_cr"].values
    assert np.all(np.diff(t, axis=0) > 0) and np.all(np.diff(t, axis=1) < 0)


def test_process_pool_equals_in_process() -> None:
    spec = small_spec()
    one = run_sweep(spec, runner=Runner(workers=1))
    run = execute_sweep(spec, runner=Runner(workers=2, chunk_size=1))
    assert run.workers == 2 and run.n_computed == 6
    xr.testing.assert_identical(one, run.dataset)


def test_cheap_study_runs_in_process(monkeypatch: pytest.MonkeyPatch) -> None:
    """With the real threshold a 6-point study (~ms of work) starts no pool; its probe
    chunk and the rest give the same dataset as workers=1."""
    monkeypatch.setattr(runs_runner, "POOL_MIN_SERIAL_S", 0.1)  # the module's default
    spec = small_spec()
    one = run_sweep(spec, runner=Runner(workers=1))
    run = execute_sweep(spec, runner=Runner(workers=2, chunk_size=1))
    assert run.workers == 1 and run.n_computed == 6
    xr.testing.assert_identical(one, run.dataset)


def test_spawned_pool_equals_in_process(monkeypatch: pytest.MonkeyPatch) -> None:
    import multiprocessing

    spec = small_spec(axes={"spin_rate": [300.0, 500.0], "mu_s": [0.55]})
    one = run_sweep(spec, runner=Runner(workers=1))
    monkeypatch.setattr(pools, "mp_context", lambda: multiprocessing.get_context("spawn"))
    xr.testing.assert_identical(one, run_sweep(spec, runner=Runner(workers=2, chunk_size=1)))


def test_not_opened_is_nan_with_status() -> None:
    spec = small_spec(axes={"spin_rate": [300.0, 600.0]}, fixed={"mu_s": 0.55}, t_max=0.3)
    ds = run_sweep(spec, runner=Runner(workers=1))
    assert ds["status"].values.tolist() == [1, 0]
    assert np.isfinite(ds["t_cr"].values[0]) and np.isnan(ds["t_cr"].values[1])
    s = sweep_summary(ds)
    assert s["n_opened"] == 1 and s["n_not_opened"] == 1
    assert s["argmin"] == {"spin_rate": 300.0}


def test_solver_failure_is_recorded(monkeypatch: pytest.MonkeyPatch) -> None:
    def fail(case: object, options: object) -> float:
        raise RuntimeError("step limit")

    # the failure is injected into the per-point path of a method outside the packed
    # path; the lanes' statuses are checked against it in tests/core/test_lanes.py
    monkeypatch.setattr("obturator.solve.many.opening_time", fail)
    spec = small_spec(axes={"spin_rate": [300.0, 400.0]})
    spec = replace(spec, options=replace(spec.options, method="radau"))
    ds = run_sweep(spec, runner=Runner(workers=1))
    assert ds["status"].values.tolist() == [Status.FAILED] * 2
    assert np.all(np.isnan(ds["t_cr"].values))


# --------------------------------------------------------------------------- resuming


class Boom(Exception):
    pass


def test_resume_skips_finished_points(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    spec = small_spec(axes={"spin_rate": [300.0, 350.0, 400.0, 450.0, 500.0], "mu_s": [0.5, 0.6]})
    store = tmp_path / "s.nc"
    original = job_module.run_chunk  # every chunk runs here
    calls: list[tuple[float, float]] = []

    def exploding(sp: SweepSpec, names, rows, *packed):
        if len(calls) == 4:
            raise Boom
        calls.extend((r[0], r[1]) for r in rows.tolist())
        return original(sp, names, rows, *packed)

    monkeypatch.setattr(job_module, "run_chunk", exploding)
    with pytest.raises(Boom):
        run_sweep(spec, runner=Runner(workers=1, chunk_size=2, store=store))
    side = sidecar_path(store)
    assert side.exists() and not store.exists()
    lines = side.read_text().splitlines()
    assert json.loads(lines[0])["study"] == spec.digest()
    assert len(lines) == 1 + 2  # two finished chunks of two points; the third was cut
    done = {(r[0], r[1]) for line in lines[1:] for r in spec.rows(json.loads(line)["keys"])}
    assert len(done) == 4

    recomputed: list[tuple[float, float]] = []

    def counting(sp: SweepSpec, names, rows, *packed):
        recomputed.extend((r[0], r[1]) for r in rows.tolist())
        return original(sp, names, rows, *packed)

    monkeypatch.setattr(job_module, "run_chunk", counting)
    run = execute_sweep(spec, runner=Runner(workers=1, chunk_size=2, store=store))
    assert run.n_resumed == 4 and run.n_computed == 6
    assert len(recomputed) == 6 and not done & set(recomputed)
    assert store.exists() and not side.exists()
    monkeypatch.setattr(job_module, "run_chunk", original)
    full = run_sweep(spec, runner=Runner(workers=1))
    xr.testing.assert_identical(full, run.dataset)
    with xr.open_dataset(store) as on_disk:
        xr.testing.assert_equal(on_disk.load(), full)


def _record(spec: SweepSpec, index, t_cr, status) -> dict:
    """A store record as the sweep writes it, with each point's planned route."""
    from obturator.solve.many import pack_points
    from obturator.solve.plan import plan_routes

    spins = spec.axes["spin_rate"]
    routes = []
    for i in index:
        if not 0 <= i < len(spins):
            routes.append(0)
            continue
        packed = pack_points([spec.build_case({"spin_rate": float(spins[i])})], spec.options)
        routes.append(int(plan_routes(packed.valid, packed.p, packed.y0, spec.options)[0]))
    keys = list(index)
    values = {"t_cr": list(t_cr), "status": list(status), "route": routes}
    crc = run_store.record_crc(keys, values)
    return {"keys": keys, "values": values, "study": spec.digest(), "crc": crc}


def test_resume_ignores_cut_line_and_refuses_other_spec(tmp_path: Path) -> None:
    spec = small_spec(axes={"spin_rate": [300.0, 400.0]}, fixed={"mu_s": 0.55})
    store = tmp_path / "r.nc"
    side = sidecar_path(store)
    header = {"format": run_store.STORE_FORMAT, "study": spec.digest()}
    t0 = opening_time(spec.build_case({"spin_rate": 300.0}), FAST)
    side.write_text(
        json.dumps(header)
        + "\n"
        + json.dumps(_record(spec, [0], [t0], [1]))
        + '\n{"keys": [1], "values": {"t_c'  # interrupted mid-write
    )
    run = execute_sweep(spec, runner=Runner(workers=1, store=store))
    assert run.n_resumed == 1 and run.n_computed == 1
    assert run.dataset["t_cr"].values[0] == t0

    other = small_spec(axes={"spin_rate": [300.0, 500.0]}, fixed={"mu_s": 0.55})
    side.write_text(json.dumps(header) + "\n")
    with pytest.raises(InputError, match="different study"):
        run_sweep(other, runner=Runner(workers=1, store=store))
    ds = run_sweep(other, runner=Runner(workers=1, store=store, restart=True))
    assert ds["spin_rate"].values.tolist() == [300.0, 500.0] and not side.exists()


def test_bad_worker_count_and_directory(tmp_path: Path) -> None:
    spec = small_spec(axes={"spin_rate": [300.0, 400.0]})
    with pytest.raises(InputError, match="workers"):
        run_sweep(spec, runner=Runner(workers=0))
    with pytest.raises(InputError, match="does not exist"):
        run_sweep(spec, runner=Runner(workers=1, store=tmp_path / "no" / "x.nc"))


# --------------------------------------------------------------------------- dask


def test_dask_distributed_equals_local(dask_cluster) -> None:
    import distributed

    spec = small_spec()
    local = run_sweep(spec, runner=Runner(workers=1))
    with distributed.Client(dask_cluster) as client:
        run = execute_sweep(spec, runner=Runner(scheduler=client, chunk_size=2))
        assert run.backend == "dask.distributed"
        xr.testing.assert_identical(local, run.dataset)
    by_address = run_sweep(spec, runner=Runner(scheduler=dask_cluster.scheduler_address))
    xr.testing.assert_identical(local, by_address)


# --------------------------------------------------------------------------- CLI


def test_cli_sweep_writes_netcdf_and_csv(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "sweep.nc"
    argv = ["sweep", "--case", "spin-rig", "--spin-rate", "300:600:3", "--mu-s", "0.5473"]
    argv += ["--rtol", "1e-6", "--workers", "1", "--no-progress", "--out", str(out)]
    assert main(argv) == 0
    line = capsys.readouterr().out.strip()
    assert line.count("\n") == 0 and "3 points" in line and "3 opened" in line
    with xr.open_dataset(out) as ds:
        assert ds["t_cr"].dims == ("spin_rate",)
        assert float(ds["mu_s"]) == 0.5473
        want = [opening_time(rig_case(w, 0.5473), FAST) for w in (300.0, 450.0, 600.0)]
        np.testing.assert_array_equal(ds["t_cr"].values, want)
    lines = (tmp_path / "sweep.csv").read_text().splitlines()
    comments = [r for r in lines if r.startswith("#")]
    rows = [r for r in lines if not r.startswith("#")]
    # the fixed parameters and the settings travel with the CSV
    assert "# mu_s = 0.5473 1" in comments and any("solver_rtol" in c for c in comments)
    assert any(c.startswith("# history = ") and "sweep" in c for c in comments)
    assert rows[0] == "spin_rate [rad/s],t_cr [s],status,route" and len(rows) == 4
    assert float(rows[1].split(",")[1]) == pytest.approx(want[0], rel=1e-11)


def test_cli_sweep_json_and_flight(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "f.nc"
    argv = ["sweep", "--case", "flight", "--mach", "2.5,3", "--altitude-m", "1000"]
    argv += ["--spin-rate", "12042", "--rtol", "1e-6", "--workers", "1", "--no-progress"]
    argv += ["--out", str(out), "--no-csv", "--json"]
    assert main(argv) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["n_points"] == 2 and d["n_opened"] == 2 and d["csv"] is None
    assert 0.0 < d["t_cr_min_s"] < 0.1  # flight opens well within 0.1 s
    assert not (tmp_path / "f.csv").exists()


@pytest.mark.parametrize(
    ("argv", "field"),
    [
        (["--spin-rate", "200:700"], "spin_rate"),
        (["--spin-rate", "200:700:zero"], "spin_rate"),
        (["--mu-s", "0.5,abc"], "mu_s"),
        (["--mach", "2,3"], "mach"),
        (["--theta0-deg", "80:95:3"], "theta0"),
        (["--workers", "0"], "workers"),
        (["--rtol", "big"], "rtol"),
    ],
)
def test_cli_sweep_bad_input(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], argv: list[str], field: str
) -> None:
    code = main(["sweep", "--case", "spin-rig", *argv, "--out", str(tmp_path / "x.nc")])
    assert code == 2
    err = capsys.readouterr().err
    assert err.startswith("obturator: error:") and err.count("\n") == 1
    assert field in err or field.replace("_", "-") in err  # the flag, when its kind refuses it
    assert not list(tmp_path.iterdir())


def test_cli_sweep_missing_directory(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["sweep", "--spin-rate", "300,400", "--out", str(tmp_path / "a" / "b.nc")])
    assert code == 2
    assert "does not exist" in capsys.readouterr().err


def test_cli_subprocess(tmp_path: Path) -> None:
    out = tmp_path / "p.nc"
    cmd = [sys.executable, "-m", "obturator", "sweep", "--case", "spin-rig"]
    cmd += ["--spin-rate", "400,500", "--mu-s", "0.5473", "--rtol", "1e-6", "--workers", "2"]
    cmd += ["--out", str(out)]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=300, cwd=tmp_path)
    assert res.returncode == 0, res.stderr
    assert "2 points" in res.stdout and "2 opened" in res.stdout
    with xr.open_dataset(out) as ds:
        assert np.all(np.isfinite(ds["t_cr"].values))
    bad = subprocess.run(
        [*cmd[:6], "--spin-rate", "400:500:x", "--out", str(out)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert bad.returncode == 2
    assert bad.stderr.startswith("obturator: error:") and bad.stderr.count("\n") == 1


def test_convergence_check_marks_unconverged_points():
    # The regularised law with a too-wide friction width (1e-5 omega_p): t_cr at 78 rad/s
    # moves ~1 % against width / 10 and another regularisation family (long near-stick
    # phase) and must be flagged; at 200 rad/s the same width is converged (changes
    # ~1e-4). (Under "auto" 78 rad/s runs set-valued: no width, nothing to flag.)
    from obturator.sweeps import SweepSpec, run_sweep

    spec = SweepSpec(
        "spin-rig",
        {"spin_rate": np.array([78.0, 200.0])},
        {"mu_s": 0.5473},
        options=SolverOptions(friction_width=1e-5, method="regularised"),
        check_convergence=True,
    )
    ds = run_sweep(spec, runner=Runner(workers=1))
    assert ds["status"].values.tolist() == [Status.UNCONVERGED, Status.OPENED]
    assert np.all(np.isfinite(ds["t_cr"].values))
    plain = SweepSpec(
        "spin-rig",
        {"spin_rate": np.array([78.0, 200.0])},
        {"mu_s": 0.5473},
        options=SolverOptions(friction_width=1e-5, method="regularised"),
    )
    assert plain.digest() != spec.digest()  # a resumed run cannot mix the two


@pytest.mark.parametrize(
    "damage",
    ["t_cr changed 1 %", "index -1", "index n", "status 300", "invalid utf-8", "foreign hash"],
)
def test_damaged_records_are_discarded_and_recomputed(
    tmp_path: Path, damage: str, capsys: pytest.CaptureFixture[str]
) -> None:
    spec = small_spec(axes={"spin_rate": [300.0, 400.0]}, fixed={"mu_s": 0.55})
    store = tmp_path / "d.nc"
    truth = run_sweep(spec, runner=Runner(workers=1))
    t = truth["t_cr"].values
    good = _record(spec, [0], [t[0]], [1])
    bad = dict(_record(spec, [1], [t[1]], [1]))
    if damage == "t_cr changed 1 %":
        bad["values"] = {**bad["values"], "t_cr": [t[1] * 1.01]}  # the CRC no longer matches
    elif damage == "index -1":
        bad = _record(spec, [-1], [t[1]], [1])
    elif damage == "index n":
        bad = _record(spec, [2], [t[1]], [1])
    elif damage == "status 300":
        bad = _record(spec, [1], [t[1]], [300])
    elif damage == "foreign hash":
        bad["study"] = "0" * 64
    header = {"format": run_store.STORE_FORMAT, "study": spec.digest()}
    body = (json.dumps(header) + "\n" + json.dumps(good) + "\n").encode()
    body += (
        b"\xff\xfe garbage\n" if damage == "invalid utf-8" else (json.dumps(bad) + "\n").encode()
    )
    sidecar_path(store).write_bytes(body)
    run = execute_sweep(spec, runner=Runner(workers=1, store=store))
    assert run.n_resumed == 1 and run.n_computed == 1
    np.testing.assert_array_equal(run.dataset["t_cr"].values, t)  # bit-identical
    assert "1 damaged or foreign records" in capsys.readouterr().err


def test_second_writer_is_refused_and_stale_lock_taken_over(tmp_path: Path) -> None:
    import os

    spec = small_spec(axes={"spin_rate": [300.0, 400.0]}, fixed={"mu_s": 0.55})
    store = tmp_path / "l.nc"
    lock = store.with_name(store.name + ".lock")
    lock.write_text(json.dumps({"pid": os.getppid(), "spec_hash": "x"}))  # a live process
    with pytest.raises(InputError, match="being written by another run"):
        run_sweep(spec, runner=Runner(workers=1, store=store))
    assert not sidecar_path(store).exists()
    lock.write_text(json.dumps({"pid": 2**22 + 12345, "spec_hash": "x"}))  # no such pid
    ds = run_sweep(spec, runner=Runner(workers=1, store=store))
    assert np.all(np.isfinite(ds["t_cr"].values)) and not lock.exists()


def test_csv_that_collides_with_netcdf_is_refused(tmp_path: Path) -> None:
    spec = small_spec(axes={"spin_rate": [300.0, 400.0]}, fixed={"mu_s": 0.55})
    out = tmp_path / "data.csv"
    with pytest.raises(InputError, match="also the NetCDF output"):
        execute_sweep(spec, csv=out, runner=Runner(workers=1, store=out))


@pytest.mark.parametrize("victim", ["write_netcdf", "write_csv"])
def test_full_disk_is_one_line_and_loses_nothing(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, victim: str
) -> None:
    # ENOSPC injected while an output is written: one InputError naming the file and
    # saying the finished points are kept; the rerun writes the outputs from the
    # partial results without recomputing a point, bit-identical to a clean run.
    import errno

    spec = small_spec(axes={"spin_rate": [300.0, 400.0, 500.0]}, fixed={"mu_s": 0.55})
    store, csv = tmp_path / "f.nc", tmp_path / "f.csv"
    original = getattr(export, victim)

    def full(*args, **kwargs):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(export, victim, full)
    with pytest.raises(InputError, match="No space left on device.*finished points are kept"):
        execute_sweep(spec, csv=csv, runner=Runner(workers=1, store=store))
    assert sidecar_path(store).exists()
    monkeypatch.setattr(export, victim, original)
    run = execute_sweep(spec, csv=csv, runner=Runner(workers=1, store=store))
    assert run.n_resumed == 3 and run.n_computed == 0
    assert store.exists() and csv.exists() and not sidecar_path(store).exists()
    full_run = run_sweep(spec, runner=Runner(workers=1))
    np.testing.assert_array_equal(run.dataset["t_cr"].values, full_run["t_cr"].values)


def test_validation_mechanisms_are_sweep_axes() -> None:
    """theta_dot0, release_phase, speed_ratio and slip_speed sweep like any parameter;
    each point equals the case built directly (rig_case keywords)."""
    import math

    from obturator.model.cases import rig_case
    from obturator.model.torques import SlipSpeedLaw
    from obturator.solve import opening_time

    spec = SweepSpec(
        case="spin-rig",
        axes={"speed_ratio": [0.3, 0.9], "theta_dot0": [-1.0, 1.0]},
        fixed={"spin_rate": 200.0, "mu_s": 0.75, "slip_speed": 0.12, "release_phase": 1.0},
        speed_law="strengthening",
    )
    ds = run_sweep(spec, runner=Runner(workers=1))
    for r in (0.3, 0.9):
        for td in (-1.0, 1.0):
            case = rig_case(
                200.0,
                0.75,
                speed_law=SlipSpeedLaw("strengthening", r, 0.12),
                release_rate=(td, 0.0, 0.0),
                release_phase=1.0,
            )
            got = float(ds["t_cr"].sel(speed_ratio=r, theta_dot0=td))
            assert math.isfinite(got) and got == opening_time(case)
    with pytest.raises(InputError, match="^speed_law"):
        SweepSpec(case="flight", speed_law="weakening")


def test_default_chunks_lanes_and_tasks() -> None:
    """About 8 chunks per worker, every point once; lane chunks up to LANE_CHUNK points
    (enough stiff points per chunk for the Radau IIA lanes), others up to TASK_CHUNK."""
    todo = np.arange(100_000)
    lanes = run_chunks.make_chunks(todo, 2, None, LANE_CHUNK)
    tasks = run_chunks.make_chunks(todo, 2, None)
    assert LANE_CHUNK == 1024 and run_chunks.TASK_CHUNK == 256
    assert 1000 < max(c.size for c in lanes) <= 1024 and len(lanes) == 98
    assert 250 < max(c.size for c in tasks) <= 256 and len(tasks) == 391
    small = run_chunks.make_chunks(np.arange(10_000), 2, None, LANE_CHUNK)
    assert len(small) == 16 and {c.size for c in small} == {625}
    for chunks in (lanes, tasks, small):
        np.testing.assert_array_equal(
            np.sort(np.concatenate(chunks)), np.arange(sum(c.size for c in chunks))
        )


def test_contiguous_chunks_are_runs_of_consecutive_points() -> None:
    """A contiguous job's chunks (a sweep in lanes: its spins share return maps) are runs
    of consecutive points, as many and as large as the strided ones, each point once,
    handed out from both ends of the run inwards."""
    todo = np.arange(3, 10_003)
    strided = run_chunks.make_chunks(todo, 2, None, LANE_CHUNK)
    runs = run_chunks.make_chunks(todo, 2, None, LANE_CHUNK, contiguous=True)
    assert len(runs) == len(strided) == 16
    assert max(c.size for c in runs) == max(c.size for c in strided)
    for c in runs:
        np.testing.assert_array_equal(np.diff(c), 1)
    starts = [int(c[0]) for c in runs]
    np.testing.assert_array_equal(np.concatenate([runs[k] for k in np.argsort(starts)]), todo)
    rank = np.argsort(np.argsort(starts))  # position of each handed-out chunk in the run
    assert rank.tolist() == [0, 15, 1, 14, 2, 13, 3, 12, 4, 11, 5, 10, 6, 9, 7, 8]
    odd = run_chunks.make_chunks(np.arange(5), 2, 1, LANE_CHUNK, contiguous=True)
    assert [int(c[0]) for c in odd] == [0, 4, 1, 3, 2]
    spec = SweepSpec(case="spin-rig", axes={"spin_rate": [40.0, 41.0]})
    assert sweep_job(spec, ("spin_rate",), lambda idx: idx).contiguous
    one_by_one = SweepSpec(
        case="spin-rig", axes={"spin_rate": [40.0]}, options=SolverOptions(method="radau")
    )
    assert not sweep_job(one_by_one, ("spin_rate",), lambda idx: idx).contiguous
