"""Generation on a Dask distributed cluster gives the same shards as a local run."""

from __future__ import annotations

import pytest

from twsb_sim.dataset.generation import generate

from .conftest import shard_bytes

distributed = pytest.importorskip("distributed")


def test_local_dask_cluster_writes_the_same_shards(tmp_path, reference, short_settings):
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None
    ) as cluster:
        report = generate(
            tmp_path, 4, short_settings, scheduler=cluster.scheduler_address, progress=False
        )
    assert report.generated == 4
    expected = {k: v for k, v in shard_bytes(reference).items() if int(k[-14:-8]) < 4}
    assert shard_bytes(tmp_path) == expected
