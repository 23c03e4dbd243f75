"""The Hector-style SLAM on synthetic scans: it tracks a known trajectory, and a corrupted
scan stream ends as a reported tracking failure, not a crash."""

import numpy as np
import pytest

from scaneval.geometry import compose, invert, transform_points
from scaneval.slam import HectorParams, HectorSlam, score_trajectory
from scaneval.synthetic import cluttered_room, scan_from_pose

LEVEL_ATE_M = 0.05  # m: what the SLAM must reach on noisy (1 cm) scans of a level sensor


def ellipse_trajectory(count: int = 150) -> np.ndarray:
    """One lap of an ellipse inside the cluttered room, heading along the path, 10 Hz.

    About 0.6 m/s and up to ~1 rad/s at the ends: the speeds of the paper's house runs.
    """
    phase = np.linspace(0.0, 2.0 * np.pi, count, endpoint=False)
    x, y = 1.8 * np.cos(phase), -0.5 + 1.0 * np.sin(phase)
    heading = np.arctan2(1.0 * np.cos(phase), -1.8 * np.sin(phase))
    return np.column_stack((x, y, heading))


@pytest.fixture(scope="module")
def level_run():
    """Scans along the ellipse, with the poses and the room they were cast in."""
    room, truth = cluttered_room(), ellipse_trajectory()
    rng = np.random.default_rng(7)
    scans = [scan_from_pose(room, pose, stamp=0.1 * k, rng=rng) for k, pose in enumerate(truth)]
    return room, truth, scans


def run(slam, scans):
    return np.array([slam.process_scan(scan).pose for scan in scans])


@pytest.fixture(scope="module")
def level_slam(level_run):
    """The SLAM after the whole level run, and its estimated trajectory."""
    slam = HectorSlam()
    return slam, run(slam, level_run[2])


def test_tracks_a_level_sensor_to_within_a_few_centimetres(level_run, level_slam):
    slam, estimate = level_slam
    score = score_trajectory(estimate, level_run[1])
    assert not score.failed, score.failure
    assert score.rmse_m < LEVEL_ATE_M
    assert not slam.lost


def test_the_map_frame_is_the_first_sensor_frame(level_run, level_slam):
    truth, estimate = level_run[1], level_slam[1]
    # unaligned: the estimate mapped into the world by the first true pose
    in_world = np.array([compose(truth[0], pose) for pose in estimate])
    assert np.max(np.hypot(*(in_world[:, :2] - truth[:, :2]).T)) < 3 * LEVEL_ATE_M


def test_the_map_shows_the_walls(level_run, level_slam):
    room, truth, _ = level_run
    grid = level_slam[0].maps[0]
    # points along the room's walls, in the map frame (the first sensor frame)
    t = np.linspace(0.1, 0.9, 20)[:, None]
    wall_points = np.concatenate([a + t * (b - a) for a, b in room[:4]])
    cells = np.floor((transform_points(wall_points, invert(truth[0])) - grid.origin_xy) / 0.05)
    cells = cells.astype(int)
    probability = grid.probability()
    # a wall's surface lies on a cell edge as often as not: look one cell around it
    near = [probability[i - 1 : i + 2, j - 1 : j + 2].max() for i, j in cells]
    assert np.mean(np.array(near) > 0.8) > 0.9


def test_a_corrupted_scan_stream_is_a_tracking_failure_not_a_crash(level_run):
    _, truth, scans = level_run
    rng = np.random.default_rng(3)
    corrupted = [
        # from scan 60 on, the ranges are shuffled across beams: nonsense points
        scan if k < 60 else scan.with_ranges(rng.permutation(scan.ranges))
        for k, scan in enumerate(scans)
    ]
    slam = HectorSlam()
    estimate = run(slam, corrupted)
    assert slam.lost and slam.lost_at_scan >= 60
    score = score_trajectory(estimate, truth, lost_at_scan=slam.lost_at_scan)
    assert score.failed
    assert "lost track" in score.failure


def test_empty_and_invalid_scans_are_survived(level_run):
    _, _, scans = level_run
    slam = HectorSlam(HectorParams(lost_after_scans=3))
    slam.process_scan(scans[0])
    for ranges in (np.full(720, np.nan), np.full(720, np.inf), np.zeros(720)):
        update = slam.process_scan(scans[1].with_ranges(ranges))
        assert not update.matched and update.points == 0
        np.testing.assert_array_equal(update.pose, slam.pose)
    assert slam.lost  # three unmatched scans in a row


def test_reset_forgets_the_map_and_the_pose(level_run):
    _, _, scans = level_run
    slam = HectorSlam()
    run(slam, scans[:20])
    slam.reset()
    assert slam.scans == 0 and not slam.pose.any() and not slam.maps[0].log_odds.any()


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"resolution_m": -0.05}, "resolution_m"),
        ({"levels": 0}, "levels"),
        ({"p_occupied": 0.3}, "p_occupied"),
        ({"range_min_m": 5.0, "range_max_m": 1.0}, "range_min_m"),
    ],
)
def test_bad_parameters_are_refused_by_name(kwargs, field):
    with pytest.raises(ValueError, match=field):
        HectorParams(**kwargs)
