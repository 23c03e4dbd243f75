"""Every filter by name: one registry that every command, evaluation and the Gym env use.

The filters of this package are registered here (``paper``, ``improved`` and ``none``,
the pass-through); other packages register theirs through the ``pvfilter.filters``
entry-point group (the evaluation baselines of ``scaneval``: ``datmo``, ``imu_gate``),
and a user registers a filter class from Python::

    from pvfilter import FilterEntry, register_filter

    register_filter(FilterEntry("mine", MyFilter, MyParams, "my own filter"))

after which ``make_filter("mine")``, parameter files (``filter = "mine"``) and every
command that takes ``--filter NAME`` know it.
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Callable, Mapping
from importlib import metadata
from typing import Any

from pvfilter.contract import ScanFilter
from pvfilter.improved import ImprovedParams, ImprovedPitchVariationFilter
from pvfilter.paper import FilterParams, PitchVariationFilter
from pvfilter.pass_through import NoFilter

ENTRY_POINT_GROUP = "pvfilter.filters"
# robot geometry a filter's parameters may hold under these names (m); callers that know
# the robot (the simulator, a robot's launch file) set them with ``robot_geometry``
ROBOT_GEOMETRY_FIELDS: tuple[str, ...] = ("lidar_height_m", "axle_height_m", "lidar_ahead_m")


@dataclasses.dataclass(frozen=True)
class FilterEntry:
    """A filter as the registry knows it.

    Attributes:
        name: the name commands and parameter files use (``--filter NAME``).
        factory: builds the filter; called with its parameters (an instance of
            ``params_type``), or with no argument when ``params_type`` is None.
        params_type: the frozen dataclass of its parameters (their defaults when none are
            given), or None for a filter without parameters.
        summary: one line for listings.
        needs: the keyword robot inputs it cannot run without (see
            :mod:`pvfilter.contract`): callers always give them.
        accepts: the robot inputs it can use besides; callers give them when asked to
            (the filter works without them).
        threshold: the parameter a precision-recall sweep varies, or None.
        one_pass: the filter's state does not depend on ``threshold``, and it removes a
            beam exactly when its score exceeds it: one pass gives every threshold.
    """

    name: str
    factory: Callable[..., ScanFilter]
    params_type: type | None = None
    summary: str = ""
    needs: tuple[str, ...] = ()
    accepts: tuple[str, ...] = ()
    threshold: str | None = None
    one_pass: bool = False

    def default_params(self) -> Any:
        """The parameters with their defaults (None for a filter without parameters)."""
        return self.params_type() if self.params_type is not None else None

    def make(
        self,
        params: Any = None,
        *,
        robot_geometry: Mapping[str, float] | None = None,
        **fields: Any,
    ) -> ScanFilter:
        """A new filter of this kind.

        Args:
            params: its parameters (defaults when None).
            robot_geometry: values of :data:`ROBOT_GEOMETRY_FIELDS` that the parameters
                take where they have such a field (a filter without one ignores it; a
                key that is none of them is an error: a misspelled height would pass
                silently, and a wrong height costs the improved filter dearly).
            **fields: parameter values that replace those of ``params``.

        Raises:
            ValueError: parameters of another filter, an unknown or invalid field, or a
                ``robot_geometry`` key that is no geometry field.
        """
        strange = sorted(set(robot_geometry or {}) - set(ROBOT_GEOMETRY_FIELDS))
        if strange:
            known = ", ".join(ROBOT_GEOMETRY_FIELDS)
            raise ValueError(f"robot_geometry: unknown key {strange[0]!r} (known: {known})")
        if self.params_type is None:
            if params is not None or fields:
                raise ValueError(f"{self.name}: takes no parameters")
            return self.factory()
        params = self.default_params() if params is None else params
        if not isinstance(params, self.params_type):
            raise ValueError(
                f"{self.name}: expects {self.params_type.__name__}, got {type(params).__name__}"
            )
        names = {f.name for f in dataclasses.fields(params)}
        geometry = {k: v for k, v in (robot_geometry or {}).items() if k in names}
        unknown = sorted(set(fields) - names)
        if unknown:
            known = ", ".join(sorted(names))
            raise ValueError(f"{self.name}: unknown parameter {unknown[0]!r} (known: {known})")
        if geometry or fields:
            params = dataclasses.replace(params, **geometry, **fields)
        return self.factory(params)


_BUILT_IN = (
    FilterEntry(
        "improved",
        ImprovedPitchVariationFilter,
        ImprovedParams,
        "the improved filter: free-space evidence and tilted-plane geometry",
        accepts=("pitch_rad", "roll_rad", "pose_sensor_in_odom"),
        threshold="p_th",
        one_pass=True,
    ),
    FilterEntry(
        "paper",
        PitchVariationFilter,
        FilterParams,
        "the paper's Pitch Variation Filter, Table I defaults",
        threshold="p_th",
    ),
    FilterEntry("none", NoFilter, None, "removes nothing (the reference)"),
)
_entries: dict[str, FilterEntry] = {entry.name: entry for entry in _BUILT_IN}
_plugins_loaded = False


def register_filter(entry: FilterEntry, *, replace: bool = False) -> FilterEntry:
    """Make a filter known by its name everywhere.

    Raises:
        ValueError: the name is taken (unless ``replace``) or not a plain word.
    """
    _load_plugins()
    if not entry.name or not entry.name.replace("_", "").replace("-", "").isalnum():
        raise ValueError(f"name: must be a word of letters, digits, _ and -, got {entry.name!r}")
    if entry.name in _entries and not replace:
        raise ValueError(f"name: a filter named {entry.name!r} is already registered")
    _entries[entry.name] = entry
    return entry


def unregister_filter(name: str) -> None:
    """Forget a registered filter (for tests and interactive use)."""
    _load_plugins()
    _entries.pop(name, None)


def filter_names() -> tuple[str, ...]:
    """The names of every registered filter, sorted."""
    _load_plugins()
    return tuple(sorted(_entries))


def filter_entry(name: str) -> FilterEntry:
    """The registry's entry for ``name``.

    Raises:
        ValueError: ``"filter: unknown filter 'x' (known: ...)"``.
    """
    _load_plugins()
    if name not in _entries:
        raise ValueError(f"filter: unknown filter {name!r} (known: {', '.join(filter_names())})")
    return _entries[name]


def make_filter(
    name: str,
    params: Any = None,
    *,
    robot_geometry: Mapping[str, float] | None = None,
    **fields: Any,
) -> ScanFilter:
    """A new filter by name (see :meth:`FilterEntry.make`)."""
    return filter_entry(name).make(params, robot_geometry=robot_geometry, **fields)


def entry_for_params(params: Any) -> FilterEntry:
    """The entry whose parameters ``params`` are.

    Raises:
        ValueError: no registered filter takes parameters of that type.
    """
    _load_plugins()
    for entry in _entries.values():
        if entry.params_type is not None and type(params) is entry.params_type:
            return entry
    raise ValueError(f"no registered filter takes {type(params).__name__}")


def filter_for(params: Any) -> ScanFilter:
    """A new filter of the kind ``params`` are for."""
    return entry_for_params(params).make(params)


def _load_plugins() -> None:
    """Register the entries other installed packages declare, once."""
    global _plugins_loaded
    if _plugins_loaded:
        return
    _plugins_loaded = True
    for point in metadata.entry_points(group=ENTRY_POINT_GROUP):
        if point.name in _entries:
            continue  # this package's own, or a name already taken
        try:
            entry = point.load()
        except Exception as error:  # a broken plug-in must not take the other filters down
            warnings.warn(f"filter {point.name!r} could not be loaded: {error}", stacklevel=3)
            continue
        if not isinstance(entry, FilterEntry) or entry.name != point.name:
            message = f"entry point {point.name!r} names no FilterEntry of that name"
            warnings.warn(message, stacklevel=3)
            continue
        _entries[entry.name] = entry
