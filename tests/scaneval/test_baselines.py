import math

import numpy as np
import pytest

from pvfilter import FilterResult, ScanFilter, make_filter
from pvfilter.scan import Scan
from scaneval.baselines import DatmoLikeFilter, DatmoParams, ImuGateParams, ImuHeightGate, NoFilter
from scaneval.geometry import transform_points
from scaneval.synthetic import box_segments, scan_from_pose

WALL = np.array([[[-2.0, -1.0], [-2.0, 1.0]]])  # world frame, m: a static wall behind


def box_centre(k, velocity, start):
    return np.asarray(start, dtype=float) + 0.1 * k * np.asarray(velocity, dtype=float)


def box_scan(k, sensor_pose=(0.0, 0.0, 0.0), velocity=(0.5, 0.0), start=(1.5, 0.0)):
    """Scan k (10 Hz) of the wall and a 0.4 m box moving at ``velocity`` (m/s)."""
    scene = np.concatenate((WALL, box_segments(box_centre(k, velocity, start), 0.2, 0.2)))
    return scan_from_pose(scene, sensor_pose, stamp=0.1 * k, rng=np.random.default_rng(k))


def world_points(scan, sensor_pose):
    return transform_points(scan.points(), sensor_pose)


def box_beams(scan, k, sensor_pose=(0.0, 0.0, 0.0), velocity=(0.5, 0.0), start=(1.5, 0.0)):
    """Beams that end on the box."""
    offset = world_points(scan, sensor_pose) - box_centre(k, velocity, start)
    with np.errstate(invalid="ignore"):
        return np.all(np.abs(offset) < 0.25, axis=1)


def wall_beams(scan, sensor_pose=(0.0, 0.0, 0.0)):
    with np.errstate(invalid="ignore"):
        return np.abs(world_points(scan, sensor_pose)[:, 0] + 2.0) < 0.05


def test_no_filter_removes_nothing():
    scan = box_scan(0)
    assert not NoFilter().process(scan, pose_sensor_in_odom=(0, 0, 0), pitch_rad=0.1).removed.any()
    result = NoFilter().process(scan)
    assert result.removed.shape == (len(scan),) and result.scan is scan


@pytest.mark.parametrize("name", ["none", "datmo", "imu_gate"])
def test_every_baseline_is_a_registered_scan_filter(name):
    scan_filter = make_filter(name)
    assert isinstance(scan_filter, ScanFilter)
    result = scan_filter.process(box_scan(0), pose_sensor_in_odom=(0, 0, 0), pitch_rad=0.0)
    assert isinstance(result, FilterResult)
    assert result.removed.shape == result.scores.shape == (len(box_scan(0)),)
    np.testing.assert_array_equal(
        np.isnan(result.scan.ranges) & ~np.isnan(box_scan(0).ranges), result.removed
    )


def test_baselines_refuse_to_run_without_the_input_they_need():
    with pytest.raises(ValueError, match="pose_sensor_in_odom"):
        DatmoLikeFilter().process(box_scan(0))
    with pytest.raises(ValueError, match="pitch_rad"):
        ImuHeightGate().process(box_scan(0))


@pytest.mark.parametrize("velocity", [(0.5, 0.0), (-0.5, 0.0), (1.0, 0.0)])
def test_datmo_estimates_speed_of_box_moving_radially_within_ten_percent(velocity):
    # straight ahead only the box's front face is seen, so its centroid moves with the box
    datmo = DatmoLikeFilter()
    for k in range(5):
        scan = box_scan(k, velocity=velocity)
        result = datmo.process(scan, pose_sensor_in_odom=(0.0, 0.0, 0.0))
    speed = np.median(result.scores[box_beams(scan, k, velocity=velocity)])
    assert speed == pytest.approx(np.hypot(*velocity), rel=0.10)


def test_datmo_removes_moving_box_and_keeps_static_wall():
    datmo = DatmoLikeFilter(DatmoParams(speed_threshold_mps=0.1))
    for k in range(5):
        scan = box_scan(k)
        removed = datmo.process(scan, pose_sensor_in_odom=(0.0, 0.0, 0.0)).removed
    on_box, on_wall = box_beams(scan, k), wall_beams(scan)
    assert on_box.sum() >= 10 and on_wall.sum() >= 50
    assert removed[on_box].all()
    assert not removed[~on_box].any()


def test_datmo_keeps_static_scene_seen_from_moving_sensor_with_its_world_pose():
    datmo = DatmoLikeFilter(DatmoParams(speed_threshold_mps=0.1))
    for k in range(10):
        pose = (0.03 * k, 0.0, 0.02 * k)  # 0.3 m/s forward while turning left
        scan = box_scan(k, pose, velocity=(0.0, 0.0))
        removed = datmo.process(scan, pose_sensor_in_odom=pose).removed
        assert box_beams(scan, k, pose, velocity=(0.0, 0.0)).sum() >= 10
        assert not removed.any()


def test_datmo_sensor_frame_poses_make_static_box_look_moving():
    datmo = DatmoLikeFilter(DatmoParams(speed_threshold_mps=0.1))
    for k in range(5):
        pose = (0.05 * k, 0.0, 0.0)  # 0.5 m/s forward, but told it stands still
        scan = box_scan(k, pose, velocity=(0.0, 0.0))
        removed = datmo.process(scan, pose_sensor_in_odom=(0.0, 0.0, 0.0)).removed
    assert removed[box_beams(scan, k, pose, velocity=(0.0, 0.0))].all()


