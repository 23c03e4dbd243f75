"""The environments' parts on their own: scan encoding, reward, disturbances."""

from __future__ import annotations

import math

import numpy as np
import pytest

from twsb_sim.envs import Disturbances, RewardConfig, TwsbVelocityEnv
from twsb_sim.envs.disturbances import draw_hard_stop, draw_shove
from twsb_sim.envs.observation import encode_scan
from twsb_sim.envs.options import coerce
from twsb_sim.envs.reward import reward_terms


def test_scan_encoding_maps_rep117_into_the_box() -> None:
    ranges = np.array([np.inf, -np.inf, np.nan, 0.05, 3.5, 12.0])
    encoded = encode_scan(ranges, range_max_m=12.0)
    assert encoded.dtype == np.float32
    np.testing.assert_array_equal(encoded, np.float32([12.0, 0.0, 0.0, 0.05, 3.5, 12.0]))


def test_reward_is_best_when_tracking_upright_and_still() -> None:
    config = RewardConfig()
    best = reward_terms(config, 0.1, 0.0, 0.0, 0.0, 0.0, np.zeros(2), fell=False)
    assert best["reward_velocity"] == pytest.approx(config.velocity * 0.1)
    assert best["reward_yaw_rate"] == pytest.approx(config.yaw_rate * 0.1)
    assert sum(best.values()) == pytest.approx((config.velocity + config.yaw_rate) * 0.1)
    off = reward_terms(config, 0.1, 0.25, 0.0, 0.2, 1.0, np.array([1.0, -1.0]), fell=True)
    assert off["reward_velocity"] == pytest.approx(config.velocity * 0.1 / math.e)
    assert off["reward_pitch"] == pytest.approx(-config.pitch * 0.04 * 0.1)
    assert off["reward_torque"] == pytest.approx(-config.torque * 2.0 * 0.1)
    assert off["reward_fall"] == -config.fall


def test_disturbance_draws_follow_their_rates() -> None:
    rng = np.random.default_rng(0)
    config = Disturbances(shove_rate_hz=2.0, hard_stop_rate_hz=0.5)
    shoves = [draw_shove(config, rng, 0.1) for _ in range(20000)]
    stops = [draw_hard_stop(config, rng, 0.1) for _ in range(20000)]
    drawn = [s for s in shoves if s is not None]
    assert len(drawn) / 2000.0 == pytest.approx(2.0, rel=0.1)  # per simulated second
    assert sum(stops) / 2000.0 == pytest.approx(0.5, rel=0.15)
    magnitudes = [math.hypot(*s.force_heading_n[:2]) for s in drawn]
    assert 20.0 <= min(magnitudes) and max(magnitudes) <= 40.0
    # from behind or from the front, never more than the spread off the x axis
    angles = [abs(math.atan2(s.force_heading_n[1], abs(s.force_heading_n[0]))) for s in drawn]
    assert max(angles) <= math.radians(15.0) + 1e-9
    assert draw_shove(Disturbances(), rng, 0.1) is None


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"shove_rate_hz": -1.0}, "shove_rate_hz"),
        ({"shove_force_n": (50.0, 10.0)}, "shove_force_n"),
        ({"hard_stop_duration_s": math.nan}, "hard_stop_duration_s"),
    ],
)
def test_invalid_disturbances_name_the_field(kwargs: dict, field: str) -> None:
    with pytest.raises(ValueError, match=field):
        Disturbances(**kwargs)


def test_disturbances_from_a_dict_reject_unknown_keys() -> None:
    assert coerce(Disturbances, {"shove_force_n": [1.0, 2.0]}, "d").shove_force_n == (1.0, 2.0)
    with pytest.raises(ValueError, match="shove_rate"):
        coerce(Disturbances, {"shove_rate": 1.0}, "d")


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"control_period_s": 0.003}, "control_period_s"),
        ({"target_velocity_mps": 2.0}, "target_velocity_mps"),
        ({"house": "castle"}, "house"),
        ({"render_mode": "human"}, "render_mode"),
        ({"reward": "weights"}, "reward"),
    ],
)
def test_invalid_env_options_name_the_option(kwargs: dict, field: str) -> None:
    with pytest.raises(ValueError, match=field):
        TwsbVelocityEnv(**kwargs)
