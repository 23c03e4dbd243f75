"""Writing the output bag under a hidden ``.NAME.partial`` name beside the destination,
renamed when complete, so that an interrupted run leaves no half-written bag."""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


def partial_path(path: Path) -> Path:
    """The hidden name ``path`` is written under until it is complete."""
    return path.with_name(f".{path.name}.partial")


def remove_path(path: Path) -> None:
    """Remove a file or a folder tree, if there is one (what a killed run left)."""
    if path.is_dir() and not path.is_symlink():
        shutil.rmtree(path, ignore_errors=True)
    else:
        path.unlink(missing_ok=True)


@contextmanager
def staged_output(out: Path, replace: bool) -> Iterator[Path]:
    """Where to write the bag ``out``: moved into place when the block completes.

    The path yielded has ``out``'s name (rosbag2 names its files after its folder) inside
    a hidden ``.NAME.partial`` folder beside ``out``. With ``replace``, an existing
    ``out`` is replaced at the end; otherwise it is refused before any work.

    Raises:
        ValueError: ``out`` exists and ``replace`` is False.
    """
    if out.exists() and not replace:
        raise ValueError(f"{out}: exists; give --force to replace it")
    staging = partial_path(out)
    remove_path(staging)  # what a killed run left
    staging.mkdir(parents=True)
    try:
        yield staging / out.name
        if out.exists():
            old = out.with_name(f".{out.name}.old")
            remove_path(old)
            os.replace(out, old)
            os.replace(staging / out.name, out)
            remove_path(old)
        else:
            os.replace(staging / out.name, out)
    finally:
        remove_path(staging)
