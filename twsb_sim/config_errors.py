"""Configuration overrides from TOML tables, with errors a user can act on.

Every subsystem keeps its parameters in a frozen dataclass with defaults in code
(``RobotConfig``, ``LidarConfig``, ``LqrConfig``, ...). Each dataclass checks its own
values in ``__post_init__`` and raises ``ValueError("field: what was expected, got X")``.
This module applies a TOML table on top of such a dataclass and turns every mistake
(unknown key, wrong type, rejected value) into one :class:`ConfigError` that names the
file, the dotted key and what was expected, so the command line can print it without
a traceback.
"""

from __future__ import annotations

import dataclasses
import functools
import types
import typing
from pathlib import Path
from typing import Any, TypeVar

T = TypeVar("T")


class ConfigError(ValueError):
    """A configuration file holds a key or value we cannot use.

    Attributes:
        source: the file (or other origin) the value came from.
        key: dotted key path, e.g. ``robot.lidar_height_m``.
    """

    def __init__(self, source: str | Path, key: str, message: str) -> None:
        self.source = str(source)
        self.key = key
        super().__init__(f"{self.source}: {key}: {message}" if key else f"{self.source}: {message}")


def _type_name(tp: Any) -> str:
    return getattr(tp, "__name__", str(tp))


def coerce_value(value: Any, tp: Any, source: str | Path, key: str) -> Any:
    """Check ``value`` (parsed from TOML) against the annotation ``tp`` and convert it.

    Ints are accepted where floats are expected (TOML writes ``1`` for ``1.0``);
    bools are never accepted as numbers. Tuples accept TOML arrays.

    Raises:
        ConfigError: naming the key and the expected type.
    """
    origin = typing.get_origin(tp)
    if origin in (typing.Union, types.UnionType):
        options = typing.get_args(tp)
        if value is None and type(None) in options:
            return None
        for option in options:
            if option is type(None):
                continue
            try:
                return coerce_value(value, option, source, key)
            except ConfigError:
                continue  # the next option may take it; if none does, one error names all
        expected = " or ".join(_type_name(o) for o in options if o is not type(None))
        raise ConfigError(source, key, f"expected {expected}, got {value!r}")
    if origin is tuple:
        args = typing.get_args(tp)
        if not isinstance(value, list | tuple):
            raise ConfigError(source, key, f"expected an array, got {value!r}")
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(
                coerce_value(v, args[0], source, f"{key}[{i}]") for i, v in enumerate(value)
            )
        if len(value) != len(args):
            raise ConfigError(
                source, key, f"expected an array of {len(args)} values, got {len(value)}"
            )
        return tuple(
            coerce_value(v, a, source, f"{key}[{i}]")
            for i, (v, a) in enumerate(zip(value, args, strict=True))
        )
    if origin is typing.Literal:
        choices = typing.get_args(tp)
        if value not in choices:
            raise ConfigError(source, key, f"expected one of {list(choices)}, got {value!r}")
        return value
    if tp is float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ConfigError(source, key, f"expected a number, got {value!r}")
        return float(value)
    if tp is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigError(source, key, f"expected an integer, got {value!r}")
        return value
    if tp is bool:
        if not isinstance(value, bool):
            raise ConfigError(source, key, f"expected true or false, got {value!r}")
        return value
    if tp is str:
        if not isinstance(value, str):
            raise ConfigError(source, key, f"expected a string, got {value!r}")
        return value
    raise TypeError(f"unsupported config annotation {tp!r} for {key}")


@functools.cache
def _type_hints(cls: type) -> dict[str, Any]:
    # resolving the annotations evaluates their strings: about 0.2 ms a class, and a
    # scenario applies a few dozen tables
    return typing.get_type_hints(cls)


def apply_overrides(base: T, table: dict[str, Any], source: str | Path, prefix: str) -> T:
    """Return a copy of the frozen dataclass ``base`` with ``table``'s values applied.

    Args:
        base: the dataclass instance holding the defaults.
        table: the parsed TOML table (keys are the dataclass's field names).
        source: where the table came from, for error messages.
        prefix: the table's dotted name, e.g. ``"robot"``.

    Raises:
        ConfigError: for an unknown key, a value of the wrong type, or a value the
            dataclass rejects.
    """
    if not isinstance(table, dict):
        raise ConfigError(source, prefix, f"expected a table, got {table!r}")
    hints = _type_hints(type(base))
    fields = {f.name for f in dataclasses.fields(base) if f.init}
    changes = {}
    for name, value in table.items():
        key = f"{prefix}.{name}" if prefix else name
        if name not in fields:
            known = ", ".join(sorted(fields))
            raise ConfigError(source, key, f"unknown key (known keys: {known})")
        changes[name] = coerce_value(value, hints[name], source, key)
    try:
        return dataclasses.replace(base, **changes)
    except ValueError as error:
        field = str(error).split(":", 1)[0]
        key = f"{prefix}.{field}" if field in fields else prefix
        raise ConfigError(source, key, str(error).split(":", 1)[-1].strip()) from None
