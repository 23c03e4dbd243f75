"""A labeled 2D LiDAR: one ``mj_multiRay`` call per scan from the tilted sensor pose.

The scanner spins in the x-y plane of the ``lidar`` site. When the robot pitches or rolls,
that plane tilts with it, and beams that would run level hit the floor, the ceiling or a
table top instead: the pitch-variation points this project is about. Each beam gets a
ground-truth ``BeamLabel`` from the geom it hit and that surface's normal:

| condition (first that holds) | label |
|---|---|
| beam inside the blocked sector | OCCLUDED |
| nothing hit within ``range_max_m`` | NO_RETURN |
| hit geom is the floor | FLOOR |
| hit geom is the ceiling | CEILING |
| hit geom sits on a moving body (not the robot) | DYNAMIC |
| hit surface is horizontal (abs(normal z) >= ``horizontal_normal_min_z``) | HORIZONTAL |
| anything else (walls, door frames, furniture sides) | STATIC |

Ranges follow REP-117: ``+inf`` no return within ``range_max_m``; ``-inf`` a hit closer
than ``range_min_m``. Blocked beams are ``-inf`` too: the leg that blocks them is closer
than ``range_min_m``. Labels come from the noiseless hit, so noise never creates or removes
a return: a true hit in [range_min, range_max] keeps a finite noisy range, clipped to that
interval.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import mujoco
import numpy as np

from twsb_sim.house.surfaces import ROBOT_GEOM_GROUP, SurfaceClass, surface_classes
from twsb_sim.labels import BeamLabel

_NUM_GEOM_GROUPS = 6  # mjNGROUP
# bounds of what a 2D LiDAR can be: a finer, faster or longer-ranged scanner than any on
# sale is a typo, and would only fill the memory (beams x rate x duration) or stall the run
MAX_BEAMS_PER_REVOLUTION = 7200  # 0.05 deg resolution
MIN_RATE_HZ = 1.0  # Hz, scans per second
MAX_RATE_HZ = 50.0  # Hz; the physics runs at 500 Hz
MAX_RANGE_MIN_M = 1.0  # m
MAX_RANGE_M = 100.0  # m
MAX_RANGE_NOISE_STD_M = 1.0  # m


def _number(name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise ValueError(f"{name}: expected a finite number, got {value!r}")
    return float(value)


def _bounded(name: str, value: object, low: float, high: float, unit: str) -> float:
    number = _number(name, value)
    if not low <= number <= high:
        raise ValueError(f"{name}: expected {low:g} to {high:g} {unit}, got {value!r}")
    return number


@dataclass(frozen=True)
class LidarConfig:
    """The scanner's parameters (defaults: DESIGN.md, paper §IV-A)."""

    beams_per_revolution: int = 720  # beams over 360 deg (2 per degree)
    rate_hz: float = 10.0  # scans per second (Hz)
    useful_fov_deg: float = 240.0  # field of view not blocked by the robot's body (deg)
    blocked_sector_center_deg: float = -90.0  # centre of the blocked sector, CCW from ahead (deg)
    range_min_m: float = 0.05  # closer hits read -inf (m)
    range_max_m: float = 12.0  # no hit within this reads +inf (m)
    range_noise_std_m: float = 0.02  # std of the Gaussian range noise (m); 0 = noiseless
    horizontal_normal_min_z: float = 0.9  # abs(normal z) from which a surface is horizontal

    def __post_init__(self) -> None:
        n = self.beams_per_revolution
        if isinstance(n, bool) or not isinstance(n, int) or not 4 <= n <= MAX_BEAMS_PER_REVOLUTION:
            raise ValueError(
                f"beams_per_revolution: expected an integer in [4, {MAX_BEAMS_PER_REVOLUTION}],"
                f" got {n!r}"
            )
        _bounded("rate_hz", self.rate_hz, MIN_RATE_HZ, MAX_RATE_HZ, "Hz")
        fov = _number("useful_fov_deg", self.useful_fov_deg)
        if not 0 < fov <= 360:
            raise ValueError(f"useful_fov_deg: expected a value in (0, 360], got {fov!r}")
        _bounded("blocked_sector_center_deg", self.blocked_sector_center_deg, -360.0, 360.0, "deg")
        _bounded("range_min_m", self.range_min_m, 0.0, MAX_RANGE_MIN_M, "m")
        if _number("range_max_m", self.range_max_m) <= self.range_min_m:
            raise ValueError(
                f"range_max_m: expected a value above range_min_m ({self.range_min_m}), "
                f"got {self.range_max_m!r}"
            )
        _bounded("range_max_m", self.range_max_m, 0.0, MAX_RANGE_M, "m")
        _bounded("range_noise_std_m", self.range_noise_std_m, 0.0, MAX_RANGE_NOISE_STD_M, "m")
        nz = _number("horizontal_normal_min_z", self.horizontal_normal_min_z)
        if not 0 < nz <= 1:
            raise ValueError(f"horizontal_normal_min_z: expected a value in (0, 1], got {nz!r}")


@dataclass(frozen=True, eq=False)
class LidarReading:
    """One scan, with its ground truth.

    Attributes:
        ranges: float64[n], REP-117 encoded, with noise (m).
        labels: uint8[n] ``BeamLabel`` codes, from the noiseless hit.
        hit_points_world: float64[n, 3], true hit points in the world (m); NaN where no
            geom was hit within ``range_max`` and for blocked beams.
        geom_ids: int32[n], the geom each beam hit, -1 where none (as for the points).
        position_sensor_in_world: (3,) the sensor origin used for the cast (m).
        rotation_sensor_to_world: (3, 3) the sensor orientation used for the cast.
    """

    ranges: np.ndarray
    labels: np.ndarray
    hit_points_world: np.ndarray
    geom_ids: np.ndarray
    position_sensor_in_world: np.ndarray
    rotation_sensor_to_world: np.ndarray = field(repr=False)


