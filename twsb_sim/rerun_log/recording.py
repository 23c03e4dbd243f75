"""Where a recording goes: the ``--rrd`` file and Rerun's own script flags.

``twsb run SCENARIO --rrd out.rrd`` writes a file with no viewer and no display. Rerun's
``script_add_args`` flags work as in Rerun's examples: ``--save PATH`` (a file, like
``--rrd``), ``--connect [--url URL]`` (stream to a running viewer), ``--serve`` (host a
gRPC server and a web viewer), ``--stdout`` (pipe into ``rerun -``), plus ``--spawn``
(start a viewer and stream to it). Files and streams combine (``--rrd x.rrd --spawn``).
With none of them, nothing is recorded and :func:`rerun_sink` returns a do-nothing sink.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import rerun as rr

from twsb_sim.config_errors import ConfigError
from twsb_sim.output_paths import output_file
from twsb_sim.sinks import FrameSink, NullSink

APPLICATION_ID = "twsb"
VIEWER_PORT = 9876  # Rerun's default gRPC port


def add_recording_args(parser: argparse.ArgumentParser) -> None:
    """Add ``--rrd``, ``--spawn`` and Rerun's ``script_add_args`` flags to a parser."""
    group = parser.add_argument_group(
        "Rerun recording",
        "Record the run for the Rerun viewer. Nothing is recorded without one of these.",
    )
    group.add_argument(
        "--rrd",
        type=Path,
        default=None,
        metavar="PATH",
        help="write the recording to this .rrd file (headless: no viewer, no display)",
    )
    group.add_argument("--spawn", action="store_true", help="start a Rerun viewer and stream to it")
    rr.script_add_args(group)  # --headless --connect --serve --url --save --stdout
    group.add_argument(
        "--state-rate",
        type=float,
        default=0.0,
        metavar="HZ",
        help="also record the robot's state this often between frames, e.g. 50 to catch "
        "wheel-torque spikes (about 10%% more run time); default 0: at the 10 Hz frames",
    )


def wants_recording(args: argparse.Namespace) -> bool:
    """Whether any recording destination was asked for."""
    return bool(
        args.rrd or args.save or args.spawn or args.connect or args.url or args.serve or args.stdout
    )


def _check(args: argparse.Namespace) -> None:
    if args.headless and (args.spawn or args.serve):
        what = "--spawn" if args.spawn else "--serve"
        raise ConfigError("--headless", "", f"contradicts {what}, which opens a viewer")
    if args.stdout and (args.rrd or args.save or args.spawn or args.connect or args.serve):
        raise ConfigError("--stdout", "", "streams the recording alone: drop the other flags")
    if args.state_rate < 0:
        raise ConfigError("--state-rate", "", f"expected a rate >= 0 Hz, got {args.state_rate}")


def open_recording(args: argparse.Namespace) -> rr.RecordingStream | None:
    """A recording stream with the sinks the flags ask for, or None when none is asked for.

    The folders above a recording file are created, as ``--out`` creates its folder.

    Raises:
        ConfigError: contradictory flags, or a recording path that is a folder.
    """
    _check(args)
    if not wants_recording(args):
        return None
    rec = rr.RecordingStream(APPLICATION_ID)
    if args.stdout:
        rec.stdout()
        return rec
    sinks: list[rr.FileSink | rr.GrpcSink | rr.GrpcServerSink] = []
    files = {
        output_file(path, flag, create_parents=True).resolve()  # as --out makes its folder
        for flag, path in (("--rrd", args.rrd), ("--save", args.save))
        if path
    }
    sinks += [rr.FileSink(path) for path in sorted(files)]
    urls = {args.url} if (args.connect or args.url) else set()
    if args.spawn:
        rr.spawn(port=VIEWER_PORT, connect=False)
        urls.add(f"rerun+http://127.0.0.1:{VIEWER_PORT}/proxy")
    sinks += [rr.GrpcSink(url) for url in sorted(urls, key=str)]
    server = rr.GrpcServerSink() if args.serve else None
    if server is not None:
        sinks.append(server)
    try:
        rec.set_sinks(*sinks)
    except RuntimeError as error:  # (Rerun opens the files here: a place none can be made)
        flag = "--rrd" if args.rrd else "--save"
        raise ConfigError(flag, "", f"cannot write the recording: {error}") from None
    if server is not None:
        rr.serve_web_viewer(open_browser=True, connect_to=server.uri)
    return rec


def rerun_sink(args: argparse.Namespace, p_th: float = float("nan")) -> FrameSink:
    """The run's Rerun sink: a :class:`RerunLogger` when the flags ask for a recording,
    else a :class:`NullSink`."""
    rec = open_recording(args)
    if rec is None:
        return NullSink()
    from twsb_sim.rerun_log.logger import RerunLogger  # the logger's imports are heavy

    # the CLI owns the recording: close it with the run, except while serving it
    return RerunLogger(
        rec, state_rate_hz=args.state_rate, p_th=p_th, close_recording=not args.serve
    )


def wait_while_serving() -> None:
    """With ``--serve``, keep the server up for the viewer until Ctrl-C."""
    print("serving the recording to the web viewer; Ctrl-C to stop", file=sys.stderr)
    try:
        while True:
            time.sleep(1.0)
    except KeyboardInterrupt:
        pass
