import numpy as np
import pytest

from scaneval.geometry import scan_points
from scaneval.synthetic import cluttered_room, scan_from_pose

TRUE_POSE = np.array([0.15, -0.10, np.radians(4.0)])  # source sensor in the target's frame


@pytest.fixture(scope="session")
def room_pair():
    """Points of two noisy scans of a cluttered room, the source taken at ``TRUE_POSE``.

    Both scans miss the 120 degree sector on their right, so the overlap is partial.
    """
    room = cluttered_room()
    target = scan_points(scan_from_pose(room, (0.0, 0.0, 0.0), rng=np.random.default_rng(1)))
    source = scan_points(scan_from_pose(room, TRUE_POSE, rng=np.random.default_rng(2)))
    return source, target, TRUE_POSE
