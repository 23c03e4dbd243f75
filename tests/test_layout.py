"""The code's layering: which package may import which, and no borrowed private names."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("pvfilter", "scaneval", "twsb_sim")


def imports(path: Path) -> list[tuple[str, list[str]]]:
    """(module, names) of every import in a file, at any depth."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module:
            found.append((node.module, [a.name for a in node.names]))
        elif isinstance(node, ast.Import):
            found.extend((a.name, []) for a in node.names)
    return found


def modules(package: str) -> list[Path]:
    return sorted((ROOT / package).rglob("*.py"))


# the optional packages pvfilter may use, and the one module that imports each (inside a
# function or a fallback, never at import time): its extras, not its requirements
# (ruamel.yaml, rosbags' YAML library, writes the bag's metadata.yaml)
OPTIONAL_IN_PVFILTER = {"rosbags": "bag/bagfile.py", "ruamel": "bag/bagfile.py"}
OPTIONAL_IN_PVFILTER |= {"tomli": "toml_reader.py"}


def test_pvfilter_needs_numpy_and_scipy_only():
    allowed = {"numpy", "scipy", "pvfilter"}
    for path in modules("pvfilter"):
        for module, _ in imports(path):
            top = module.split(".")[0]
            if top in OPTIONAL_IN_PVFILTER:
                where = path.relative_to(ROOT / "pvfilter").as_posix()
                assert where == OPTIONAL_IN_PVFILTER[top], f"{where} imports {module}"
                continue
            assert top in allowed or not _third_party(top), f"{path.name} imports {module}"


def test_pvfilter_imports_without_its_optional_packages():
    blocked = "; ".join(f"sys.modules[{name!r}] = None" for name in OPTIONAL_IN_PVFILTER)
    code = (
        f"import sys; {blocked}; import pvfilter, pvfilter.cli, pvfilter.bag.command; "
        "print(sorted(m for m, v in sys.modules.items() "
        "if v and m.split('.')[0] in ('rosbags', 'ruamel', 'tomli')))"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=False
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


def test_the_two_filters_are_siblings_that_do_not_import_each_other():
    for a, b in (("paper", "improved"), ("improved", "paper")):
        for path in sorted((ROOT / "pvfilter" / a).rglob("*.py")):
            for module, _ in imports(path):
                assert not module.startswith(f"pvfilter.{b}"), f"{a}/{path.name} imports {module}"


def test_scaneval_never_imports_the_simulator():
    for path in modules("scaneval"):
        for module, _ in imports(path):
            assert not module.startswith("twsb_sim"), f"{path.name} imports {module}"


def test_no_package_imports_the_command_lines():
    for package in PACKAGES:
        for path in modules(package):
            if path.name in ("cli.py", "__main__.py"):
                continue
            for module, _ in imports(path):
                assert module not in ("twsb_sim.cli", "pvfilter.cli"), f"{path} imports {module}"


def test_no_module_imports_another_module_s_private_names():
    for package in PACKAGES:
        for path in modules(package):
            for module, names in imports(path):
                private = [n for n in names if n.startswith("_") and not n.startswith("__")]
                assert not private, f"{path.relative_to(ROOT)} imports {private} from {module}"


def _third_party(top: str) -> bool:
    return top not in sys.stdlib_module_names
