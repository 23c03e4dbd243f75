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

:func:`map_unordered` is the pool itself. ``concurrent.futures.ProcessPoolExecutor``
cannot be stopped safely from Ctrl-C: the interrupt lands inside its locks and queues
(a future's condition lock half-acquired in ``wait``, a worker killed halfway through
sending a shard of a few hundred kB, which its result thread then waits for forever),
and ``shutdown`` hangs. Here each worker has a pipe of its own, the parent reads whole
results only, and stopping is: kill the workers, reap them. Nothing else to wait for.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import multiprocessing
import multiprocessing.connection
import os
import signal
import sys
import threading
import time
import traceback
from collections.abc import Callable, Iterable, Iterator
from typing import Any

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


class WorkerError(RuntimeError):
    """A task raised in a worker, or a worker died; the message holds its traceback."""


def _serve(connection: Any, function: Callable[[Any, Any], Any], common: Any, parent: int):
    """A worker's life: take a task, send back ``("ok", result)`` or ``("error", text)``,
    until the parent sends ``None`` or goes away."""
    init_worker(parent)
    while (item := connection.recv()) is not None:
        try:
            reply = ("ok", function(common, item))
        except Exception:
            reply = ("error", f"{function.__name__}({item!r}) failed:\n{traceback.format_exc()}")
        connection.send(reply)


def _receive(pipe: Any, process: Any) -> tuple[str, Any]:
    """The worker's reply; a worker gone without one is an error."""
    try:
        return pipe.recv()
    except EOFError:
        process.join()
        raise WorkerError(f"a worker died (exit code {process.exitcode})") from None


def map_unordered(
    function: Callable[[Any, Any], Any],
    common: Any,
    items: Iterable[Any],
    workers: int,
    context: multiprocessing.context.BaseContext,
) -> Iterator[Any]:
    """``function(common, item)`` for every item, in ``workers`` processes, yielded as
    they finish (one task in flight per worker).

    However the generator ends (exhausted, closed early, an exception from the caller
    or a Ctrl-C anywhere inside it), its workers are gone when it returns.

    Raises:
        WorkerError: a task raised (its traceback in the message), or a worker died.
    """
    queue = iter(items)
    parent = os.getpid()
    pipes, processes = [], []
    try:
        for _ in range(workers):
            ours, theirs = context.Pipe()
            process = context.Process(
                target=_serve, args=(theirs, function, common, parent), daemon=True
            )
            process.start()
            theirs.close()
            pipes.append(ours)
            processes.append(process)
        busy: dict[Any, Any] = {}  # pipe -> its worker's process, while it has a task
        for pipe, process in zip(pipes, processes, strict=True):
            if (item := next(queue, None)) is not None:
                pipe.send(item)
                busy[pipe] = process
        while busy:
            ready = multiprocessing.connection.wait([*busy, *(p.sentinel for p in busy.values())])
            for pipe in [p for p in busy if p in ready or busy[p].sentinel in ready]:
                status, value = _receive(pipe, busy[pipe])
                if status == "error":
                    raise WorkerError(value)
                yield value
                process = busy.pop(pipe)
                if (item := next(queue, None)) is not None:
                    pipe.send(item)
                    busy[pipe] = process
        for pipe in pipes:
            pipe.send(None)  # done: the workers return
    finally:
        for process in processes:
            if process.is_alive():
                process.kill()
        for process in processes:
            process.join()
        for pipe in pipes:
            pipe.close()
