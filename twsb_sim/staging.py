"""Outputs that appear whole or not at all, whenever a command is interrupted or killed.

A report folder (``twsb eval``, ``twsb slam``) or a parameter file (``twsb tune``) is
written under a hidden ``.NAME.partial`` name beside its destination and moved into place
once complete. An interrupt (Ctrl-C, SIGTERM, an error) removes the partial output; a
kill (``kill -9``, a power cut) can leave it behind, and the next run of the same
command removes it before it starts. Either way the destination holds the previous
complete output, or the new one, never a half-written file.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

from pvfilter.bag.staging import partial_path, remove_path
from twsb_sim.stopping import raise_if_stopped


@contextmanager
def staged_folder(out: Path) -> Iterator[Path]:
    """A folder to write into instead of ``out``; its files move into ``out`` at the end.

    Each file replaces its namesake in ``out`` atomically; files of ``out`` that the new
    output does not have are kept.

    Yields:
        The staging folder (empty).
    """
    staging = partial_path(out)
    remove_path(staging)  # what a killed run left
    staging.mkdir(parents=True)
    try:
        yield staging
        raise_if_stopped()  # a stop that landed where Python ignored it
        out.mkdir(parents=True, exist_ok=True)
        for path in sorted(staging.rglob("*")):
            target = out / path.relative_to(staging)
            if path.is_dir():
                target.mkdir(parents=True, exist_ok=True)
            else:
                os.replace(path, target)
    finally:
        remove_path(staging)


@contextmanager
def staged_new_folder(out: Path) -> Iterator[Path]:
    """Where to create the new folder ``out`` (which must not exist): it is renamed to
    ``out`` when complete. The path yielded has ``out``'s name, for writers that name
    their files after their folder (rosbag2).

    Yields:
        A path that does not exist yet, inside a hidden staging folder.
    """
    staging = partial_path(out)
    remove_path(staging)
    staging.mkdir(parents=True)
    try:
        yield staging / out.name
        raise_if_stopped()
        os.replace(staging / out.name, out)
    finally:
        remove_path(staging)


@contextmanager
def staged_file(path: Path) -> Iterator[Path]:
    """Where to write the file ``path``: renamed to ``path`` once the block completes.

    The temporary name keeps ``path``'s suffix, for writers that choose the format by it.

    Yields:
        The temporary path (absent).
    """
    temporary = path.with_name(f".{path.stem}.partial{path.suffix}")
    remove_path(temporary)
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        yield temporary
        raise_if_stopped()
        os.replace(temporary, path)
    finally:
        remove_path(temporary)
