"""A labeled 2D LiDAR: a rotating (or global-shutter) ray cast from the tilted sensor pose.

The scanner spins in the x-y plane of the ``lidar`` site. When the robot pitches or rolls,
that plane tilts with it, and beams that would run level hit the floor, the ceiling or a
table top instead: the pitch-variation points this project is about. Each beam gets a
ground-truth ``BeamLabel`` from the geom it hit and that surface's normal:

| condition (first that holds) | label |
|---|---|
| beam inside the blocked sector | OCCLUDED |
| nothing hit within ``range_max_m``, or the return was lost (dropout) | NO_RETURN |
| hit geom is the floor | FLOOR |
| hit geom is the ceiling | CEILING |
| hit geom sits on a moving body (not the robot) | DYNAMIC |
| hit surface is horizontal (abs(normal z) >= ``horizontal_normal_min_z``) | HORIZONTAL |
| anything else (walls, door frames, furniture sides) | STATIC |

**Timing** (``sweep``): a real scanner measures its beams one after the other over a
revolution. With ``"rotating"`` (the default) beam ``i`` is cast from the sensor's pose
at ``stamp + i * time_increment``, ``time_increment = scan_time / beams_per_revolution``
(negative for a clockwise scanner, whose beam 0 comes last), ``stamp`` the time of beam
0, as ROS drivers publish ``LaserScan``. A scan is complete, and handed out, when its
revolution ends. ``"instant"`` casts every beam at one instant (``time_increment = 0``).

Labels, hit points and ranges all come from the same per-beam poses. Ranges follow
REP-117: ``+inf`` no return within ``range_max_m``; ``-inf`` a hit closer than
``range_min_m`` (and the blocked beams: the leg is closer than that). The imperfections
of a cheap scanner (noise growing with range, quantisation, dropouts, mixed pixels; see
:mod:`twsb_sim.sensors.lidar_errors`) change the readings only: a true hit in
[range_min, range_max] that is not dropped keeps a finite range, clipped to that interval.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Literal

import mujoco
import numpy as np

from twsb_sim.house.surfaces import ROBOT_GEOM_GROUP, SurfaceClass, surface_classes
from twsb_sim.labels import BeamLabel, with_label
from twsb_sim.lidar_reading import PARAMS, from_beam_origins, read_beams
from twsb_sim.raycast import RayCaster
from twsb_sim.sensors.checks import non_negative, number, within
from twsb_sim.sensors.sweep import PoseTrack

_NUM_GEOM_GROUPS = 6  # mjNGROUP
_RANDOM_ROWS = 5  # uniform draws per useful beam and scan: 2 dropouts, 3 mixed pixels
# bounds of what a 2D LiDAR can be: a finer, faster or longer-ranged scanner than any on
# sale is a typo, and would only fill the memory (beams x rate x duration) or stall the run
MAX_BEAMS_PER_REVOLUTION = 7200  # 0.05 deg resolution
MIN_RATE_HZ = 1.0  # Hz, scans per second
MAX_RATE_HZ = 50.0  # Hz; the physics runs at 500 Hz
MAX_RANGE_MIN_M = 1.0  # m
MAX_RANGE_M = 100.0  # m
MAX_RANGE_NOISE_STD_M = 1.0  # m

Sweep = Literal["rotating", "instant"]
Rotation = Literal["counter-clockwise", "clockwise"]


@dataclass(frozen=True)
class LidarConfig:
    """The scanner's parameters.

    Layout and rate: docs/conventions.md and the paper (§IV-A). Imperfections: the SLAMTEC RPLIDAR
    A1M8 data sheet where it gives a number (range 0.15-12 m, resolution under 1 % of the
    distance); ``docs/sensors.md`` lists the sources. ``LidarConfig.ideal()`` switches
    every imperfection off.
    """

    beams_per_revolution: int = 720  # beams over 360 deg (2 per degree)
    rate_hz: float = 10.0  # revolutions (scans) per second (Hz)
    useful_fov_deg: float = 240.0  # field of view not blocked by the robot's body (deg)
    blocked_sector_center_deg: float = -90.0  # centre of the blocked sector, CCW from ahead (deg)
    range_min_m: float = 0.15  # closer hits read -inf (m); RPLIDAR A1: 0.15 m
    range_max_m: float = 12.0  # no hit within this reads +inf (m); RPLIDAR A1: 12 m
    sweep: Sweep = "rotating"  # beams measured one after the other, or all at one instant
    rotation: Rotation = "counter-clockwise"  # spin direction seen from above
    range_noise_std_m: float = 0.005  # Gaussian range noise std at zero range (m)
    range_noise_fraction: float = 0.01  # ... plus this fraction of the range (A1: < 1 %)
    range_resolution_m: float = 0.0005  # readings are multiples of this (m); 0 = exact
    dropout_probability: float = 0.01  # a return lost at random
    grazing_dropout_start_deg: float = 85.0  # incidence beyond which returns fade; 90 = never
    mixed_pixel_probability: float = 0.5  # a depth edge between two beams gives a mixed return
    mixed_pixel_min_jump_m: float = 0.2  # m, range jump between neighbours that is an edge
    ray_groups: int = 1  # rotating sweep: ray casts per scan, each from its part's mid pose
    horizontal_normal_min_z: float = 0.9  # abs(normal z) from which a surface is horizontal

    def __post_init__(self) -> None:
        n = self.beams_per_revolution
        if isinstance(n, bool) or not isinstance(n, int) or not 4 <= n <= MAX_BEAMS_PER_REVOLUTION:
            raise ValueError(
                f"beams_per_revolution: expected an integer in [4, {MAX_BEAMS_PER_REVOLUTION}],"
                f" got {n!r}"
            )
        within("rate_hz", self.rate_hz, MIN_RATE_HZ, MAX_RATE_HZ, "Hz")
        fov = number("useful_fov_deg", self.useful_fov_deg)
        if not 0 < fov <= 360:
            raise ValueError(f"useful_fov_deg: expected a value in (0, 360], got {fov!r}")
        within("blocked_sector_center_deg", self.blocked_sector_center_deg, -360.0, 360.0, "deg")
        within("range_min_m", self.range_min_m, 0.0, MAX_RANGE_MIN_M, "m")
        if number("range_max_m", self.range_max_m) <= self.range_min_m:
            raise ValueError(
                f"range_max_m: expected a value above range_min_m ({self.range_min_m}), "
                f"got {self.range_max_m!r}"
            )
        if self.sweep not in ("rotating", "instant"):
            raise ValueError(f"sweep: expected 'rotating' or 'instant', got {self.sweep!r}")
        if self.rotation not in ("counter-clockwise", "clockwise"):
            raise ValueError(
                f"rotation: expected 'counter-clockwise' or 'clockwise', got {self.rotation!r}"
            )
        within("range_max_m", self.range_max_m, 0.0, MAX_RANGE_M, "m")
        within("range_noise_std_m", self.range_noise_std_m, 0.0, MAX_RANGE_NOISE_STD_M, "m")
        within("range_noise_fraction", self.range_noise_fraction, 0.0, 1.0)
        within("range_resolution_m", self.range_resolution_m, 0.0, 1.0, "m")
        within("dropout_probability", self.dropout_probability, 0.0, 1.0)
        within("grazing_dropout_start_deg", self.grazing_dropout_start_deg, 0.0, 90.0, "deg")
        within("mixed_pixel_probability", self.mixed_pixel_probability, 0.0, 1.0)
        non_negative("mixed_pixel_min_jump_m", self.mixed_pixel_min_jump_m, "m")
        g = self.ray_groups
        if isinstance(g, bool) or not isinstance(g, int) or not 1 <= g <= 50:
            raise ValueError(f"ray_groups: expected an integer from 1 to 50, got {g!r}")
        nz = number("horizontal_normal_min_z", self.horizontal_normal_min_z)
        if not 0 < nz <= 1:
            raise ValueError(f"horizontal_normal_min_z: expected a value in (0, 1], got {nz!r}")

    @classmethod
    def ideal(cls, **changes: object) -> LidarConfig:
        """A scanner without imperfections (exact ranges, no dropouts, no mixed pixels),
        the minimum range of a good one (0.05 m); ``changes`` override any field."""
        perfect = {
            "range_min_m": 0.05,
            "range_noise_std_m": 0.0,
            "range_noise_fraction": 0.0,
            "range_resolution_m": 0.0,
            "dropout_probability": 0.0,
            "grazing_dropout_start_deg": 90.0,
            "mixed_pixel_probability": 0.0,
        }
        return cls(**{**perfect, **changes})


@dataclass(frozen=True, eq=False)
class LidarReading:
    """One scan, with its ground truth.

    Attributes:
        ranges: float64[n], REP-117 encoded, as the scanner reads them (m).
        labels: uint8[n] ``BeamLabel`` codes, from the noiseless hit of each beam's pose.
        hit_points_world: float64[n, 3], true hit points in the world (m); NaN where no
            return (nothing within ``range_max``, a lost return) and for blocked beams.
        geom_ids: int32[n], the geom each beam hit, -1 where no return (as the points).
        position_sensor_in_world: (3,) the sensor origin at the stamp (m).
        rotation_sensor_to_world: (3, 3) the sensor orientation at the stamp.
        stamp_s: time of beam 0, s.
        useful_origins_world: float64[m, 3], where each useful (not blocked) beam
            started (m), in beam order; :attr:`origins_world` spreads them over all beams.
    """

    ranges: np.ndarray
    labels: np.ndarray
    hit_points_world: np.ndarray
    geom_ids: np.ndarray
    position_sensor_in_world: np.ndarray
    rotation_sensor_to_world: np.ndarray = field(repr=False)
    stamp_s: float = 0.0
    useful_origins_world: np.ndarray | None = field(default=None, repr=False)

    @property
    def origins_world(self) -> np.ndarray:
        """float64[n, 3], where each beam started (m); NaN for blocked beams."""
        origins = np.full(self.hit_points_world.shape, np.nan)
        origins[~with_label(self.labels, BeamLabel.OCCLUDED)] = self.useful_origins_world
        return origins


class Lidar:
    """A spinning 2D LiDAR simulated by ray casting from a site of a MuJoCo model.

    The LaserScan intrinsics are attributes: ``angle_min`` (rad, = -pi), ``angle_max``,
    ``angle_increment`` (rad), ``range_min``, ``range_max`` (m), ``scan_time`` (s, 1 /
    rate) and ``time_increment`` (s: ``scan_time / n``, negative when clockwise, 0 for an
    instant sweep). ``stamp_offset_s`` is where a scan's stamp lies relative to the end
    of its revolution (``-scan_time`` counter-clockwise: beam 0 comes first; 0 clockwise
    and instant).
    """

    def __init__(
        self, model: mujoco.MjModel, config: LidarConfig = LidarConfig(), site: str = "lidar"
    ) -> None:
        """Precompute beam directions and times, the useful-beam mask and the geoms' classes.

        Args:
            model: compiled model holding the house, the robot and a site named ``site``.
            config: scanner parameters.
            site: name of the site at the scanner's origin; its x axis is beam angle 0
                and its z axis the spin axis.

        Raises:
            ValueError: when the model has no such site.
        """
        site_id = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, site)
        if site_id < 0:
            raise ValueError(f"site: the model has no site named {site!r}")
        self.model = model
        self.config = config
        self.site_id = site_id
        n = config.beams_per_revolution
        self.num_beams = n
        self.angle_increment = 2 * math.pi / n  # rad
        self.angle_min = -math.pi  # rad
        self.angle_max = self.angle_min + (n - 1) * self.angle_increment  # rad
        self.range_min = config.range_min_m
        self.range_max = config.range_max_m
        self.scan_time = 1.0 / config.rate_hz  # s
        self.rotating = config.sweep == "rotating"
        clockwise = config.rotation == "clockwise"
        beam_period = self.scan_time / n if self.rotating else 0.0  # s
        self.time_increment = -beam_period if clockwise else beam_period
        self.stamp_offset_s = -self.scan_time if self.rotating and not clockwise else 0.0
        self.angles = self.angle_min + self.angle_increment * np.arange(n)  # rad
        # blocked sector: half-open [centre - half, centre + half) in beam angle
        half_blocked = math.radians(360.0 - config.useful_fov_deg) / 2
        centre = math.radians(config.blocked_sector_center_deg)
        offset = np.mod(self.angles - centre + math.pi, 2 * math.pi) - math.pi
        eps = 1e-9
        blocked = (offset >= -half_blocked - eps) & (offset < half_blocked - eps)
        self.useful = ~blocked  # bool[n]
        self._useful_idx = np.flatnonzero(self.useful)
        self._adjacent = np.diff(self._useful_idx) == 1  # neighbours in angle, for mixed pixels
        angles = self.angles[self._useful_idx]
        self._dirs_sensor = np.stack((np.cos(angles), np.sin(angles), np.zeros_like(angles)), -1)
        self._dirs_world = np.empty_like(self._dirs_sensor)
        # rotating sweep: each useful beam's time after the stamp, and its cast group
        self._beam_offsets_s = self._useful_idx * self.time_increment
        start = self._beam_offsets_s.min() if len(angles) else 0.0
        part = np.floor((self._beam_offsets_s - start) / self.scan_time * config.ray_groups)
        group = np.clip(part.astype(int), 0, config.ray_groups - 1)
        # each group is a contiguous run of beams, cast from its middle beam's origin
        self._runs = []  # (first, stop, middle) beam of each group
        self._cast_from = np.empty(len(angles), dtype=np.int64)  # each beam's middle beam
        for g in range(config.ray_groups):
            beams = np.flatnonzero(group == g)
            if len(beams):
                lo, hi = int(beams[0]), int(beams[-1]) + 1
                self._runs.append((lo, hi, lo + (hi - lo) // 2))
                self._cast_from[lo:hi] = lo + (hi - lo) // 2
        self.surface_class = surface_classes(model)  # uint8 per geom id
        # label of a hit per geom (before the normal test); the extra last entry serves
        # geom id -1, so one gather labels misses too
        by_class = np.full(max(SurfaceClass) + 1, int(BeamLabel.STATIC), dtype=np.uint8)
        by_class[SurfaceClass.FLOOR] = BeamLabel.FLOOR
        by_class[SurfaceClass.CEILING] = BeamLabel.CEILING
        by_class[SurfaceClass.DYNAMIC] = BeamLabel.DYNAMIC
        self._label_by_geom = np.append(by_class[self.surface_class], np.uint8(BeamLabel.NO_RETURN))
        self.geomgroup = np.ones(_NUM_GEOM_GROUPS, dtype=np.uint8)
        self.geomgroup[ROBOT_GEOM_GROUP] = 0
        self.caster = RayCaster(model, self.geomgroup)  # mj_multiRay's answers, sooner
        m = self._useful_idx.size
        self._geom_ids = np.empty(m, dtype=np.int32)
        self._dist = np.empty(m, dtype=np.float64)
        self._normals = np.empty(3 * m, dtype=np.float64)
        self._along = np.empty(m, dtype=np.float64)  # normal . direction of each beam
        self._no_groups = np.empty(0, dtype=np.int64)
        numbers = {
            **{name: getattr(config, name) for name in PARAMS if hasattr(config, name)},
            "cos_grazing_start": math.cos(math.radians(config.grazing_dropout_start_deg)),
        }
        self._params = np.array([numbers[name] for name in PARAMS], dtype=np.float64)

    def scan(self, data: mujoco.MjData, rng: np.random.Generator) -> LidarReading:
        """Cast every beam at once from the site's current pose (run mj_forward first).

        This is the ``"instant"`` sweep; its stamp is ``data.time``.

        Args:
            data: the simulation state; kinematics must be current.
            rng: the source of the reading errors; a fixed number of draws per scan
                whatever the settings, so the stream stays aligned across configs.

        Returns:
            The ranges, labels, hit points and geom ids of all ``num_beams`` beams.
        """
        position = data.site_xpos[self.site_id].copy()
        rotation = data.site_xmat[self.site_id].reshape(3, 3).copy()
        np.matmul(self._dirs_sensor, rotation.T, out=self._dirs_world)
        self._cast(data, position, self._dirs_world, grouped=False)
        origins = np.broadcast_to(position, self._dirs_world.shape)
        return self._reading(origins, self._dirs_world, rng, position, rotation, float(data.time))

    def sweep(
        self, data: mujoco.MjData, rng: np.random.Generator, track: PoseTrack, stamp_s: float
    ) -> LidarReading:
        """Cast a revolution whose beam 0 was measured at ``stamp_s``, each beam from its pose.

        Each beam's direction is turned by the sensor's orientation at the beam's time;
        the beams are cast in ``ray_groups`` calls, each from the sensor's position at its
        group's middle time, and each range is then moved to the beam's own origin along
        the hit surface's plane, exactly for flat surfaces (``docs/sensors.md``).

        Args:
            data: the simulation state (for the geoms; they are static or current).
            rng: the source of the reading errors (as :meth:`scan`).
            track: the sensor's poses over the revolution.
            stamp_s: the scan's stamp, s: the revolution ends at ``stamp_s -
                stamp_offset_s``.
        """
        stamp = stamp_s
        origins, dirs = track.beams(stamp + self._beam_offsets_s, self._dirs_sensor)
        self._cast(data, origins, dirs, grouped=True)
        position, rotation = track.at(stamp)
        return self._reading(origins, dirs, rng, position, rotation, stamp)

    def _cast(
        self, data: mujoco.MjData, origins: np.ndarray, dirs: np.ndarray, grouped: bool
    ) -> None:
        """Fill ``_geom_ids``, ``_dist`` (from each beam's own origin), ``_normals`` and
        ``_along`` (each hit normal dotted with its beam's direction)."""
        cast, limit = self.caster.cast, self.config.range_max_m
        ids, dist, normals = self._geom_ids, self._dist, self._normals
        if not grouped:  # one origin for all: one cast
            cast(data, origins, dirs, ids, dist, normals, limit)
            # no groups: only the normals' products with the directions; origins unread
            from_beam_origins(dist, ids, normals, self._along, dirs, dirs, self._no_groups)
            return
        # a cast costs ~20 us whatever its size (filing the geoms): a few, then the plane fix
        for lo, hi, mid in self._runs:
            cast(data, origins[mid], dirs[lo:hi], ids[lo:hi], dist[lo:hi],
                 normals[3 * lo : 3 * hi], limit)  # fmt: skip
        from_beam_origins(dist, ids, normals, self._along, origins, dirs, self._cast_from)

    def _reading(
        self,
        origins: np.ndarray,
        dirs: np.ndarray,
        rng: np.random.Generator,
        position: np.ndarray,
        rotation: np.ndarray,
        stamp: float,
    ) -> LidarReading:
        """Labels, errors and REP-117 encoding of the cast in ``_geom_ids``/``_dist``."""
        m = self._useful_idx.size
        normal_draws = rng.standard_normal(m)  # fixed counts per scan
        uniforms = rng.random((_RANDOM_ROWS, m))
        ranges, labels, points, geom_ids = read_beams(
            self._dist, self._geom_ids, self._normals, self._along, normal_draws, uniforms,
            self._label_by_geom, self._adjacent, origins, dirs, self._useful_idx,
            self.num_beams, self._params,
        )  # fmt: skip
        return LidarReading(ranges, labels, points, geom_ids, position, rotation, stamp, origins)
