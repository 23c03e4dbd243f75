"""The Rerun logger records an env's episodes: it is a sink like any other."""

from __future__ import annotations

from pathlib import Path

import gymnasium as gym
import numpy as np
import pytest

from twsb_sim.envs import VELOCITY_ID, Disturbances

rr = pytest.importorskip("rerun")
rerun_log = pytest.importorskip("twsb_sim.rerun_log")


def test_rerun_logger_records_episodes_with_states_filter_and_shoves(tmp_path: Path) -> None:
    from rerun.chunk import RrdReader

    path = tmp_path / "episode.rrd"
    rec = rr.RecordingStream(rerun_log.APPLICATION_ID)
    rec.save(path)
    logger = rerun_log.RerunLogger(rec, state_rate_hz=50.0)
    env = gym.make(
        VELOCITY_ID,
        sink=logger,
        scan_filter=True,
        target_velocity_mps=0.8,
        disturbances=Disturbances(shove_rate_hz=1.0, hard_stop_rate_hz=1.0),
    )
    for seed in (0, 1):  # two episodes, one after the other in the recording
        env.reset(seed=seed)
        for _ in range(20):
            env.step(np.array([0.8, 0.0], dtype=np.float32))
    env.close()
    rec.disconnect()  # finishes the file (its footer)
    entities = {str(chunk.entity_path) for chunk in RrdReader(path).stream().to_chunks()}
    for entity in (
        rerun_log.paths.HOUSE_WALLS,
        rerun_log.paths.ROBOT,
        rerun_log.paths.LIDAR_HITS,
        rerun_log.paths.SENSOR_DECISION,
        rerun_log.paths.PLOT_PITCH,
        rerun_log.paths.EVENTS,
    ):
        assert "/" + entity in entities
