"""The collision region of an episode: its lane, with room for what the plan cannot foresee.

An episode's robot drives back and forth along one lane from its start pose (see
:mod:`twsb_sim.dataset.motion`), so the house's geoms far from that lane can leave
collision for a cheaper physics step with the same trajectory
(:mod:`twsb_sim.collision_region`). The region is the lane (margins already taken off)
grown by ``LANE_SLACK_M`` on every side, up to ``HEADROOM_M`` above the LiDAR's mounting
height. On 48 episodes of the default ranges the LiDAR origin strayed at most 0.95 m
sideways from the lane (a robot shoved over) and 0.84 m past its ends (hard stops), so an
episode rarely leaves it; one that does is simulated again with every geom in collision.
"""

from __future__ import annotations

from twsb_sim.collision_region import CollisionRegion
from twsb_sim.dataset.motion import Lane

LANE_SLACK_M = 1.0  # m, room around the lane, sideways and past its ends
HEADROOM_M = 0.5  # m, room above the LiDAR's mounting height
FLOOR_CLEARANCE_M = 1.0  # m, room below the floor (nothing collides there)


def lane_region(
    start: tuple[float, float, float], lane: Lane, lidar_height_m: float
) -> CollisionRegion:
    """The box the LiDAR origin stays in during an episode on ``lane``.

    Args:
        start: the start pose, ``(x m, y m, yaw rad)``; the lane runs along the yaw.
        lane: how far the robot may drive behind and ahead of the start.
        lidar_height_m: the LiDAR origin's height above the floor, robot upright.
    """
    x, y, yaw = start
    return CollisionRegion(
        origin_m=(x, y, 0.0),
        yaw_rad=yaw,
        lower_m=(-lane.behind_m - LANE_SLACK_M, -LANE_SLACK_M, -FLOOR_CLEARANCE_M),
        upper_m=(lane.ahead_m + LANE_SLACK_M, LANE_SLACK_M, lidar_height_m + HEADROOM_M),
    )
