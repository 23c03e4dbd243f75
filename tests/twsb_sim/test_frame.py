"""Frames are immutable: the simulator's own read-only arrays are kept as they are, any
array a caller could still change is copied."""

from __future__ import annotations

import numpy as np
import pytest

from twsb_sim.frame import _frozen
from twsb_sim.house import make_house
from twsb_sim.simulation import Simulation


def test_a_read_only_view_of_a_writable_array_is_copied():
    owner = np.arange(6.0)
    view = owner[:3]
    view.flags.writeable = False
    kept = _frozen(view, np.float64)
    owner[0] = 99.0  # the caller changes its array after handing the view over
    assert kept[0] == 0.0 and not kept.flags.writeable


def test_a_read_only_array_nothing_else_can_change_is_kept_and_others_are_copied():
    block = np.arange(6.0)
    block.flags.writeable = False
    assert _frozen(block[2:5], np.float64).base is block  # a view of a frozen block: kept
    writable = np.arange(3.0)
    assert _frozen(writable, np.float64) is not writable  # copied, the original untouched
    assert writable.flags.writeable
    assert _frozen(block, np.float32).dtype == np.float32  # another dtype: converted


@pytest.fixture(scope="module")
def frame():
    sim = Simulation(make_house("house1"))
    sim.step(0.5, 0.0, 50)
    return sim.frame(0)


def test_a_simulated_frame_is_read_only_throughout(frame):
    arrays = [frame.labels, frame.hit_points_world, frame.geom_ids, frame.scan.ranges]
    truth = frame.truth
    arrays += [truth.position_base_in_world, truth.rotation_sensor_to_world, truth.imu_quat]
    sensors = frame.sensors
    arrays += [sensors.attitude_rpy_rad, sensors.pose_lidar_in_odom, sensors.imu.gyro_rad_s]
    for array in arrays:
        with pytest.raises(ValueError, match="read-only"):
            array[...] = 0.0
    assert truth.rotation_sensor_to_world.shape == (3, 3)
    np.testing.assert_allclose(np.linalg.det(truth.rotation_sensor_to_world), 1.0, atol=1e-9)
