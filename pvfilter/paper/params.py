"""The paper filter's parameters, named with the paper's symbols (Table I defaults)."""

from __future__ import annotations

import dataclasses
from typing import Literal

from pvfilter.checks import check_flag, check_integer, check_number

ClusteringMode = Literal["scan_order", "radius"]
CLUSTERING_MODES: tuple[str, ...] = ("scan_order", "radius")


@dataclasses.dataclass(frozen=True)
class FilterParams:
    """Parameters of the Pitch Variation Filter; defaults are the paper's Table I.

    Invalid values raise ``ValueError("<field>: <what was expected>, got <value>")``.

    Attributes:
        d_th: clustering distance, m (preprocessing). Two points closer than this join the
            same cluster. Larger merges more of the scan into fewer clusters.
        m_th: minimum cluster size, points (preprocessing). Clusters with fewer points are
            dropped as noise and never removed. Raise it for denser LiDARs (paper IV-B).
        v_th: perpendicular variance ratio threshold, 1 (detection and tracking). Clusters
            with ``v_C = v_y / (v_x + v_y) < v_th`` (eq. 1) are not lines across the
            direction of travel and are skipped. Higher suppresses false positives.
        sigma_theta: spread of the angular confidence P(theta_C), 1 (detection, eq. 2;
            ``cos^2`` is unitless). Smaller makes clusters ahead and behind count more as
            pitch variation; larger is more tolerant of noise but may miss clusters.
        sigma_l: spread of the likelihood field P(L_C), m (detection, eq. 3). Smaller flags
            smaller displacements from the previous scan as new; larger is more robust to
            noise but may miss clusters.
        p_th: detection threshold on P(C_pv), 1 (detection, eq. 5). A cluster is detected
            when ``P(C_pv) > p_th``. Lower removes more.
        d_track: association gate, m (tracking). A cluster follows the nearest queued
            cluster of the previous scan when their centroids are at most this far apart.
            ``inf`` disables the gate.
        d_min: nearest plausible centroid range of a tracked cluster, m (tracking).
        d_max: farthest plausible centroid range of a tracked cluster, m (tracking).
            Floor and ceiling hits fall in a radial band; tracked clusters outside
            ``[d_min, d_max]`` leave the queue. Detection does not apply this check.
        size_ratio_min: smallest accepted size ratio (current / associated previous
            cluster), 1 (tracking). Table I writes it as Delta m_th = (m/2, 2m).
        size_ratio_max: largest accepted size ratio, 1 (tracking). A tracked cluster whose
            size jumps outside ``[size_ratio_min, size_ratio_max]`` leaves the queue.
        clustering: ``"scan_order"`` (default, the paper's sweep from the first index) or
            ``"radius"`` (all neighbours within ``d_th``); see :mod:`pvfilter.clustering`.
        tracking: run the tracking module (Algorithm 2). ``False`` is the paper's
            detection-only variant: only clusters detected in this scan are removed.
    """

    d_th: float = 0.3  # m
    m_th: int = 10  # points
    v_th: float = 0.65  # 1
    sigma_theta: float = 1.0  # 1
    sigma_l: float = 1.0  # m
    p_th: float = 0.8  # 1
    d_track: float = 1.5  # m
    d_min: float = 0.3  # m
    d_max: float = 2.0  # m
    size_ratio_min: float = 0.5  # 1
    size_ratio_max: float = 2.0  # 1
    clustering: ClusteringMode = "scan_order"
    tracking: bool = True

    def __post_init__(self) -> None:
        check_number("d_th", self.d_th, lower=0.0, unit="m")
        check_integer("m_th", self.m_th, 1)
        check_number("v_th", self.v_th, lower=0.0, upper=1.0, closed=True)
        check_number("sigma_theta", self.sigma_theta, lower=0.0)
        check_number("sigma_l", self.sigma_l, lower=0.0, unit="m")
        check_number("p_th", self.p_th, lower=0.0, upper=1.0, closed=True)
        check_number("d_track", self.d_track, lower=0.0, unit="m", infinite=True)
        check_number("d_min", self.d_min, lower=0.0, unit="m", closed=True)
        check_number("d_max", self.d_max, lower=self.d_min, unit="m", infinite=True, below="d_min")
        check_number("size_ratio_min", self.size_ratio_min, lower=0.0)
        check_number(
            "size_ratio_max",
            self.size_ratio_max,
            lower=self.size_ratio_min,
            closed=True,
            infinite=True,
            below="size_ratio_min",
        )
        if self.clustering not in CLUSTERING_MODES:
            choices = ", ".join(CLUSTERING_MODES)
            raise ValueError(f"clustering: must be one of {choices}, got {self.clustering!r}")
        check_flag("tracking", self.tracking)
