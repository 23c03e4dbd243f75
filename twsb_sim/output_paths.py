"""Checks of the output paths a command is given, before it spends any time simulating.

Every ``twsb`` command that writes something takes its destination from a flag
(``--out``, ``--rrd``, ...). A folder flag pointing at an existing file, a file flag
pointing at a folder, or a path running through a file would otherwise fail with an
``OSError`` traceback after minutes of work. These checks fail first, in one line naming
the flag and the path.
"""

from __future__ import annotations

from pathlib import Path

from twsb_sim.config_errors import ConfigError


def _check_parents(path: Path, flag: str) -> None:
    for parent in path.absolute().parents:
        if parent.exists():
            if not parent.is_dir():
                raise ConfigError(flag, "", f"{path}: {parent} is a file, not a folder")
            return


def output_folder(path: str | Path, flag: str = "--out") -> Path:
    """``path`` as a folder to write into: absent (it is created later) or a folder.

    Raises:
        ConfigError: ``path`` is an existing file, or lies under one.
    """
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise ConfigError(flag, "", f"{path} is a file; give a folder (new or existing)")
    _check_parents(path, flag)
    return path


def output_file(path: str | Path, flag: str = "--out", create_parents: bool = False) -> Path:
    """``path`` as a file to write: absent or a file, never a folder.

    Args:
        path: the file.
        flag: the flag that gave it, for the message.
        create_parents: create the missing folders above it now (as ``--out`` does for
            its folder), so that writers that expect them find them.

    Raises:
        ConfigError: ``path`` is an existing folder, or lies under a file.
    """
    path = Path(path)
    if path.is_dir():
        raise ConfigError(flag, "", f"{path} is a folder; give a file name")
    _check_parents(path, flag)
    if create_parents:
        path.parent.mkdir(parents=True, exist_ok=True)
    return path
