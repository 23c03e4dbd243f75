"""How the ``pvfilter`` commands end: their exit statuses, and one line instead of a
traceback for what a user can fix (a missing file, a bad value, an optional package not
installed) and for a Ctrl-C."""

from __future__ import annotations

import os
import sys
import warnings
from collections.abc import Callable

EXIT_USAGE = 2
EXIT_INTERRUPTED = 130
EXIT_PIPE_CLOSED = 141  # 128 + SIGPIPE, as a Unix tool killed by a closed pipe ends


def run_command(
    prog: str,
    work: Callable[[], int],
    interrupted: str = "interrupted",
    mistakes: tuple[type[BaseException], ...] = (OSError, ValueError),
) -> int:
    """``work()``'s exit status; a user mistake ends in ``"<prog>: error: <what>"`` and 2,
    a Ctrl-C in ``"<prog>: <interrupted>"`` and 130, both on stderr. Output piped into a
    reader that stopped early (``| head``) ends the command quietly with 141, as a Unix
    tool ends. A warning the work raises (a stamp that went back, a geometry not given)
    is shown as one line too, ``"<prog>: warning: <what>"``, without Python's source path
    and code.

    Args:
        prog: the command's name, as its messages start.
        work: the command's work; returns its exit status.
        interrupted: what a Ctrl-C left behind, in words.
        mistakes: the exceptions that are the user's to fix (their message names what).
    """
    formatted = warnings.formatwarning
    warnings.formatwarning = _one_line_warnings(prog)
    try:
        return work()
    except KeyboardInterrupt:
        print(f"{prog}: {interrupted}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        _silence_stdout()
        return EXIT_PIPE_CLOSED
    except mistakes as error:
        print(f"{prog}: error: {_what(error)}", file=sys.stderr)
        return EXIT_USAGE
    finally:
        warnings.formatwarning = formatted


def _one_line_warnings(prog: str) -> Callable[..., str]:
    """A ``warnings.formatwarning`` giving ``"<prog>: warning: <message>"``. The format,
    not the display (``showwarning``), is replaced: ``pytest.warns``,
    ``catch_warnings(record=True)`` and ``logging.captureWarnings`` around the command
    still receive every warning."""

    def one_line(message, category, filename, lineno, line=None) -> str:
        return f"{prog}: warning: {message}\n"

    return one_line


def _what(error: BaseException) -> str:
    """The mistake in words: a file the system could not open as ``FILE: why`` (as a Unix
    tool says it), not Python's ``[Errno 2] ...``."""
    if isinstance(error, OSError) and error.filename is not None and error.strerror:
        return f"{error.filename}: {error.strerror}"
    return str(error)


def _silence_stdout() -> None:
    """Point stdout at the null device: the reader is gone, and flushing what is left for
    it at exit would raise again."""
    try:
        descriptor = sys.stdout.fileno()
    except (AttributeError, OSError, ValueError):  # not a file (a test's capture)
        return
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, descriptor)
    os.close(null)