def test_datmo_beam_speeds_threshold_like_the_filter():
    datmo = DatmoLikeFilter(DatmoParams(speed_threshold_mps=0.3))
    for k in range(6):
        result = datmo.process(box_scan(k), pose_sensor_in_odom=(0.0, 0.0, 0.0))
    assert result.removed.any()
    np.testing.assert_array_equal(result.removed, result.scores > 0.3)


def test_datmo_reset_and_stamp_going_back_forget_tracks():
    datmo = DatmoLikeFilter()
    for k in range(3):
        datmo.process(box_scan(k), pose_sensor_in_odom=(0.0, 0.0, 0.0))
    assert len(datmo.states) > 0
    removed = datmo.process(box_scan(0), pose_sensor_in_odom=(0.0, 0.0, 0.0)).removed
    assert not removed.any()  # every track is new again
    datmo.reset()
    assert len(datmo.states) == 0


def test_datmo_rejects_bad_parameters():
    with pytest.raises(ValueError, match="gate_m"):
        DatmoParams(gate_m=0.0)
    with pytest.raises(ValueError, match="max_cluster_size: must be an integer >= 10"):
        DatmoParams(min_cluster_size=10, max_cluster_size=5)


LIDAR_HEIGHT = 0.25  # m
CEILING = 2.4  # m
FRONT, BACK, LEFT, RIGHT = 5.0, 3.0, 2.0, 2.5  # m, walls around the sensor


def tilted_room_scan(pitch, roll):
    """A full-turn scan of a box room from a tilted scanner, ray cast in 3D in closed form.

    Returns the scan and the true height above the floor of every beam's end point.
    """
    angles = -math.pi + (2.0 * math.pi / 720) * np.arange(720)
    beams = np.column_stack((np.cos(angles), np.sin(angles), np.zeros(720)))
    cp, sp, cr, sr = math.cos(pitch), math.sin(pitch), math.cos(roll), math.sin(roll)
    rotation = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]]) @ np.array(
        [[1, 0, 0], [0, cr, -sr], [0, sr, cr]]
    )
    d = beams @ rotation.T  # beam directions in the level frame
    with np.errstate(divide="ignore"):
        planes = [
            np.where(d[:, 0] > 0, FRONT / d[:, 0], np.inf),
            np.where(d[:, 0] < 0, -BACK / d[:, 0], np.inf),
            np.where(d[:, 1] > 0, LEFT / d[:, 1], np.inf),
            np.where(d[:, 1] < 0, -RIGHT / d[:, 1], np.inf),
            np.where(d[:, 2] < 0, -LIDAR_HEIGHT / d[:, 2], np.inf),  # floor
            np.where(d[:, 2] > 0, (CEILING - LIDAR_HEIGHT) / d[:, 2], np.inf),  # ceiling
        ]
    ranges = np.min(planes, axis=0)
    heights = LIDAR_HEIGHT + ranges * d[:, 2]
    scan = Scan(
        ranges=ranges,
        angle_min=-math.pi,
        angle_increment=2.0 * math.pi / 720,
        range_min=0.05,
        range_max=12.0,
    )
    return scan, heights


def level_gate():
    """The gate of a scanner that tilts about its own origin, as the closed-form room has it."""
    return ImuHeightGate(ImuGateParams(lidar_height_m=LIDAR_HEIGHT, axle_height_m=LIDAR_HEIGHT))


def test_imu_gate_keeps_level_wall():
    scan, _ = tilted_room_scan(0.0, 0.0)
    assert not level_gate().process(scan, pitch_rad=0.0, roll_rad=0.0).removed.any()


@pytest.mark.parametrize(("pitch_deg", "roll_deg"), [(5.0, 0.0), (-6.0, 0.0), (4.0, 3.0)])
def test_imu_gate_drops_floor_and_ceiling_hits_of_tilted_scanner(pitch_deg, roll_deg):
    pitch, roll = math.radians(pitch_deg), math.radians(roll_deg)
    scan, heights = tilted_room_scan(pitch, roll)
    gate = level_gate()
    result = gate.process(scan, pitch_rad=pitch, roll_rad=roll)
    removed = result.removed
    np.testing.assert_array_equal(removed, result.scores > 0.0)
    np.testing.assert_allclose(gate.heights(scan, pitch, roll), heights, atol=1e-9)
    np.testing.assert_array_equal(removed, (heights < 0.05) | (heights > 2.0))
    on_floor = np.isclose(heights, 0.0)
    assert on_floor.sum() > 20  # the tilted plane reaches the floor
    assert removed[on_floor].all()
    assert (~removed).sum() > 300  # the walls stay


def test_imu_gate_floor_hit_of_pitched_scanner_at_closed_form_range():
    pitch = math.radians(5.0)
    scan, _ = tilted_room_scan(pitch, 0.0)
    ahead = len(scan) // 2  # beam at 0 rad
    assert scan.ranges[ahead] == pytest.approx(LIDAR_HEIGHT / math.sin(pitch))
    assert level_gate().process(scan, pitch_rad=pitch).removed[ahead]


def test_imu_gate_tilting_about_the_axle_lowers_the_scanner():
    gate = ImuHeightGate(ImuGateParams(lidar_height_m=0.25, axle_height_m=0.05))
    assert gate.sensor_height(0.0, 0.0) == pytest.approx(0.25)
    assert gate.sensor_height(math.radians(60.0), 0.0) == pytest.approx(0.05 + 0.2 * 0.5)
