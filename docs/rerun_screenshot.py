"""Render a recording in a headless Rerun viewer at a chosen time and save a screenshot.

Needs a Vulkan driver (on Debian: ``apt-get install mesa-vulkan-drivers``). The README's
picture is::

    twsb run hard_stop --rrd runs/hard_stop.rrd
    python docs/rerun_screenshot.py runs/hard_stop.rrd docs/rerun.png --time 3.0

The viewer takes a few seconds to come up (longer on a busy machine): the script polls
it until it answers, and stops with the viewer's own last words if it exits first.
"""

from __future__ import annotations

import argparse
import os
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

VIEWER_START_TIMEOUT_S = 60.0  # s; the software rasterizer is slow to start on 2 cores
POLL_S = 0.2  # s between two attempts to reach the viewer
LOAD_S = 2.0  # s for the viewer to load the recording
DRAW_S = 4.0  # s for the software rasterizer to draw a few frames


NO_VULKAN_HINT = (
    "rerun_screenshot: the headless viewer needs a Vulkan driver: on Debian or Ubuntu "
    "apt-get install mesa-vulkan-drivers (docs/rerun.md, the screenshot recipe)"
)


class ViewerFailed(RuntimeError):
    """The viewer exited, or did not answer in time."""


def free_port() -> int:
    """A TCP port nobody listens on now (as ``rerun --port auto`` would pick)."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def connect_when_up(
    url: str,
    viewer: subprocess.Popen,
    timeout_s: float = VIEWER_START_TIMEOUT_S,
    connect: Callable[[str], Any] | None = None,
) -> Any:
    """A client of the viewer at ``url``, once it answers.

    Both connecting and the first request fail (``ConnectionError: transport error``)
    until the viewer's server is up, so both are retried.

    Args:
        url: the viewer's proxy URL.
        viewer: the viewer process: if it exits, waiting is over.
        timeout_s: how long to wait (s).
        connect: the function making a client (default ``ViewerClient.connect``).

    Raises:
        ViewerFailed: the viewer exited first, or did not answer within ``timeout_s``.
    """
    if connect is None:
        from rerun.experimental import ViewerClient

        connect = ViewerClient.connect
    deadline = time.monotonic() + timeout_s
    while True:
        if viewer.poll() is not None:
            raise ViewerFailed(f"the viewer exited with status {viewer.returncode} first")
        try:
            client = connect(url)
            client.get_state()
            return client
        except ConnectionError as error:
            if time.monotonic() > deadline:
                raise ViewerFailed(f"no answer from the viewer in {timeout_s:g} s") from error
            time.sleep(POLL_S)


def main() -> int:
    import rerun_cli

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rrd", type=Path)
    parser.add_argument("png", type=Path)
    parser.add_argument("--time", type=float, default=3.0, help="sim_time to show (s)")
    parser.add_argument("--size", default="1600x1000", help="window size in points")
    parser.add_argument("--port", type=int, default=None, help="viewer port (default: a free one)")
    args = parser.parse_args()
    if not args.rrd.is_file():
        parser.error(f"{args.rrd}: no such recording")
    port = args.port or free_port()
    log = tempfile.TemporaryFile()
    viewer = subprocess.Popen(
        [str(Path(rerun_cli.__file__).parent / "rerun"), "--headless", "--port", str(port),
         "--window-size", args.size],
        env={**os.environ, "CI": "1"},  # no usage data
        stdout=log,
        stderr=subprocess.STDOUT,
    )  # fmt: skip
    try:
        client = connect_when_up(f"rerun+http://127.0.0.1:{port}/proxy", viewer)
        client.open(str(args.rrd.resolve()))
        time.sleep(LOAD_S)
        client.set_time("sim_time", duration=args.time, play_state="paused")
        time.sleep(DRAW_S)
        client.save_screenshot(str(args.png))
    except (ViewerFailed, ConnectionError, RuntimeError) as error:
        # (a viewer that dies while answering surfaces as the client's transport error)
        time.sleep(0.5)
        if not isinstance(error, ViewerFailed) and viewer.poll() is not None:
            error = ViewerFailed(f"the viewer exited with status {viewer.returncode}")
        log.seek(0)
        lines = log.read().decode(errors="replace").strip().splitlines()
        # the viewer's own reason (a Rust panic) comes before its backtrace: the last
        # lines alone are frames of the backtrace
        reasons = [line for line in lines if "panicked" in line or "error" in line.lower()][:3]
        print(f"rerun_screenshot: {error}", *(reasons or lines[-5:]), sep="\n  ", file=sys.stderr)
        if any("render context" in line or "Vulkan" in line for line in lines):
            print(NO_VULKAN_HINT, file=sys.stderr)
        return 1
    finally:
        viewer.terminate()
        viewer.wait(10)
        log.close()
    try:  # Pillow, when installed, stores the same pixels in about half the bytes
        from PIL import Image

        Image.open(args.png).save(args.png, optimize=True)
    except ImportError:
        pass
    return 0


if __name__ == "__main__":
    sys.exit(main())
