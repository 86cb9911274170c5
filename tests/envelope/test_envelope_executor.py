"""Resumable execution (store, interruption, local pool, Dask) and the envelope map."""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
import pytest

from obturator.envelope.envelope import EnvelopeSpec, envelope_summary, run_envelope
from obturator.envelope.model import FlightModel
from obturator.errors import InputError
from obturator.flow import choking_mach_freestream
from obturator.runs import Runner, sidecar_path, study_digest, task_key
from obturator.solve import SolverOptions

FAST = SolverOptions(rtol=1e-6, atol=1e-8)


@dataclass(frozen=True)
class Square:
    """Picklable toy point function."""

    def __call__(self, task):
        return {"y": task["x"] ** 2}


@dataclass
class Interrupting:
    """Raises KeyboardInterrupt at its `stop`-th call (in-process runs only)."""

    stop: int
    calls: int = 0

    def __call__(self, task):
        self.calls += 1
        if self.calls == self.stop:
            raise KeyboardInterrupt
        return {"y": task["x"] ** 2}


def tasks(n=10):
    return [{"x": float(i)} for i in range(n)]


def test_local_pool_and_duplicates():
    ts = tasks(12) + [{"x": 3.0}]
    a = Runner(workers=1).map(Square(), ts)
    b = Runner(workers=2, chunk_size=2).map(Square(), ts)
    assert a == b and a[-1] == {"y": 9.0}
    assert task_key({"x": 1.0, "z": 2.0}) == task_key({"z": 2.0, "x": 1.0})


def test_interrupted_run_resumes_without_loss_or_duplicates(tmp_path):
    out = tmp_path / "out.nc"
    path = sidecar_path(out)
    digest = study_digest({"study": "toy"})
    runner = Runner(workers=1, store=out, chunk_size=1)
    runner.open(digest)
    fn = Interrupting(stop=5)
    with pytest.raises(KeyboardInterrupt):
        runner.map(fn, tasks())
    lines = path.read_text().splitlines()
    assert len(lines) == 1 + 4  # header + four finished chunks
    assert not out.with_name("out.nc.lock").exists()  # released on the interruption
    path.write_text(path.read_text() + '{"keys": ["cut sh')  # a line cut by the interruption
    counter = Interrupting(stop=-1)
    runner = Runner(workers=1, store=out)
    runner.open(digest)
    assert len(runner.sidecar.records) == 4 and runner.sidecar.n_discarded == 1
    out_values = runner.map(counter, tasks())
    assert [r["y"] for r in out_values] == [float(i * i) for i in range(10)]
    assert counter.calls == 6 and runner.n_resumed == 4 and runner.n_computed == 6
    keys = [
        k
        for line in path.read_text().splitlines()[1:]
        if line.startswith('{"keys": [') and line.endswith("}")
        for k in json.loads(line)["keys"]
    ]
    assert len(keys) == len(set(keys)) == 10
    runner.close()
    other = study_digest({"study": "other"})
    with pytest.raises(InputError, match="^store:.*different study"):
        Runner(store=out).open(other)
    fresh = Runner(store=out, restart=True)
    fresh.open(other)
    assert len(fresh.sidecar.records) == 0
    fresh.write_outputs([])
    assert not path.exists()


def test_dask_backend():
    distributed = pytest.importorskip("distributed")
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1) as client:
        out = Runner(scheduler=client).map(Square(), tasks(5))
    assert [r["y"] for r in out] == [0.0, 1.0, 4.0, 9.0, 16.0]


def test_envelope_map_and_marks():
    spec = EnvelopeSpec(
        [1.5, 3.0], [0.0, 10_000.0], model=FlightModel(options=FAST, check_convergence=False)
    )
    ds = run_envelope(spec, Runner(workers=1))
    assert ds["t_cr_coupled"].dims == ("mach", "altitude_m")
    assert (ds["status_coupled"] == 1).all() and (ds["status_constant"] == 1).all()
    assert (ds["relative_difference"] > 0).all()
    # Fanno choking Mach at 10 km (independent call) lies above 1.5: marked choked there
    m_choke = choking_mach_freestream(76.2 / 9.44, 9.44e-3, altitude_m=10_000.0)
    assert ds["choke_mach"].sel(altitude_m=10_000.0) == pytest.approx(m_choke)
    assert m_choke > 1.5 and ds["choked_at_muzzle"].sel(mach=1.5, altitude_m=10_000.0) == 1
    assert ds["choked_at_muzzle"].sel(mach=3.0).sum() == 0
    assert (ds["started"] == 1).all()  # constant-area bore
    # t_cr grows with altitude and falls with Mach
    t = ds["t_cr_constant"].values
    assert t[0, 1] > t[0, 0] and t[1, 0] < t[0, 0]
    s = envelope_summary(ds)
    assert s["points"] == 4 and s["coupled_opened"] == 4
    assert s["max_relative_difference_at"]["mach"] == 1.5
    # a contraction that does not self-start below Mach ~1.6 marks the Mach 1.5 row
    spec2 = EnvelopeSpec([1.5, 3.0], [0.0], model=spec.model, area_ratio=1.2)
    ds2 = run_envelope(spec2)
    assert list(ds2["started"].values) == [0, 1]


def test_envelope_resumes(tmp_path, monkeypatch):
    spec = EnvelopeSpec(
        [2.0, 3.0, 4.0], [0.0], model=FlightModel(options=FAST, check_convergence=False)
    )
    out = tmp_path / "env.nc"
    seen: list[float] = []
    original = FlightModel.evaluate_many

    def flaky(self, points):  # interrupted when the third point starts
        for values in points:
            if values["mach"] not in seen:  # (a point may call the model more than once)
                seen.append(values["mach"])
        if len(seen) == 3:
            raise KeyboardInterrupt
        return original(self, points)

    monkeypatch.setattr(FlightModel, "evaluate_many", flaky)
    runner = Runner(workers=1, store=out, chunk_size=1)
    runner.open(study_digest(spec.identity()))
    with pytest.raises(KeyboardInterrupt):
        run_envelope(spec, runner)
    monkeypatch.setattr(FlightModel, "evaluate_many", original)
    runner = Runner(workers=1, store=out)
    runner.open(study_digest(spec.identity()))
    ds = run_envelope(spec, runner)
    assert runner.n_resumed == 2 and runner.n_computed == 1
    ref = run_envelope(spec)
    np.testing.assert_array_equal(ds["t_cr_coupled"].values, ref["t_cr_coupled"].values)


def test_envelope_validation():
    with pytest.raises(InputError, match="^mach:"):
        EnvelopeSpec([0.8, 2.0], [0.0])
    with pytest.raises(InputError, match="^altitude_m:"):
        EnvelopeSpec([2.0], [0.0, 0.0])
    with pytest.raises(InputError, match="^area_ratio:"):
        EnvelopeSpec([2.0], [0.0], area_ratio=1.8)
