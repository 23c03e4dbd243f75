"""The improved pitch-variation filter: a sibling of the paper's, registered as ``improved``.

:class:`ImprovedPitchVariationFilter` is a :class:`pvfilter.ScanFilter` (``process(scan)``,
``reset()``; its result an :class:`ImprovedResult`), and optionally takes the robot's
pitch and roll from its IMU estimator and the LiDAR's pose from wheel odometry. Its
parameters (:class:`ImprovedParams`) are physical quantities; ``twsb tune`` fits them to
a robot and writes a file that :func:`load_params` reads (no simulator needed). How it
works: ``docs/improved_filter.md``.
"""

from pvfilter.improved.beams import BeamLayout
from pvfilter.improved.detection import LineDetection, detect_lines
from pvfilter.improved.evidence import free_space_gaps, new_points
from pvfilter.improved.filter import ImprovedPitchVariationFilter
from pvfilter.improved.memory import LevelMemory, LevelView
from pvfilter.improved.motion import Motion, estimate_motion
from pvfilter.improved.params import ImprovedParams
from pvfilter.improved.result import ImprovedResult, LineRecord
from pvfilter.improved.segmentation import Segments, segment_scan

__all__ = [
    "BeamLayout",
    "ImprovedParams",
    "ImprovedPitchVariationFilter",
    "ImprovedResult",
    "LevelMemory",
    "LevelView",
    "LineDetection",
    "LineRecord",
    "Motion",
    "Segments",
    "detect_lines",
    "estimate_motion",
    "free_space_gaps",
    "new_points",
    "segment_scan",
]
