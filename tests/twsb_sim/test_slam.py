"""SLAM in the simulated houses: the Hector-style SLAM tracks a level robot, KISS-ICP runs,
a corrupted scan stream is a reported tracking failure, and the random hard-stop
sequences keep the robot off the walls."""

import numpy as np
import pytest

from scaneval.slam import score_trajectory
from twsb_sim.house import ROBOT_RADIUS_M
from twsb_sim.house.spawn import Obstacles
from twsb_sim.robot_inputs import sensor_pose_2d
from twsb_sim.slam.experiment import cut
from twsb_sim.slam.recording import record_frames
from twsb_sim.slam.sequences import hard_stop_sequence, shipped_sequence
from twsb_sim.slam.systems import run_system

LEVEL_ATE_M = 0.05  # m: the Hector-style SLAM on a level robot in house1
LEVEL_PITCH_DEG = 1.5  # deg: the gentle part of house1_single never pitches more


@pytest.fixture(scope="module")
def gentle_run():
    """The first 18 s of house1_single: gentle start and stop, a turn; frames and truth."""
    sequence = cut(shipped_sequence("house1_single"), 18.0)
    frames, _ = record_frames(sequence.scenario, seed=0)
    truth = np.array([sensor_pose_2d(f.truth) for f in frames])
    return frames, truth


def keep_all(frames):
    return [np.zeros(len(f.scan), dtype=bool) for f in frames]


def test_the_gentle_run_is_level(gentle_run):
    frames, _ = gentle_run
    assert max(abs(np.degrees(f.truth.pitch_rad)) for f in frames) < LEVEL_PITCH_DEG


def test_hector_tracks_a_level_robot_in_house1(gentle_run):
    frames, truth = gentle_run
    run = run_system("hector", frames, keep_all(frames))
    score = score_trajectory(run.poses, truth, lost_at_scan=run.lost_at_scan, error=run.error)
    assert not score.failed, score.failure
    assert score.rmse_m < LEVEL_ATE_M
    assert run.wall_s > 0.0


def test_kiss_icp_runs_on_a_short_sequence(gentle_run):
    pytest.importorskip("kiss_icp")
    frames, truth = gentle_run
    frames, truth = frames[:100], truth[:100]
    run = run_system("kiss_icp", frames, keep_all(frames))
    assert run.error == ""
    score = score_trajectory(run.poses, truth)
    assert not score.failed, score.failure
    assert score.rmse_m < 0.1
    assert run.slam.max_out_of_plane_m < 0.01  # z = 0 points keep it in the plane


def test_a_corrupted_scan_stream_is_a_tracking_failure_not_a_crash(gentle_run):
    frames, truth = gentle_run
    rng = np.random.default_rng(0)
    # from frame 60 on, every scan's ranges are shuffled across its beams
    corrupted = [
        f if f.index < 60 else _with_scan(f, f.scan.with_ranges(rng.permutation(f.scan.ranges)))
        for f in frames
    ]
    run = run_system("hector", corrupted, keep_all(frames))
    assert run.error == ""
    score = score_trajectory(run.poses, truth, lost_at_scan=run.lost_at_scan)
    assert score.failed
    assert run.lost_at_scan is not None and run.lost_at_scan >= 60


def test_a_system_that_raises_is_a_tracking_failure_not_a_crash(gentle_run):
    frames, truth = gentle_run
    wrong_masks = [np.zeros(3, dtype=bool)] * len(frames)  # not one value per beam
    run = run_system("hector", frames, wrong_masks)
    assert "ValueError" in run.error
    assert np.isnan(run.poses).all()
    score = score_trajectory(run.poses, truth, error=run.error)
    assert score.failed and score.failure.startswith("error: ValueError")


def _with_scan(frame, scan):
    import dataclasses

    return dataclasses.replace(frame, scan=scan)


@pytest.mark.parametrize("house_seed", [1, 2, 3])
def test_random_hard_stop_sequences_keep_the_robot_off_the_walls(house_seed):
    sequence = hard_stop_sequence(house_seed)
    stops = [c for c in sequence.scenario.commands if c.label == "hard stop"]
    assert len(stops) >= 3
    frames, summary = record_frames(sequence.scenario, seed=0)
    assert not summary.fell
    xy = np.array([f.truth.position_base_in_world[:2] for f in frames])
    assert Obstacles(sequence.house.parts()).is_free(xy, ROBOT_RADIUS_M).all()
    assert max(abs(np.degrees(f.truth.pitch_rad)) for f in frames) > 5.0  # real hard stops


def test_hard_stop_sequences_are_reproducible():
    a, b = hard_stop_sequence(5), hard_stop_sequence(5)
    assert a.scenario == b.scenario
    assert a.scenario != hard_stop_sequence(6).scenario
