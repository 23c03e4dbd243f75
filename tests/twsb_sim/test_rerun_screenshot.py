"""docs/rerun_screenshot.py waits for the headless viewer instead of failing to connect."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SCRIPT = REPO / "docs" / "rerun_screenshot.py"
VULKAN_ICDS = Path("/usr/share/vulkan/icd.d")


def _load_script():
    spec = importlib.util.spec_from_file_location("rerun_screenshot", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


class FakeClient:
    def get_state(self) -> dict:
        return {}


def test_connecting_is_retried_until_the_viewer_answers(monkeypatch):
    script = _load_script()
    monkeypatch.setattr(script, "POLL_S", 0.001)
    attempts = []

    def connect(url: str) -> FakeClient:
        attempts.append(url)
        if len(attempts) < 5:  # the server is not up yet: connect itself fails
            raise ConnectionError("transport error")
        return FakeClient()

    viewer = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(30)"])
    try:
        client = script.connect_when_up("rerun+http://x/proxy", viewer, 5.0, connect)
    finally:
        viewer.kill()
        viewer.wait()
    assert isinstance(client, FakeClient) and len(attempts) == 5


def test_a_viewer_that_exits_first_is_reported_not_waited_for(monkeypatch):
    script = _load_script()
    monkeypatch.setattr(script, "POLL_S", 0.001)
    viewer = subprocess.Popen([sys.executable, "-c", "raise SystemExit(3)"])
    viewer.wait()

    def refuse(url: str) -> FakeClient:
        raise ConnectionError("transport error")

    with pytest.raises(script.ViewerFailed, match="exited with status 3"):
        script.connect_when_up("rerun+http://x/proxy", viewer, 60.0, refuse)


@pytest.mark.skipif(
    not list(VULKAN_ICDS.glob("*.json")) if VULKAN_ICDS.is_dir() else True,
    reason="needs a Vulkan driver (apt-get install mesa-vulkan-drivers)",
)
def test_the_script_saves_a_screenshot_of_a_recording(tmp_path):
    from twsb_sim.cli import main

    scenario = tmp_path / "tiny.toml"
    scenario.write_text("duration_s = 1.0\n")
    rrd, png = tmp_path / "runs" / "tiny.rrd", tmp_path / "shot.png"
    assert main(["run", str(scenario), "--quiet", "--rrd", str(rrd)]) == 0
    done = subprocess.run(
        [sys.executable, str(SCRIPT), str(rrd), str(png), "--time", "0.5", "--size", "640x400"],
        capture_output=True,
        text=True,
        timeout=180,
    )
    assert done.returncode == 0, done.stderr
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
