"""Preprocessing: BFS clustering in scan order or by radius, m_th, cluster moments, KD-tree."""

import math

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from pvfilter import FilterParams, Scan
from pvfilter.paper.clustering import (
    cluster_scan,
    covers_full_turn,
    drop_small_clusters,
    radius_labels,
    scan_order_labels,
)
from pvfilter.synthetic import cross_line, room_segments, segment_scan


def test_scan_order_starts_a_new_cluster_where_the_step_exceeds_d_th():
    points = np.array([[0.0, 0.0], [0.25, 0.0], [0.5, 0.0], [1.5, 0.0], [1.75, 0.0]])
    assert scan_order_labels(points, d_th=0.5).tolist() == [0, 0, 0, 1, 1]
    # a step of exactly d_th still joins ("within d_th")
    assert scan_order_labels(points, d_th=1.0).tolist() == [0, 0, 0, 0, 0]


def test_ring_joins_the_last_run_to_the_first():
    points = np.array([[1.0, 0.0], [1.0, 0.25], [5.0, 5.0], [1.0, -0.25]])
    assert scan_order_labels(points, d_th=0.5).tolist() == [0, 0, 1, 2]
    assert scan_order_labels(points, d_th=0.5, ring=True).tolist() == [0, 0, 1, 0]


def test_radius_mode_joins_neighbours_that_are_apart_in_scan_order():
    points = np.array([[0.0, 0.0], [5.0, 0.0], [0.25, 0.0]])
    assert scan_order_labels(points, d_th=0.5).tolist() == [0, 1, 2]
    assert radius_labels(cKDTree(points), d_th=0.5).tolist() == [0, 1, 0]


def test_clusters_smaller_than_m_th_are_dropped_and_the_rest_renumbered():
    labels = np.array([0, 0, 0, 1, 2, 2, 2])
    assert drop_small_clusters(labels, m_th=3).tolist() == [0, 0, 0, -1, 1, 1, 1]
    assert drop_small_clusters(labels, m_th=1).tolist() == labels.tolist()


def test_full_turn_scans_are_rings():
    def scan(beams, increment_deg):
        return Scan(
            ranges=np.ones(beams),
            angle_min=-math.pi,
            angle_increment=math.radians(increment_deg),
            range_min=0.1,
            range_max=5.0,
        )

    assert covers_full_turn(scan(720, 0.5))
    assert covers_full_turn(scan(719, 0.5))  # one missing beam
    assert not covers_full_turn(scan(480, 0.5))  # a 240 degree field of view


def test_invalid_beams_never_join_but_do_not_split_a_cluster():
    ranges = np.full(40, 1.0)
    ranges[[3, 10, 20, 30]] = [np.nan, np.inf, -np.inf, 0.01]  # 0.01 < range_min
    scan = Scan(ranges=ranges, angle_min=-0.2, angle_increment=0.01, range_min=0.05, range_max=5.0)
    clusters = cluster_scan(scan, FilterParams())
    assert clusters.labels[[3, 10, 20, 30]].tolist() == [-1, -1, -1, -1]
    assert len(clusters) == 1 and clusters.sizes.tolist() == [36]


@pytest.mark.parametrize("mode", ["scan_order", "radius"])
def test_line_and_walls_give_separate_clusters_with_numpy_moments(mode):
    segments = np.concatenate((room_segments(5.0, 5.0, 3.0, 3.0), cross_line(1.0, 0.5)))
    scan = segment_scan(segments)
    clusters = cluster_scan(scan, FilterParams(clustering=mode))
    assert len(clusters) == 2  # the room's closed wall loop, and the line
    for index, members in enumerate(clusters.beam_indices()):
        assert (clusters.labels[members] == index).all()
        points = scan.points()[members]
        assert clusters.sizes[index] == len(members)
        np.testing.assert_allclose(clusters.centroids[index], points.mean(axis=0), atol=1e-12)
        np.testing.assert_allclose(clusters.variances[index], points.var(axis=0), atol=1e-12)
    line = clusters.labels[360]  # beam 360 points straight ahead
    np.testing.assert_allclose(clusters.centroids[line], [1.0, 0.0], atol=1e-9)


def test_kd_tree_holds_every_valid_point_clustered_or_not():
    ranges = np.array([1.0, np.nan, 1.0, 3.0])
    scan = Scan(ranges=ranges, angle_min=0.0, angle_increment=0.01, range_min=0.05, range_max=5.0)
    clusters = cluster_scan(scan, FilterParams())
    assert len(clusters) == 0  # all smaller than m_th
    assert clusters.tree.n == 3


def test_radius_labels_are_the_connected_components_of_the_radius_graph():
    rng = np.random.default_rng(1)
    for _ in range(50):
        points = rng.uniform(0.0, rng.uniform(0.5, 8.0), size=(rng.integers(0, 150), 2))
        tree = cKDTree(points)
        pairs = tree.query_pairs(0.3, output_type="ndarray")
        graph = coo_matrix((np.ones(len(pairs)), pairs.T), shape=(len(points), len(points)))
        reference = connected_components(graph, directed=False)[1]
        labels = radius_labels(tree, 0.3)
        # the same partition, numbered in order of first point
        same_cluster = labels[:, None] == labels[None, :]
        np.testing.assert_array_equal(same_cluster, reference[:, None] == reference[None, :])
        first_points = np.unique(labels, return_index=True)[1]
        assert (np.diff(first_points) > 0).all()
