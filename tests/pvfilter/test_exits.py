"""How the pvfilter commands end: a user mistake, a Ctrl-C, a reader that stopped early."""

import subprocess
import sys
import warnings

import pytest

from pvfilter.exits import EXIT_INTERRUPTED, EXIT_PIPE_CLOSED, EXIT_USAGE, run_command


def raising(error):
    def work():
        raise error

    return work


def test_a_mistake_is_one_line_and_exit_2(capsys):
    assert run_command("pvfilter", raising(ValueError("p_th: must be <= 1"))) == EXIT_USAGE
    assert capsys.readouterr().err == "pvfilter: error: p_th: must be <= 1\n"


def test_a_file_that_cannot_be_opened_is_named_as_a_unix_tool_names_it(capsys):
    missing = FileNotFoundError(2, "No such file or directory", "scans.npz")
    assert run_command("pvfilter", raising(missing)) == EXIT_USAGE
    assert capsys.readouterr().err == "pvfilter: error: scans.npz: No such file or directory\n"


def test_ctrl_c_says_what_it_left(capsys):
    status = run_command("pvfilter", raising(KeyboardInterrupt()), "interrupted: nothing written")
    assert status == EXIT_INTERRUPTED
    assert capsys.readouterr().err == "pvfilter: interrupted: nothing written\n"


def test_a_closed_pipe_is_not_an_error(capsys):
    assert run_command("pvfilter", raising(BrokenPipeError(32, "Broken pipe"))) == EXIT_PIPE_CLOSED
    assert capsys.readouterr().err == ""


def test_output_into_a_reader_that_stops_early_ends_quietly():
    # as `pvfilter eval-labels ... | head -1`: the command keeps printing after the reader left
    program = (
        "import sys\n"
        "from pvfilter.exits import run_command\n"
        "def work():\n"
        "    for i in range(200000):\n"
        "        print('line', i)\n"
        "    return 0\n"
        "sys.exit(run_command('pvfilter', work))\n"
    )
    reader = subprocess.Popen(
        [sys.executable, "-c", program], stdout=subprocess.PIPE, stderr=subprocess.PIPE
    )
    assert reader.stdout.readline() == b"line 0\n"
    reader.stdout.close()  # the reader stops
    stderr = reader.stderr.read()
    assert reader.wait(timeout=60) == EXIT_PIPE_CLOSED
    assert stderr == b""


def test_a_warning_is_one_line_naming_the_command():
    # (in a fresh interpreter: pytest records the warnings of its own tests, not shows them)
    program = (
        "import warnings\n"
        "from pvfilter.exits import run_command\n"
        "def work():\n"
        "    warnings.warn('scan stamp 2.0 s is earlier than the previous 3.0 s')\n"
        "    return 0\n"
        "before = warnings.formatwarning\n"
        "assert run_command('pvfilter', work) == 0\n"
        "assert warnings.formatwarning is before\n"  # restored: later ones as before
    )
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stderr == "pvfilter: warning: scan stamp 2.0 s is earlier than the previous 3.0 s\n"


def test_a_warning_still_reaches_a_recorder_around_the_command():
    def work():
        warnings.warn("stamp went back", stacklevel=1)
        return 0

    with pytest.warns(UserWarning, match="stamp went back"):
        assert run_command("pvfilter", work) == 0
