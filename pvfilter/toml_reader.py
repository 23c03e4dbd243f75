"""TOML reading on every Python this package supports, with one error when it cannot.

Python 3.11 and later read TOML with the standard library's ``tomllib``. On 3.10 (ROS 2
Humble's Python) the same parser is the ``tomli`` package, which the robot distribution
declares for Python < 3.11 only; without it, TOML parameter files raise a ``ValueError``
that says what to install (JSON parameter files need nothing).
"""

from __future__ import annotations

import json
from types import ModuleType
from typing import Any

_parser: ModuleType | None
try:
    import tomllib as _parser
except ModuleNotFoundError:  # Python 3.10
    try:
        import tomli as _parser
    except ModuleNotFoundError:
        _parser = None

INSTALL_HINT = "reading TOML on Python 3.10 needs tomli: pip install tomli (or use JSON)"


class TomlError(ValueError):
    """Text that is not valid TOML."""


def loads(text: str) -> dict[str, Any]:
    """The tables of a TOML document.

    Raises:
        TomlError: the text is not valid TOML.
        ValueError: no TOML parser is installed (Python 3.10 without tomli).
    """
    if _parser is None:
        raise ValueError(INSTALL_HINT)
    try:
        return _parser.loads(text)
    except _parser.TOMLDecodeError as error:
        raise TomlError(str(error)) from None


def value(text: str) -> Any:
    """A value as ``--set NAME=VALUE`` gives it: TOML (``0.5``, ``true``, ``"radius"``,
    ``[1, 2]``), or a bare word, which is a string.

    Without a TOML parser (Python 3.10 without tomli) numbers, booleans, quoted and bare
    words still read the same; arrays and tables need the parser.
    """
    text = text.strip()
    if _parser is not None:
        try:
            return _parser.loads(f"v = {text}")["v"]
        except _parser.TOMLDecodeError:
            return text
    if text in ("true", "false"):
        return text == "true"
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    if text[:1] in "[{":
        raise ValueError(f"{text}: {INSTALL_HINT}")
    return json.loads(text) if len(text) > 1 and text[0] == text[-1] == '"' else text
