"""A sweep's points give the bits of each point alone, on every backend of the runner.

The plan's contract (:mod:`obturator.solve.plan`): a point's t_cr and status depend on
that point and the options alone, not on which points share its batch, chunk or worker.
``tests/solve/test_plan.py`` checks batches and chunkings in one process; here the same
spins, across the routes of the rig's operating range (set-valued with the shared return
maps of the sweep's default options, regularised in lanes), run as a sweep with one
worker, with two (one point per chunk, so each worker holds a different set) and on a
Dask cluster of two processes, and every t_cr is compared with ``opening_time`` of the
point alone at the same options, bit for bit.
"""

from __future__ import annotations

import numpy as np
import pytest

from obturator.model.cases import rig_case
from obturator.runs import Runner
from obturator.solve import opening_time
from obturator.status import Status
from obturator.sweeps import SweepSpec, execute_sweep, run_sweep

# set-valued (shared maps) below ~218 rad/s, regularised lanes above; 88.02 and 112.04
# rad/s are the spins whose t_cr depended on their batch before the plan
SPINS = [52.0, 88.02, 112.04, 160.0, 260.0, 480.0, 900.0]
MU_S = 0.5473


def _alone(spec: SweepSpec) -> np.ndarray:
    return np.array([opening_time(rig_case(w, MU_S), spec.options) for w in SPINS])


def _bits(x: np.ndarray) -> list[str]:
    return [float(v).hex() for v in np.ravel(x)]


@pytest.fixture(scope="module")
def spec_and_alone() -> tuple[SweepSpec, np.ndarray]:
    spec = SweepSpec("spin-rig", {"spin_rate": SPINS}, {"mu_s": MU_S})
    assert spec.options.shared_maps  # the sweep's default: the shared-map route is in play
    return spec, _alone(spec)


def test_one_and_two_workers_give_the_bits_of_each_point_alone(spec_and_alone) -> None:
    spec, alone = spec_and_alone
    one = run_sweep(spec, runner=Runner(workers=1))
    two = execute_sweep(spec, runner=Runner(workers=2, chunk_size=1))
    assert two.workers == 2
    for ds in (one, two.dataset):
        assert np.all(ds["status"].values == Status.OPENED)
        assert _bits(ds["t_cr"].values) == _bits(alone)


def test_dask_gives_the_bits_of_each_point_alone(spec_and_alone, dask_cluster) -> None:
    import distributed

    spec, alone = spec_and_alone
    with distributed.Client(dask_cluster) as client:
        run = execute_sweep(spec, runner=Runner(scheduler=client, chunk_size=2))
    assert run.backend == "dask.distributed"
    assert _bits(run.dataset["t_cr"].values) == _bits(alone)
