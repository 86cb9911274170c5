"""Fixtures of the study tests."""

from __future__ import annotations

import pytest


@pytest.fixture
def dask_cluster():
    """A local Dask cluster of two one-thread worker processes (skips without
    ``distributed``)."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=2, processes=True, threads_per_worker=1, dashboard_address=None
    ) as cluster:
        yield cluster
