"""Parameter files: a filter's parameters in TOML (or JSON), e.g. from ``twsb tune``.

A file names its filter (any registered name: :mod:`pvfilter.registry`) and holds its
parameters in a table of that name; a ``[tuning]`` table (how the values were found) is
kept for people and ignored by the loader. Nothing else may be in the file:

.. code-block:: toml

    filter = "improved"          # or "paper" (FilterParams, Table I symbols)

    [improved]
    lidar_height_m = 0.25        # m
    free_margin_m = 0.15         # m
    p_th = 0.5                   # 1

    [tuning]
    objective = "auc"

Parameters left out keep their defaults. JSON files (``.json``) have the same structure.
Mistakes raise ``ValueError("<file>: <key>: <what was expected>")``: an empty file, a
missing ``filter``, a table or key that does not belong to the named filter, a bad value.
numpy, scipy and the standard library only: no simulator is needed to read a file.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
from pathlib import Path
from typing import Any

from pvfilter import toml_reader
from pvfilter.registry import entry_for_params, filter_entry, filter_names

NOTES_TABLE = "tuning"  # how the values were found: for people, not for the loader


def read_params_file(path: str | Path) -> dict[str, Any]:
    """The file's tables as plain values (TOML, or JSON for a ``.json`` file)."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text file (a parameter file is TOML or JSON)") from None
    try:
        table = json.loads(text) if path.suffix.lower() == ".json" else toml_reader.loads(text)
    except (json.JSONDecodeError, toml_reader.TomlError) as error:
        raise ValueError(f"{path}: not a valid parameter file: {error}") from None
    if not isinstance(table, dict):
        raise ValueError(f"{path}: not a parameter file (expected a table at the top)")
    return table


def params_from_table(table: dict[str, Any], source: str = "<table>") -> Any:
    """The parameters a file's tables describe (see the module docstring).

    Raises:
        ValueError: ``"<source>: <key>: ..."`` for an unknown filter, key or bad value.
    """
    known = ", ".join(filter_names())
    if not table:
        raise ValueError(f"{source}: empty: a parameter file names its filter (filter = ...)")
    if "filter" not in table:
        raise ValueError(f"{source}: filter: missing (the filter the parameters are for: {known})")
    name = table["filter"]
    try:
        entry = filter_entry(name) if isinstance(name, str) else None
    except ValueError:
        entry = None
    if entry is None:
        raise ValueError(f"{source}: filter: must be one of {known}, got {name!r}")
    for key in table:
        if key not in ("filter", name, NOTES_TABLE):
            raise ValueError(
                f"{source}: {key}: does not belong in a parameter file for filter {name!r} "
                f"(only a [{name}] table of parameters and a [{NOTES_TABLE}] table of notes)"
            )
    kind = entry.params_type
    values = table.get(name, {})
    if kind is None:
        if values:
            raise ValueError(f"{source}: {name}: filter {name!r} takes no parameters")
        return None
    if not isinstance(values, dict):
        raise ValueError(f"{source}: {name}: must be a table of parameters")
    fields = {f.name: f for f in dataclasses.fields(kind)}
    for key, value in values.items():
        if key not in fields:
            raise ValueError(
                f"{source}: {name}.{key}: unknown parameter (known: {', '.join(fields)})"
            )
        expected = type(fields[key].default)
        if expected is int and isinstance(value, float) and value.is_integer():
            values = {**values, key: int(value)}  # JSON writers may give 10.0
        elif expected is float and isinstance(value, int) and not isinstance(value, bool):
            values = {**values, key: float(value)}
    try:
        return kind(**values)
    except (TypeError, ValueError) as error:
        raise ValueError(f"{source}: {name}.{error}") from None


def load_params(path: str | Path) -> Any:
    """Read the parameters of a parameter file (TOML, or JSON for ``.json``).

    Raises:
        ValueError: naming the file and the key, for a file that cannot be used.
        OSError: the file cannot be read.
    """
    return params_from_table(read_params_file(path), source=str(path))


def params_to_toml(params: Any, tuning: dict[str, Any] | None = None) -> str:
    """A parameter file's text for ``params`` (and a ``[tuning]`` table, if given)."""
    name = entry_for_params(params).name
    lines = [f'filter = "{name}"', "", f"[{name}]"]
    for field in dataclasses.fields(params):
        lines.append(f"{field.name} = {_toml_value(getattr(params, field.name))}")
    if tuning:
        lines += ["", "[tuning]"]
        lines += [f"{_toml_key(key)} = {_toml_value(value)}" for key, value in tuning.items()]
    return "\n".join(lines) + "\n"


def save_params(path: str | Path, params: Any, tuning: dict[str, Any] | None = None) -> None:
    """Write a parameter file: TOML, or JSON when ``path`` ends in ``.json``."""
    path = Path(path)
    if path.suffix.lower() == ".json":
        name = entry_for_params(params).name
        table = {"filter": name, name: dataclasses.asdict(params)}
        if tuning:
            table["tuning"] = tuning
        path.write_text(json.dumps(table, indent=1, allow_nan=True) + "\n", encoding="utf-8")
    else:
        path.write_text(params_to_toml(params, tuning), encoding="utf-8")


def _toml_key(key: str) -> str:
    """A bare key when it may be one, else a quoted key."""
    return key if re.fullmatch(r"[A-Za-z0-9_-]+", key) else json.dumps(key)


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)  # a TOML basic string is a JSON string
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        pairs = (f"{_toml_key(k)} = {_toml_value(v)}" for k, v in value.items())
        return "{ " + ", ".join(pairs) + " }"
    raise TypeError(f"cannot write {value!r} to TOML")
