"""Generation: the same data set whatever the workers, after a kill and resume, or extended."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from twsb_sim.cli import main
from twsb_sim.dataset.generation import generate
from twsb_sim.dataset.store import DatasetMismatchError

from .conftest import EPISODES, SEED, shard_bytes


def meta_bytes(root):
    return {name: (root / "meta" / name).read_bytes() for name in ("info.json", "episodes.jsonl")}


def test_two_workers_write_the_same_bytes_as_one(tmp_path, reference, short_settings):
    # finishing order differs with a pool; content must not
    generate(tmp_path, EPISODES, short_settings, workers=2, progress=False)
    assert shard_bytes(tmp_path) == shard_bytes(reference)
    assert meta_bytes(tmp_path) == meta_bytes(reference)


def test_killed_run_resumes_to_the_uninterrupted_data_set(tmp_path, reference, short_ranges_file):
    out = tmp_path / "data"
    command = ["generate", "--out", str(out), "--episodes", str(EPISODES), "--seed", str(SEED),
               "--ranges", str(short_ranges_file), "--workers", "1", "--quiet"]  # fmt: skip
    run = subprocess.Popen(
        [sys.executable, "-m", "twsb_sim.cli", *command],
        start_new_session=True,  # its own process group: the kill reaches all of it
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        deadline = time.monotonic() + 60
        while not list(out.glob("data/*/episode_*.parquet")) and time.monotonic() < deadline:
            assert run.poll() is None, "the run ended before it could be killed"
            time.sleep(0.01)
    finally:
        os.killpg(run.pid, signal.SIGKILL)
        run.wait()
    interrupted = shard_bytes(out)
    assert 1 <= len(interrupted) < EPISODES
    assert all(interrupted[name] == shard_bytes(reference)[name] for name in interrupted)

    assert main(command) == 0  # the same command again
    assert shard_bytes(out) == shard_bytes(reference)
    assert meta_bytes(out) == meta_bytes(reference)
    assert not list(out.rglob(".*.partial"))


def test_more_episodes_extend_and_other_settings_are_refused(tmp_path, reference, short_settings):
    generate(tmp_path, 3, short_settings, workers=1, progress=False)
    report = generate(tmp_path, 5, short_settings, workers=1, progress=False)
    assert (report.skipped, report.generated, report.episodes) == (3, 2, 5)
    assert shard_bytes(tmp_path) == {
        k: v for k, v in shard_bytes(reference).items() if int(k[-14:-8]) < 5
    }
    other = type(short_settings)(seed=SEED + 1, randomization=short_settings.randomization)
    with pytest.raises(DatasetMismatchError, match="seed: 11 there, 12 here"):
        generate(tmp_path, 5, other, workers=1, progress=False)


def test_command_line_errors_are_one_line(tmp_path, capsys, short_ranges_file):
    (tmp_path / "notes.txt").write_text("mine")
    assert main(["generate", "--out", str(tmp_path), "--episodes", "1", "--quiet"]) == 2
    assert "not a data set" in capsys.readouterr().err
    assert main(["generate", "--out", str(tmp_path / "x"), "--workers", "0"]) == 2
    assert main(["generate", "--show-ranges", "--ranges", str(short_ranges_file)]) == 0
    assert "duration_s = [2.0, 3.0]" in capsys.readouterr().out


def test_package_exports_the_functions():
    import twsb_sim.dataset as dataset
    from twsb_sim.dataset import generation

    assert dataset.generate is generation.generate  # not the module of the same stem
    assert set(dataset.__all__) >= {"generate", "open_dataset", "export_bag", "run_episode"}
