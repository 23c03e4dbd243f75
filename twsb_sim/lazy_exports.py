"""Package exports that load on first use.

Subpackages with heavy imports (matplotlib, pyarrow, rerun, MuJoCo) list their public
names and the module holding each; ``from twsb_sim.evaluation import run_evaluation``
then works as usual, while the ``twsb`` command line, which only registers their
subcommands, starts without importing them.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from typing import Any


def lazy_exports(package: str, homes: dict[str, str]) -> tuple[Callable[[str], Any], list[str]]:
    """A module ``__getattr__`` and ``__all__`` for ``package``.

    Args:
        package: the package's ``__name__``.
        homes: public name -> submodule (relative to the package) that defines it; a
            name mapped to itself that its module does not define is the submodule.

    Usage, in a package's ``__init__``: ``__getattr__, __all__ = lazy_exports(__name__, HOMES)``.
    """

    def __getattr__(name: str) -> Any:
        if name not in homes:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module = importlib.import_module(f"{package}.{homes[name]}")
        if homes[name] == name and not hasattr(module, name):
            return module
        return getattr(module, name)

    return __getattr__, sorted(homes)
