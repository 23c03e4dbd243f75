"""Real kills of ``twsb generate``: no orphaned workers, and a data set that always resumes."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from twsb_sim.cli import main
from twsb_sim.dataset.store import INFO_FILE, prepare_output

from .conftest import SEED, shard_bytes

REPO = Path(__file__).resolve().parents[3]
pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")


def _children(pid: int) -> set[int]:
    try:
        text = Path(f"/proc/{pid}/task/{pid}/children").read_text()
    except FileNotFoundError:
        return set()
    return {int(p) for p in text.split()}


def _alive(pid: int) -> bool:
    """Running or sleeping; a zombie (dead, waiting to be reaped) counts as gone."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except FileNotFoundError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] not in ("Z", "X")


def _twsb(*args: str, **popen: object) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "twsb_sim.cli", *args],
        cwd=REPO,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        **popen,
    )


@pytest.mark.parametrize("after_s", [0.0, 1.0])  # at the fork, and in the middle of episodes
def test_workers_die_when_generate_is_killed(tmp_path, after_s):
    # default episodes (20-40 s simulated): still running when the parent dies
    run = _twsb("generate", "--out", str(tmp_path / "data"), "--episodes", "4",
                "--workers", "2", "--quiet")  # fmt: skip
    workers: set[int] = set()
    try:
        deadline = time.monotonic() + 60
        while len(workers) < 2 and time.monotonic() < deadline:
            assert run.poll() is None, "generate ended before its workers started"
            workers = {p for p in _children(run.pid) if _alive(p)}
            time.sleep(0.005)
        assert len(workers) >= 2
        time.sleep(after_s)
        run.send_signal(signal.SIGKILL)  # the main process only, as `kill -9 PID` does
        run.wait()
        deadline = time.monotonic() + 5
        while any(_alive(p) for p in workers) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not any(_alive(p) for p in workers), "a worker outlived its parent"
    finally:
        for pid in workers:
            if _alive(pid):
                os.kill(pid, signal.SIGKILL)
        if run.poll() is None:
            run.kill()
            run.wait()


# creates data sets in new folders one after another, as fast as it can, until killed
_CREATE_FOREVER = textwrap.dedent(
    """
    import sys
    from pathlib import Path
    from twsb_sim.dataset.store import prepare_output
    base = Path(sys.argv[1])
    print("ready", flush=True)
    k = 0
    while True:
        prepare_output(base / f"set_{k:05d}", {"seed": k})
        k += 1
    """
)


def test_a_kill_at_any_moment_of_creating_a_data_set_leaves_it_resumable(tmp_path):
    # each kill lands at a random moment of a creation: a folder, a partial file, a
    # rename; every folder any of them left must be taken up by the next run
    created = 0
    for attempt in range(12):
        base = tmp_path / f"kill_{attempt}"
        writer = subprocess.Popen(
            [sys.executable, "-c", _CREATE_FOREVER, str(base)],
            cwd=REPO,
            stdout=subprocess.PIPE,
            text=True,
        )
        assert writer.stdout.readline().strip() == "ready"
        time.sleep(0.003 * attempt)
        writer.send_signal(signal.SIGKILL)
        writer.wait()
        writer.stdout.close()
        for root in sorted(base.glob("set_*")):  # none when killed before the first
            created += 1
            k = int(root.name.removeprefix("set_"))
            prepare_output(root, {"seed": k})  # raises if the folder is not taken up
            info = json.loads((root / INFO_FILE).read_text())
            assert info == {"settings": {"seed": k}}
            assert not list(root.rglob("*.partial"))
    assert created > 12


@pytest.mark.parametrize(
    "leftover",
    [
        [],
        ["meta/"],
        ["meta/.info.json.partial"],
        ["meta/", "data/chunk-000/"],
        ["data/chunk-000/.episode_000000.parquet.partial"],
    ],
)
def test_what_an_interrupted_creation_leaves_is_taken_up(tmp_path, leftover):
    root = tmp_path / "data"
    root.mkdir()
    for name in leftover:
        path = root / name
        if name.endswith("/"):
            path.mkdir(parents=True, exist_ok=True)
        else:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(b'{"setti')  # cut off mid-write
    prepare_output(root, {"seed": 1})
    assert json.loads((root / INFO_FILE).read_text()) == {"settings": {"seed": 1}}
    assert not list(root.rglob("*.partial"))


@pytest.mark.parametrize("foreign", ["notes.txt", "meta/notes.txt", "photos/", "data/x.parquet"])
def test_a_folder_with_anything_else_is_still_refused(tmp_path, capsys, foreign):
    root = tmp_path / "data"
    path = root / foreign
    if foreign.endswith("/"):
        path.mkdir(parents=True)
    else:
        path.parent.mkdir(parents=True)
        path.write_text("mine")
    assert main(["generate", "--out", str(root), "--episodes", "1", "--quiet"]) == 2
    assert "not a data set" in capsys.readouterr().err
    assert path.exists()


def test_generate_killed_while_creating_its_folder_resumes(tmp_path, short_ranges_file):
    out = tmp_path / "data"
    command = ["generate", "--out", str(out), "--episodes", "1", "--seed", str(SEED),
               "--ranges", str(short_ranges_file), "--workers", "1", "--quiet"]  # fmt: skip
    run = _twsb(*command)
    try:
        deadline = time.monotonic() + 60
        while not out.exists() and time.monotonic() < deadline and run.poll() is None:
            time.sleep(0.0005)
    finally:
        run.send_signal(signal.SIGKILL)
        run.wait()
    assert main(command) == 0
    assert len(shard_bytes(out)) == 1
    assert not list(out.rglob("*.partial"))
