"""Worker processes that never outlive the ``twsb generate`` process that started them.

A process pool's workers wait on a pipe for their next task. When the parent is killed
outright (``kill -9``, the out-of-memory killer), nobody closes that pipe's other end
for them in time, and they wait forever, a few hundred MB each. Two guards, run in each
worker as the pool's initializer:

- on Linux, the kernel sends the worker SIGKILL the moment its parent dies
  (``prctl(PR_SET_PDEATHSIG)``); a worker whose parent died before the call sees a new
  parent pid and exits at once;
- elsewhere, a daemon thread polls the parent pid and exits the worker when it changes.

The workers also ignore SIGINT: a Ctrl-C in a terminal reaches every process of the
foreground group, and the parent alone decides what happens (it stops the pool and
keeps the finished episodes), without a traceback per worker.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import signal
import sys
import threading
import time

PR_SET_PDEATHSIG = 1  # from <linux/prctl.h>
PARENT_POLL_S = 0.5  # s, how often the portable guard looks at the parent pid


def _set_parent_death_signal() -> bool:
    """Ask Linux to SIGKILL this process when its parent dies; False where unavailable."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        return libc.prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def _watch_parent(parent_pid: int) -> None:
    while os.getppid() == parent_pid:
        time.sleep(PARENT_POLL_S)
    os._exit(1)


def init_worker(parent_pid: int) -> None:
    """Pool initializer: tie this worker's life to ``parent_pid`` and leave Ctrl-C to it.

    Args:
        parent_pid: the pid of the process that created the pool.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if not _set_parent_death_signal():
        threading.Thread(target=_watch_parent, args=(parent_pid,), daemon=True).start()
    if os.getppid() != parent_pid:  # the parent died before the guard was in place
        os._exit(1)
