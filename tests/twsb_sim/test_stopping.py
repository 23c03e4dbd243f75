"""A stop that lands in a finalizer, where Python ignores exceptions, is not lost."""

from __future__ import annotations

import gc
import io
import sys

import pytest

from twsb_sim.staging import staged_file
from twsb_sim.stopping import Terminated, print_stop, raise_if_stopped, stopping


class _StoppedWhileCollected:
    """An object whose finalizer is where the signal lands."""

    def __init__(self, stop: KeyboardInterrupt) -> None:
        self.stop = stop

    def __del__(self) -> None:
        raise self.stop


def _collect_one(stop: KeyboardInterrupt) -> None:
    _StoppedWhileCollected(stop)  # dropped at once: its __del__ raises, Python ignores it
    gc.collect()


@pytest.mark.parametrize("stop", [KeyboardInterrupt(), Terminated()])
def test_a_stop_swallowed_by_a_finalizer_is_raised_when_the_block_ends(stop, capsys):
    reached_the_end = False
    with pytest.raises(type(stop)), stopping():
        _collect_one(stop)
        reached_the_end = True  # Python carried on, as it does
    assert reached_the_end
    assert "Exception ignored" not in capsys.readouterr().err  # recorded, not printed


def test_no_output_is_committed_after_a_swallowed_stop(tmp_path):
    path = tmp_path / "params.toml"
    with pytest.raises(KeyboardInterrupt), stopping(), staged_file(path) as temporary:
        temporary.write_text("x = 1\n")
        _collect_one(KeyboardInterrupt())
    assert not path.exists() and not list(tmp_path.iterdir())


def test_other_ignored_exceptions_still_reach_the_previous_hook(monkeypatch):
    seen = []
    monkeypatch.setattr(sys, "unraisablehook", lambda unraisable: seen.append(unraisable))
    with stopping():
        _collect_one(ValueError("not a stop"))  # type: ignore[arg-type]
    assert [type(u.exc_value) for u in seen] == [ValueError]


def test_a_finalizer_that_a_stop_left_half_built_is_not_reported_after_it(monkeypatch):
    # the stop landed in an object's __init__ (numba compiling a kernel): as the command
    # exits, its finalizer fails for an attribute it never set; other failures still show
    seen = []
    monkeypatch.setattr(sys, "unraisablehook", lambda unraisable: seen.append(unraisable))
    with pytest.raises(Terminated), stopping():
        raise Terminated()
    _collect_one(AttributeError("'OutputString' object has no attribute '_ptr'"))  # type: ignore[arg-type]
    _collect_one(ValueError("not a half-built object"))  # type: ignore[arg-type]
    assert [type(u.exc_value) for u in seen] == [ValueError]


def test_nothing_is_raised_outside_a_block_or_after_it():
    raise_if_stopped()  # no block: nothing recorded
    with pytest.raises(KeyboardInterrupt), stopping():
        _collect_one(KeyboardInterrupt())
    raise_if_stopped()  # the stop belonged to the block that ended


def _wrapped_stop(stop: KeyboardInterrupt) -> None:
    """Raise ``stop`` where a compiled function's dispatcher turns it into a SystemError."""
    try:
        raise stop
    except KeyboardInterrupt as error:
        raise SystemError("returned a result with an exception set") from error


@pytest.mark.parametrize("stop", [KeyboardInterrupt(), Terminated()])
def test_a_stop_wrapped_in_another_error_is_still_the_stop(stop):
    with pytest.raises(type(stop)), stopping():
        _wrapped_stop(stop)


def test_an_error_with_no_stop_in_it_stays_that_error():
    with pytest.raises(SystemError), stopping():
        raise SystemError("a real one")


def _stop_message_lines(capsys) -> list[str]:
    return capsys.readouterr().err.replace("\r", "\n").splitlines()


def test_the_stop_message_never_trails_a_progress_bar_left_open(capsys):
    from tqdm import tqdm

    # drawn and never closed, as a bar updated by hand outside a with block is left
    bar = tqdm(total=3, desc="SLAM runs", file=sys.stderr)
    print_stop("twsb: interrupted")
    del bar
    gc.collect()  # nor is the bar drawn again after the message when it is collected
    assert _stop_message_lines(capsys)[-1] == "twsb: interrupted"


def test_the_stop_message_never_trails_a_bar_stopped_in_its_first_line(capsys):
    from tqdm import tqdm

    # a stop that lands while a bar draws its first line: its text is out, its
    # __init__ never returned (closing it then draws nothing)
    bar = tqdm(total=3, desc="SLAM runs", file=sys.stderr)
    del bar.last_print_t
    print_stop("twsb: interrupted")
    assert _stop_message_lines(capsys)[-1] == "twsb: interrupted"
    assert bar.disable  # closed: not drawn again when collected


def test_the_stop_message_adds_no_blank_line_after_closed_bars_or_on_other_streams(capsys):
    from tqdm import tqdm

    with tqdm(total=3, desc="SLAM runs", file=sys.stderr):
        pass
    elsewhere = tqdm(total=3, desc="elsewhere", file=io.StringIO())  # open, not on stderr
    capsys.readouterr()
    print_stop("twsb: interrupted")
    assert capsys.readouterr().err == "twsb: interrupted\n"
    assert not elsewhere.disable
    elsewhere.close()
