"""A Ctrl-C or SIGTERM stops a command, wherever in the program the signal lands.

Python raises ``KeyboardInterrupt`` (and the ``twsb`` command raises :class:`Terminated`
for SIGTERM) in whatever Python code runs when the signal arrives. When that code is a
finalizer (an object's ``__del__``, a weak-reference callback, a generator closed by the
garbage collector), Python prints "Exception ignored" and carries on: the command would
run to the end and exit 0 as if it had never been stopped. So the stop is also recorded
here, where it cannot be lost: :func:`stopping` records every stop, silences the ignored
one, and :func:`raise_if_stopped` raises it again at the points that commit outputs
(:mod:`twsb_sim.staging`) and when the command returns.

A stop that lands in an object's ``__init__`` leaves it half built, and its finalizer
fails later for an attribute it never set (numba's compiler objects, when the stop lands
while a kernel compiles), often as the command exits. After a stop such a failure is
not reported: the command has said it stopped (:func:`stopping`).

A stop can also land in code that wraps what it raises: a compiled (numba) function's
dispatcher runs Python while it loads, and turns an exception raised there into a
``SystemError``. An error whose chain of causes holds a stop is that stop.
"""

from __future__ import annotations

import signal
import sys
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from types import FrameType


class Terminated(KeyboardInterrupt):
    """SIGTERM, turned into the same clean stop as a Ctrl-C."""


_stop: KeyboardInterrupt | None = None  # the stop received during :func:`stopping`


def _on_sigterm(signum: int, frame: FrameType | None) -> None:
    global _stop
    _stop = Terminated()
    raise _stop


def _on_unraisable(unraisable: sys.UnraisableHookArgs, previous: Callable[..., object]) -> None:
    """Record a stop that landed in a finalizer (where Python ignores it) instead of
    printing it; anything else goes to the hook that was there before."""
    global _stop
    if isinstance(unraisable.exc_value, KeyboardInterrupt):
        _stop = _stop or unraisable.exc_value
    else:
        previous(unraisable)


def _after_stop(unraisable: sys.UnraisableHookArgs, previous: Callable[..., object]) -> None:
    """After a stop: a finalizer that fails for a missing attribute belongs to an object
    whose ``__init__`` the stop cut short, and is not reported; anything else goes to the
    hook that was there before."""
    if not isinstance(unraisable.exc_value, AttributeError):
        previous(unraisable)


def stop_within(error: BaseException) -> KeyboardInterrupt | None:
    """The Ctrl-C or SIGTERM in ``error``'s chain of causes and contexts, if any."""
    seen: set[int] = set()
    while error is not None and id(error) not in seen:
        if isinstance(error, KeyboardInterrupt):
            return error
        seen.add(id(error))
        error = error.__cause__ or error.__context__
    return None


def print_stop(message: str) -> None:
    """Print ``message`` (what stopped, what was kept) on stderr, on a line of its own.

    A progress bar draws its line without a newline and ends it when it closes. A stop
    that lands while a bar draws its first line leaves it open (its ``__init__`` never
    returned, so no ``with`` block closes it), and so does a stop while a bar updated by
    hand is open: the cursor is then at the end of the bar's text. Such bars on stderr are
    closed first: a bar that was drawn ends its line (and will not be drawn again when it
    is collected, after the message), one that never finished its first line gets a
    newline.
    """
    from tqdm import tqdm

    with tqdm.get_lock():
        bars = [bar for bar in list(getattr(tqdm, "_instances", ())) if _on_stderr(bar)]
    half_drawn = False
    for bar in bars:
        if getattr(bar, "disable", True):
            continue
        half_drawn |= not hasattr(bar, "last_print_t")  # its __init__ never returned
        bar.close()
    if half_drawn:
        sys.stderr.write("\n")
    print(message, file=sys.stderr)


def _on_stderr(bar: object) -> bool:
    """Whether a progress bar writes to this process's stderr (tqdm wraps its stream)."""
    stream = getattr(bar, "fp", None)
    stream = getattr(stream, "_wrapped", stream)
    return stream is sys.stderr or stream is sys.__stderr__


def raise_if_stopped() -> None:
    """Raise the Ctrl-C or SIGTERM received (and perhaps swallowed) so far, if any."""
    if _stop is not None:
        raise _stop


@contextmanager
def stopping() -> Iterator[None]:
    """Within the block, SIGTERM raises :class:`Terminated` and no stop is lost.

    Outside the main thread (where Python cannot install signal handlers: a command run
    from a test's thread) only the record of swallowed stops is kept.
    """
    global _stop
    _stop = None
    in_main_thread = threading.current_thread() is threading.main_thread()
    previous_handler = signal.signal(signal.SIGTERM, _on_sigterm) if in_main_thread else None
    previous_hook = sys.unraisablehook
    sys.unraisablehook = lambda unraisable: _on_unraisable(unraisable, previous_hook)
    stopped = False
    try:
        yield
        raise_if_stopped()
    except KeyboardInterrupt:
        stopped = True
        raise
    except Exception as error:
        stop = stop_within(error) or _stop
        if stop is None:
            raise
        stopped = True
        raise stop from error
    finally:
        # (after a stop the command winds down: half-built objects fail as they go, some
        # at the interpreter's exit, when module globals may be gone: bound here)
        sys.unraisablehook = (
            (lambda unraisable, after=_after_stop, before=previous_hook: after(unraisable, before))
            if stopped
            else previous_hook
        )
        if previous_handler is not None:
            signal.signal(signal.SIGTERM, previous_handler)
        _stop = None
