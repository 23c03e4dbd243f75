"""Real Ctrl-C (SIGINT to the process group) and SIGTERM of every ``twsb`` command that
writes files: exit status 130, one line, no traceback, and outputs a re-run can use."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from twsb_sim.cli import EXIT_BROKEN_PIPE, EXIT_INTERRUPTED, main

REPO = Path(__file__).resolve().parents[2]
# ten simulated minutes: far longer than any load can make the signal take to land
LONG = "duration_s = 600.0\n[[commands]]\nt_s = 0.5\nvelocity_mps = 0.5\nramp_s = 1.0\n"
LONG_FRAMES = 6001
SHORT_RANGES = "[episode]\nduration_s = [2.0, 3.0]\n"
pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="POSIX signals")


class Command:
    """A ``twsb`` command in its own process group, its stderr collected as it comes."""

    def __init__(self, *args: str) -> None:
        self.process = subprocess.Popen(
            [sys.executable, "-m", "twsb_sim.cli", *args],
            cwd=REPO,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            start_new_session=True,  # a group of its own, as a terminal's foreground job
            # a shell running jobs in the background ignores SIGINT: undo that here
            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
        )
        self.stderr = b""
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self) -> None:
        while chunk := os.read(self.process.stderr.fileno(), 4096):
            self.stderr += chunk

    def interrupt_when(self, ready: Callable[[str], bool], how: str, timeout_s: float = 90) -> int:
        """Wait until ``ready(stderr so far)``, then Ctrl-C (``"int"``: SIGINT to the
        group, as a terminal sends it) or ``"term"`` (SIGTERM to the main process only)."""
        deadline = time.monotonic() + timeout_s
        try:
            while not ready(self.stderr.decode(errors="replace")):
                assert self.process.poll() is None, f"ended first: {self.stderr.decode()}"
                assert time.monotonic() < deadline, "never became ready"
                time.sleep(0.002)
            assert self.process.poll() is None, f"ended before the signal: {self.stderr.decode()}"
            if how == "int":
                os.killpg(self.process.pid, signal.SIGINT)
            else:
                self.process.send_signal(signal.SIGTERM)
            returncode = self.process.wait(timeout=180)  # a loaded machine is slow to stop
            self._reader.join(10)
            return returncode
        finally:
            if self.process.poll() is None:
                os.killpg(self.process.pid, signal.SIGKILL)
                self.process.wait()

    def check_clean_stop(self, how: str) -> None:
        text = self.stderr.decode(errors="replace")
        assert "Traceback" not in text, text
        last = text.replace("\r", "\n").strip().splitlines()[-1]
        word = "interrupted" if how == "int" else "terminated (SIGTERM)"
        assert last.startswith(f"twsb: {word}"), text


def _file_appears(path: Path) -> Callable[[str], bool]:
    return lambda _: path.exists()


def _no_partials(folder: Path) -> None:
    assert not list(folder.rglob("*.partial*")), list(folder.rglob("*.partial*"))


def test_a_closed_output_pipe_ends_quietly(tmp_path):
    # as `twsb run ... | head -1` when head has left before the summary is printed
    scenario = tmp_path / "tiny.toml"
    scenario.write_text("duration_s = 0.3\n")
    run = subprocess.Popen(
        [sys.executable, "-m", "twsb_sim.cli", "run", str(scenario), "--quiet"],
        cwd=REPO,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    run.stdout.close()  # the reader is gone before the first line
    stderr = run.stderr.read().decode()
    assert run.wait(timeout=60) == EXIT_BROKEN_PIPE
    assert stderr == ""


@pytest.mark.parametrize("how", ["int", "term"])
def test_run_keeps_the_frames_simulated_before_the_interrupt(tmp_path, how):
    scenario = tmp_path / "long.toml"
    scenario.write_text(LONG)
    out, rrd = tmp_path / "run", tmp_path / "recordings" / "long.rrd"
    command = Command("run", str(scenario), "--out", str(out), "--rrd", str(rrd))
    some_frames = lambda err: re.search(rf" [1-9]\d*/{LONG_FRAMES} ", err) is not None  # noqa: E731
    assert command.interrupt_when(some_frames, how) == EXIT_INTERRUPTED
    command.check_clean_stop(how)
    with np.load(out / "frames.npz") as frames:
        assert 0 < len(frames["stamps"]) < LONG_FRAMES
    assert json.loads((out / "summary.json").read_text())["end_reason"] == "interrupted"
    assert rrd.stat().st_size > 0
    _no_partials(tmp_path)


@pytest.mark.parametrize("how", ["int", "term"])
def test_generate_keeps_finished_episodes_and_resumes(tmp_path, how):
    ranges = tmp_path / "short.toml"
    ranges.write_text(SHORT_RANGES)
    out = tmp_path / "data"
    args = ("generate", "--out", str(out), "--episodes", "4", "--ranges", str(ranges),
            "--workers", "2")  # fmt: skip
    command = Command(*args)
    first_shard = lambda _: bool(list(out.glob("data/*/episode_*.parquet")))  # noqa: E731
    assert command.interrupt_when(first_shard, how) == EXIT_INTERRUPTED
    text = command.stderr.decode(errors="replace")
    assert "Traceback" not in text and "run the same command again to resume" in text
    kept = len(list(out.glob("data/*/episode_*.parquet")))
    assert 1 <= kept < 4
    info = json.loads((out / "meta" / "info.json").read_text())
    assert info["totals"]["episodes"] == kept  # the metadata was written on the way out
    _no_partials(out)
    assert main([*args, "--quiet"]) == 0
    assert len(list(out.glob("data/*/episode_*.parquet"))) == 4


@pytest.fixture(scope="module")
def one_episode(tmp_path_factory) -> Path:
    from twsb_sim.dataset.generation import GenerationSettings, generate
    from twsb_sim.dataset.randomization import randomization_from_table

    root = tmp_path_factory.mktemp("dataset") / "data"
    ranges = randomization_from_table({"episode": {"duration_s": [20.0, 20.0]}})
    generate(root, 1, GenerationSettings(seed=3, randomization=ranges), workers=1, progress=False)
    return root


@pytest.mark.parametrize("how", ["int", "term"])
def test_export_bag_leaves_no_half_bag(tmp_path, one_episode, how):
    out, ros1 = tmp_path / "bags" / "episode0", tmp_path / "bags" / "episode0.bag"
    args = ("export-bag", str(one_episode), "--out", str(out), "--ros1", str(ros1))
    command = Command(*args)
    staging = out.with_name(f".{out.name}.partial")
    assert command.interrupt_when(_file_appears(staging), how) == EXIT_INTERRUPTED
    command.check_clean_stop(how)
    # each bag is whole or absent: on a loaded machine the ROS 2 bag may have been
    # completed (and the ROS 1 one begun) before the signal arrived
    assert not out.exists() or (out / "metadata.yaml").is_file()
    assert not ros1.exists() or out.exists()  # the ROS 1 bag is written second
    _no_partials(tmp_path)
    assert main(list(args)) == 0  # the same command again
    assert (out / "metadata.yaml").is_file() and ros1.stat().st_size > 0


@pytest.mark.parametrize(
    ("args", "progress"),
    [
        (("eval", "--quick", "--houses", "house1"), "it/s"),
        (("slam", "--quick", "--no-rerun"), "SLAM runs"),
        (("tune", "--quick"), "training episodes"),
    ],
)
def test_report_commands_leave_nothing_half_written(tmp_path, args, progress):
    out = tmp_path / ("params.toml" if args[0] == "tune" else "report")
    command = Command(*args, "--out", str(out))
    assert command.interrupt_when(lambda err: progress in err, "int") == EXIT_INTERRUPTED
    command.check_clean_stop("int")
    assert not out.exists()
    assert not list(tmp_path.iterdir())  # no partial output beside it either
