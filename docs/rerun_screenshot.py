"""Render a recording in a headless Rerun viewer at a chosen time and save a screenshot.

Needs a Vulkan driver (on Debian: ``apt-get install mesa-vulkan-drivers``). The README's
picture is::

    twsb run hard_stop --rrd runs/hard_stop.rrd
    python docs/rerun_screenshot.py runs/hard_stop.rrd docs/rerun.png --time 3.0
"""

from __future__ import annotations

import argparse
import os
import subprocess
import time
from pathlib import Path

import rerun_cli
from rerun.experimental import ViewerClient


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("rrd", type=Path)
    parser.add_argument("png", type=Path)
    parser.add_argument("--time", type=float, default=3.0, help="sim_time to show (s)")
    parser.add_argument("--size", default="1600x1000", help="window size in points")
    parser.add_argument("--port", type=int, default=9879)
    args = parser.parse_args()
    viewer = subprocess.Popen(
        [str(Path(rerun_cli.__file__).parent / "rerun"), "--headless", "--port", str(args.port),
         "--window-size", args.size],
        env={**os.environ, "CI": "1"},  # no usage data
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )  # fmt: skip
    try:
        client = ViewerClient.connect(f"rerun+http://127.0.0.1:{args.port}/proxy")
        for _ in range(100):  # until the viewer answers
            try:
                client.get_state()
                break
            except ConnectionError:
                time.sleep(0.2)
        client.open(str(args.rrd.resolve()))
        time.sleep(2.0)  # loading
        client.set_time("sim_time", duration=args.time, play_state="paused")
        time.sleep(4.0)  # the software rasterizer draws a few frames
        client.save_screenshot(str(args.png))
    finally:
        viewer.terminate()
        viewer.wait(10)
    try:  # Pillow, when installed, stores the same pixels in about half the bytes
        from PIL import Image

        Image.open(args.png).save(args.png, optimize=True)
    except ImportError:
        pass


if __name__ == "__main__":
    main()
