"""The robot distribution (``packages/pvfilter``) installs alone: numpy and scipy, nothing else.

Slow on purpose: it makes a fresh virtual environment and pip-installs the distribution
from a copy of the repository's files, dependencies from the package index, as a robot
would (about 20 s with the index's wheels cached). It then runs ``pvfilter --help`` and a
filter pass there.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import venv
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
# what pip, numpy and scipy bring into a fresh environment besides the distribution
ALLOWED = {"pvfilter", "numpy", "scipy", "pip", "setuptools", "wheel"}
ALLOWED |= {"tomli"} if sys.version_info < (3, 11) else set()


def _run(*argv: str | Path, cwd: Path) -> str:
    done = subprocess.run(
        [str(a) for a in argv], cwd=cwd, capture_output=True, text=True, check=False,
        env={k: v for k, v in os.environ.items() if k != "PYTHONPATH"},
    )  # fmt: skip
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return done.stdout


@pytest.mark.install
def test_pvfilter_installs_alone_and_filters(tmp_path):
    source = tmp_path / "src"  # a copy: pip builds in the source tree, not in the checkout
    shutil.copytree(
        ROOT / "packages" / "pvfilter",
        source,
        ignore=shutil.ignore_patterns("build", "*.egg-info", "__pycache__"),
    )
    environment = tmp_path / "env"
    venv.create(environment, with_pip=True)
    python = environment / "bin" / "python"
    _run(
        python,
        "-m",
        "pip",
        "install",
        "--quiet",
        "--disable-pip-version-check",
        source,
        cwd=tmp_path,
    )

    listed = json.loads(_run(python, "-m", "pip", "list", "--format", "json", cwd=tmp_path))
    installed = {row["name"].lower() for row in listed}
    assert installed - ALLOWED == set() and {"pvfilter", "numpy", "scipy"} <= installed
    requires = _run(
        python, "-c", "import importlib.metadata as m; print(m.requires('pvfilter'))", cwd=tmp_path
    )
    assert "rosbags" in requires and 'extra == "bag"' in requires  # an extra, not a need

    assert "pvfilter bag" in _run(environment / "bin" / "pvfilter", "--help", cwd=tmp_path)
    listing = _run(environment / "bin" / "pvfilter", "--list", cwd=tmp_path)
    assert {line.split()[0] for line in listing.splitlines()} == {"improved", "none", "paper"}
    code = (
        "import numpy as np, sys\n"
        "from pvfilter.io import arrays_from_scans\n"
        "from pvfilter.synthetic import room_sequence\n"
        "scans = room_sequence(40, seed=1).scans\n"
        "np.savez('scans.npz', **arrays_from_scans(scans))\n"
    )
    _run(python, "-c", code, cwd=tmp_path)
    out = _run(environment / "bin" / "pvfilter", "scans.npz", "out.npz", "--improved", cwd=tmp_path)
    assert "improved filter, 40 scans" in out and (tmp_path / "out.npz").exists()
    bag = subprocess.run(
        [environment / "bin" / "pvfilter", "bag", "in", "out"], cwd=tmp_path, capture_output=True,
        text=True, check=False,
    )  # fmt: skip
    assert bag.returncode == 2 and 'pip install "pvfilter[bag]"' in bag.stderr
