"""The worker pool of ``twsb generate``: results as they finish, errors with the worker's
traceback, and no worker left behind however the caller stops."""

from __future__ import annotations

import multiprocessing
import os
import sys

import pytest

from twsb_sim.dataset.workers import WorkerError, map_unordered

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="fork")
FORK = multiprocessing.get_context("fork") if sys.platform.startswith("linux") else None


def _square_plus(offset: int, item: int) -> tuple[int, int, int]:
    if item == 13:
        raise ValueError("thirteen")
    if item == 99:
        os._exit(3)
    return item, item * item + offset, os.getpid()


def test_every_item_once_and_the_work_shared():
    results = sorted(map_unordered(_square_plus, 5, range(12), 3, FORK))
    assert [(item, value) for item, value, _ in results] == [(k, k * k + 5) for k in range(12)]
    assert len({pid for *_, pid in results}) > 1


def test_a_task_that_raises_names_itself_and_the_workers_are_gone():
    children_before = set(multiprocessing.active_children())
    with pytest.raises(WorkerError, match=r"(?s)_square_plus\(13\).*ValueError: thirteen"):
        list(map_unordered(_square_plus, 0, [1, 13, 2], 2, FORK))
    assert set(multiprocessing.active_children()) <= children_before


def test_a_worker_that_dies_is_an_error():
    with pytest.raises(WorkerError, match="a worker died"):
        list(map_unordered(_square_plus, 0, [99], 1, FORK))


def test_stopping_early_leaves_no_worker():
    results = map_unordered(_square_plus, 0, range(100), 2, FORK)
    next(results)
    pids = {p.pid for p in multiprocessing.active_children()}
    assert pids
    results.close()
    assert not {p.pid for p in multiprocessing.active_children()} & pids
