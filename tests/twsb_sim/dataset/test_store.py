"""Shards are written whole or not at all, and leave no temporary file behind."""

from __future__ import annotations

import os

import pytest

from twsb_sim.dataset import store


def test_a_write_lands_whole_and_leaves_no_temporary_file(tmp_path):
    path = tmp_path / "chunk-000" / "episode_000000.parquet"
    store.write_atomic(path, b"shard")
    assert path.read_bytes() == b"shard"
    assert sorted(p.name for p in path.parent.iterdir()) == [path.name]


def test_an_interrupt_mid_write_leaves_neither_the_file_nor_a_temporary_one(tmp_path, monkeypatch):
    # Ctrl-C while the bytes are being flushed to disk: the shard is absent (the episode
    # is generated again on resume) and nothing half-written lies beside it
    path = tmp_path / "chunk-000" / "episode_000001.parquet"

    def interrupted(descriptor: int) -> None:
        raise KeyboardInterrupt

    monkeypatch.setattr(os, "fsync", interrupted)
    with pytest.raises(KeyboardInterrupt):
        store.write_atomic(path, b"shard")
    assert list(path.parent.iterdir()) == []