class Lidar:
    """A spinning 2D LiDAR simulated by ray casting from a site of a MuJoCo model.

    The LaserScan intrinsics are attributes: ``angle_min`` (rad, = -pi), ``angle_max``,
    ``angle_increment`` (rad), ``range_min``, ``range_max`` (m), ``scan_time`` (s, 1 /
    rate) and ``time_increment`` (s), which is 0.0 because every beam of a scan is cast
    at the same instant (the robot does not move during a revolution).
    """

    def __init__(
        self, model: mujoco.MjModel, config: LidarConfig = LidarConfig(), site: str = "lidar"
    ) -> None:
        """Precompute beam directions, the useful-beam mask and the geoms' classes.

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
        self.time_increment = 0.0  # s: all beams are cast at one instant
        self.angles = self.angle_min + self.angle_increment * np.arange(n)  # rad
        # blocked sector: half-open [centre - half, centre + half) in beam angle
        half_blocked = math.radians(360.0 - config.useful_fov_deg) / 2
        centre = math.radians(config.blocked_sector_center_deg)
        offset = np.mod(self.angles - centre + math.pi, 2 * math.pi) - math.pi
        eps = 1e-9
        blocked = (offset >= -half_blocked - eps) & (offset < half_blocked - eps)
        self.useful = ~blocked  # bool[n]
        self._useful_idx = np.flatnonzero(self.useful)
        angles = self.angles[self._useful_idx]
        self._dirs_sensor = np.stack((np.cos(angles), np.sin(angles), np.zeros_like(angles)), -1)
        self._dirs_world = np.empty_like(self._dirs_sensor)
        self.surface_class = surface_classes(model)  # uint8 per geom id
        # label of a hit per geom (before the normal test); the extra last entry serves
        # geom id -1, so one gather labels misses too
        by_class = np.full(max(SurfaceClass) + 1, BeamLabel.STATIC, dtype=np.uint8)
        by_class[SurfaceClass.FLOOR] = BeamLabel.FLOOR
        by_class[SurfaceClass.CEILING] = BeamLabel.CEILING
        by_class[SurfaceClass.DYNAMIC] = BeamLabel.DYNAMIC
        self._label_by_geom = np.append(by_class[self.surface_class], np.uint8(BeamLabel.NO_RETURN))
        self.geomgroup = np.ones(_NUM_GEOM_GROUPS, dtype=np.uint8)
        self.geomgroup[ROBOT_GEOM_GROUP] = 0
        m = self._useful_idx.size
        self._geom_ids = np.empty(m, dtype=np.int32)
        self._dist = np.empty(m, dtype=np.float64)
        self._normals = np.empty(3 * m, dtype=np.float64)

    def scan(self, data: mujoco.MjData, rng: np.random.Generator) -> LidarReading:
        """Cast one scan from the site's current pose (run mj_forward/mj_step first).

        Args:
            data: the simulation state; kinematics must be current.
            rng: the source of the range noise; ``num_beams`` normal draws per scan,
                whatever the noise level, so the stream stays aligned across configs.

        Returns:
            The ranges, labels, hit points and geom ids of all ``num_beams`` beams.

        Cost: ~0.3 ms for 720 beams in house1 (116 geoms), ~0.45 ms in house2 (199 geoms)
        on one core of a current x86 machine; the ray cast itself is ~85 % of it.
        """
        cfg, idx = self.config, self._useful_idx
        position = data.site_xpos[self.site_id].copy()
        rotation = data.site_xmat[self.site_id].reshape(3, 3).copy()
        np.matmul(self._dirs_sensor, rotation.T, out=self._dirs_world)
        # one call for all useful beams; cutoff only culls geoms, it does not clip ranges
        mujoco.mj_multiRay(
            self.model, data, position, self._dirs_world.reshape(-1), self.geomgroup, 1, -1,
            self._geom_ids, self._dist, self._normals, idx.size, cfg.range_max_m,
        )  # fmt: skip
        dist = self._dist
        miss = (self._geom_ids < 0) | (dist > cfg.range_max_m)
        geom = np.where(miss, -1, self._geom_ids).astype(np.int32)

        # labels from the noiseless hit and the surface normal
        labels_useful = self._label_by_geom[geom]
        horizontal = np.abs(self._normals[2::3]) >= cfg.horizontal_normal_min_z
        labels_useful[horizontal & (labels_useful == BeamLabel.STATIC)] = BeamLabel.HORIZONTAL

        # noise perturbs returns only; a return stays within [range_min, range_max]
        noise = rng.standard_normal(self.num_beams)[idx]
        ranges_useful = np.clip(
            dist + cfg.range_noise_std_m * noise, cfg.range_min_m, cfg.range_max_m
        )
        ranges_useful[dist < cfg.range_min_m] = -np.inf
        ranges_useful[miss] = np.inf  # after -inf: a miss reports dist = -1

        points_useful = position + self._dirs_world * dist[:, None]
        points_useful[miss] = np.nan

        n = self.num_beams
        ranges = np.full(n, -np.inf)  # blocked beams: the leg is closer than range_min
        ranges[idx] = ranges_useful
        labels = np.full(n, BeamLabel.OCCLUDED, dtype=np.uint8)
        labels[idx] = labels_useful
        geom_ids = np.full(n, -1, dtype=np.int32)
        geom_ids[idx] = geom
        points = np.full((n, 3), np.nan)
        points[idx] = points_useful
        return LidarReading(ranges, labels, points, geom_ids, position, rotation)
