"""How the ``pvfilter`` commands end: their exit statuses, and one line instead of a
traceback for what a user can fix (a missing file, a bad value, an optional package not
installed) and for a Ctrl-C."""

from __future__ import annotations

import sys
from collections.abc import Callable

EXIT_USAGE = 2
EXIT_INTERRUPTED = 130


def run_command(
    prog: str,
    work: Callable[[], int],
    interrupted: str = "interrupted",
    mistakes: tuple[type[BaseException], ...] = (OSError, ValueError),
) -> int:
    """``work()``'s exit status; a user mistake ends in ``"<prog>: error: <what>"`` and 2,
    a Ctrl-C in ``"<prog>: <interrupted>"`` and 130, both on stderr.

    Args:
        prog: the command's name, as its messages start.
        work: the command's work; returns its exit status.
        interrupted: what a Ctrl-C left behind, in words.
        mistakes: the exceptions that are the user's to fix (their message names what).
    """
    try:
        return work()
    except KeyboardInterrupt:
        print(f"{prog}: {interrupted}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except mistakes as error:
        print(f"{prog}: error: {error}", file=sys.stderr)
        return EXIT_USAGE
