"""A DATMO-like moving-object filter: the paper's baseline (kostaskonkk/datmo).

Per scan: cluster the valid points (jump distance in beam order, as DATMO does), put the
cluster centroids in the world frame with the sensor's pose, associate them with tracks
by nearest neighbour, run a constant-velocity Kalman filter per track, and remove the
beams of clusters whose track's estimated speed exceeds a threshold. Like the original
(whose Kalman filter also tracks the cluster mean), a cluster the size of a room's wall
(``max_cluster_size``) gets no track, and a track not seen in a scan is dropped.

Choices made where DATMO differs or leaves it open: association is one-to-one, greedy in
order of Euclidean distance (DATMO uses the Manhattan distance and lets two tracks take
the same cluster); the time step is the difference of scan stamps (DATMO fixes 0.08 s);
the Kalman filter models white acceleration noise.

A cluster's centroid moves whenever the part of an object in view changes (a box turning
another face to the sensor, a wall cut by the field of view or by something in front of
it), so static structure can show a speed. Clusters that appear suddenly and deform, as
pitch-variation clusters do, are tracked poorly for the same reason.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numpy.typing import ArrayLike

from pvfilter.checks import check_integer, check_number
from pvfilter.contract import check_pose
from pvfilter.paper.clustering import covers_full_turn, drop_small_clusters, scan_order_labels
from pvfilter.result import FilterResult, without_removed
from pvfilter.scan import Scan
from scaneval.geometry import transform_points


@dataclasses.dataclass(frozen=True)
class DatmoParams:
    """Parameters of :class:`DatmoLikeFilter`.

    Invalid values raise ``ValueError("<field>: <what was expected>, got <value>")``.

    Attributes:
        speed_threshold_mps: clusters whose track's speed exceeds this are removed, m/s
            (the paper tried 0.1, 0.2 and 0.3).
        cluster_distance_m: consecutive valid points at most this far apart join one
            cluster, m.
        min_cluster_size: smaller clusters are ignored, points.
        max_cluster_size: larger clusters get no track (and are never removed), points.
        gate_m: largest distance between a track's predicted and a cluster's centroid for
            them to be associated, m.
        process_noise: spectral density of the white acceleration noise, m^2/s^3.
        measurement_noise_m: standard deviation of a centroid measurement, m.
        initial_speed_std_mps: standard deviation of a new track's velocity (which starts
            at zero), m/s.
        max_missed_scans: a track survives this many scans without a cluster.
    """

    speed_threshold_mps: float = 0.1  # m/s
    cluster_distance_m: float = 0.3  # m
    min_cluster_size: int = 3  # points
    max_cluster_size: int = 360  # points
    gate_m: float = 0.5  # m
    process_noise: float = 1.0  # m^2/s^3
    measurement_noise_m: float = 0.05  # m
    initial_speed_std_mps: float = 1.0  # m/s
    max_missed_scans: int = 0  # scans

    def __post_init__(self) -> None:
        check_number("speed_threshold_mps", self.speed_threshold_mps, lower=0.0, closed=True)
        check_number("cluster_distance_m", self.cluster_distance_m, lower=0.0, unit="m")
        check_number("gate_m", self.gate_m, lower=0.0, unit="m")
        check_number("process_noise", self.process_noise, lower=0.0, unit="m^2/s^3")
        check_number("measurement_noise_m", self.measurement_noise_m, lower=0.0, unit="m")
        check_number("initial_speed_std_mps", self.initial_speed_std_mps, lower=0.0, unit="m/s")
        check_integer("min_cluster_size", self.min_cluster_size, 1)
        check_integer("max_cluster_size", self.max_cluster_size, self.min_cluster_size)
        check_integer("max_missed_scans", self.max_missed_scans, 0)


class DatmoLikeFilter:
    """Remove clusters whose world-frame track moves faster than a speed threshold.

    A :class:`pvfilter.ScanFilter` that needs the robot input ``pose_sensor_in_odom`` (the
    paper gave DATMO SLAM poses; the evaluation gives it the sensor's true pose). The
    tracking does not depend on the threshold, and the result's ``scores`` are the speed
    of every beam's track (m/s, 0 where the beam has none), so a sweep over thresholds can
    run the sequence once and compare the scores with each value.

    Args:
        params: the parameters; :class:`DatmoParams` defaults when omitted.
    """

    def __init__(self, params: DatmoParams | None = None) -> None:
        self.params = params if params is not None else DatmoParams()
        self.reset()

    def reset(self) -> None:
        """Forget every track (a new sequence)."""
        self.states = np.zeros((0, 4))  # x, y (m), vx, vy (m/s) per track, world frame
        self.covariances = np.zeros((0, 4, 4))
        self.missed = np.zeros(0, dtype=np.intp)
        self.ages = np.zeros(0, dtype=np.intp)  # measurements per track
        self.last_stamp: float | None = None

    def speeds(self) -> np.ndarray:
        """Estimated speed of every track, m/s."""
        return np.hypot(self.states[:, 2], self.states[:, 3])

    def process(
        self,
        scan: Scan,
        *,
        pose_sensor_in_odom: ArrayLike | None = None,
        pitch_rad: float | None = None,
        roll_rad: float | None = None,
    ) -> FilterResult:
        """Track one scan's clusters and remove those of fast tracks.

        Args:
            scan: the scan; its ``stamp`` gives the time step. A stamp earlier than the
                last one starts a new sequence.
            pose_sensor_in_odom: ``(x, y, theta)`` of the sensor in a fixed frame, m, m,
                rad (required: the tracks live in that frame).
            pitch_rad: ignored.
            roll_rad: ignored.

        Returns:
            Removed: the beams of clusters whose track's speed exceeds
            ``speed_threshold_mps``; scores: every beam's track speed, m/s.

        Raises:
            ValueError: no pose given.
        """
        pose = check_pose(pose_sensor_in_odom)
        if pose is None:
            raise ValueError("pose_sensor_in_odom: the DATMO-like filter needs the sensor's pose")
        params = self.params
        valid = np.flatnonzero(scan.valid_mask())
        points = scan.points()[valid]
        labels = drop_small_clusters(
            scan_order_labels(points, params.cluster_distance_m, ring=covers_full_turn(scan)),
            params.min_cluster_size,
        )
        member = labels >= 0
        sizes = np.bincount(labels[member])
        sums = [np.bincount(labels[member], points[member, axis]) for axis in (0, 1)]
        centroids = transform_points(np.column_stack(sums) / sizes[:, None], pose)
        tracked = sizes <= params.max_cluster_size

        self._predict(scan.stamp)
        track_of = self._associate(centroids, tracked)
        cluster_speeds = self._update(centroids, track_of, tracked)

        beam_speeds = np.zeros(len(scan))
        beam_speeds[valid[member]] = cluster_speeds[labels[member]]
        removed = beam_speeds > params.speed_threshold_mps
        return FilterResult(without_removed(scan, removed), removed, beam_speeds)

    def _predict(self, stamp: float) -> None:
        """Constant-velocity prediction of every track to ``stamp``."""
        dt = 0.0 if self.last_stamp is None else stamp - self.last_stamp
        if dt < 0.0:
            self.reset()
            dt = 0.0
        self.last_stamp = stamp
        if dt == 0.0 or len(self.states) == 0:
            return
        transition = np.eye(4)
        transition[0, 2] = transition[1, 3] = dt
        q = self.params.process_noise
        block = q * np.array([[dt**3 / 3.0, dt**2 / 2.0], [dt**2 / 2.0, dt]])
        noise = np.zeros((4, 4))
        noise[np.ix_([0, 2], [0, 2])] = noise[np.ix_([1, 3], [1, 3])] = block
        self.states = self.states @ transition.T
        self.covariances = transition @ self.covariances @ transition.T + noise

    def _associate(self, centroids: np.ndarray, tracked: np.ndarray) -> np.ndarray:
        """Track index per cluster (-1: none), greedy nearest pairs within the gate."""
        track_of = np.full(len(centroids), -1, dtype=np.intp)
        if len(self.states) == 0 or len(centroids) == 0:
            return track_of
        distance = np.linalg.norm(centroids[:, None, :] - self.states[None, :, :2], axis=2)
        distance[~tracked] = np.inf
        clusters, tracks = np.nonzero(distance <= self.params.gate_m)
        order = np.argsort(distance[clusters, tracks], kind="stable")
        track_taken = np.zeros(len(self.states), dtype=bool)
        for cluster, track in zip(clusters[order], tracks[order], strict=True):
            if track_of[cluster] < 0 and not track_taken[track]:
                track_of[cluster], track_taken[track] = track, True
        return track_of

    def _update(
        self, centroids: np.ndarray, track_of: np.ndarray, tracked: np.ndarray
    ) -> np.ndarray:
        """Kalman update of associated tracks, new tracks, pruning; speed per cluster."""
        matched = track_of >= 0
        index = track_of[matched]
        if index.size:
            states, covariances = self.states[index], self.covariances[index]
            innovation = centroids[matched] - states[:, :2]
            innovation_cov = covariances[:, :2, :2] + self.params.measurement_noise_m**2 * np.eye(2)
            gain = covariances[:, :, :2] @ np.linalg.inv(innovation_cov)  # (m, 4, 2)
            self.states[index] = states + np.einsum("mij,mj->mi", gain, innovation)
            self.covariances[index] = covariances - gain @ covariances[:, :2, :]
            self.ages[index] += 1
        seen = np.zeros(len(self.states), dtype=bool)
        seen[index] = True
        self.missed = np.where(seen, 0, self.missed + 1)
        cluster_speeds = np.zeros(len(centroids))
        cluster_speeds[matched] = np.hypot(self.states[index, 2], self.states[index, 3])

        keep = self.missed <= self.params.max_missed_scans
        new = ~matched & tracked
        noise, speed_std = self.params.measurement_noise_m, self.params.initial_speed_std_mps
        initial = np.diag([noise**2] * 2 + [speed_std**2] * 2)
        self.states = np.vstack(
            (self.states[keep], np.column_stack((centroids[new], np.zeros((new.sum(), 2)))))
        )
        self.covariances = np.concatenate(
            (self.covariances[keep], np.broadcast_to(initial, (int(new.sum()), 4, 4)))
        )
        self.missed = np.concatenate((self.missed[keep], np.zeros(new.sum(), dtype=np.intp)))
        self.ages = np.concatenate((self.ages[keep], np.ones(new.sum(), dtype=np.intp)))
        return cluster_speeds
