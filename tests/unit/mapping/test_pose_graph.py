from __future__ import annotations

import math

import numpy as np

from polynav.geometry import Pose2D
from polynav.mapping.pose_graph import PoseGraph, edge_residuals


def _square_truth() -> list[Pose2D]:
    """16 poses, 1 m apart, counter-clockwise around a 4 m square, back at the start."""
    poses = [Pose2D()]
    for k in range(16):
        step = Pose2D(1.0, 0.0, math.pi / 2 if k % 4 == 3 else 0.0)
        poses.append(poses[-1].compose(step))
    return poses


def _drifting_graph(*, loop: bool, outlier: bool = False) -> tuple[PoseGraph, list[Pose2D]]:
    truth = _square_truth()
    graph = PoseGraph()
    estimate = Pose2D()
    graph.add_node(0.0, 0.0, 0.0)
    for k in range(1, len(truth)):
        rel = truth[k].relative_to(truth[k - 1])
        # Odometry turns 3° too far and reads 5 % long at every step.
        drifted = Pose2D(1.05 * rel.x, 1.05 * rel.y, rel.theta + math.radians(3.0))
        estimate = estimate.compose(drifted)
        graph.add_node(estimate.x, estimate.y, estimate.theta)
        graph.add_edge(k - 1, k, (drifted.x, drifted.y, drifted.theta), (0.03, 0.03, 0.01))
    if loop:
        # The last pose is the first one again, seen exactly, and node 8 seen from node 0.
        graph.add_edge(0, 16, (0.0, 0.0, 0.0), (0.01, 0.01, 0.005), robust=True)
        rel = truth[8].relative_to(truth[0])
        graph.add_edge(0, 8, (rel.x, rel.y, rel.theta), (0.01, 0.01, 0.005), robust=True)
    if outlier:
        graph.add_edge(0, 4, (2.0, -3.0, 1.0), (0.01, 0.01, 0.005), robust=True)
    return graph, truth


def _worst_error(graph: PoseGraph, truth: list[Pose2D]) -> float:
    return max(math.hypot(p[0] - t.x, p[1] - t.y) for p, t in zip(graph.poses, truth,
                                                                     strict=True))


def test_residual_is_zero_for_a_consistent_edge() -> None:
    a, b = Pose2D(1.0, 2.0, 0.5), Pose2D(-1.0, 0.5, -2.9)
    rel = b.relative_to(a)
    r = edge_residuals(np.array([[a.x, a.y, a.theta], [b.x, b.y, b.theta]]), np.array([0]),
                       np.array([1]), np.array([[rel.x, rel.y, rel.theta]]))
    assert np.abs(r).max() < 1e-12


def test_square_loop_with_drift_is_corrected_by_the_loop_closure() -> None:
    graph, truth = _drifting_graph(loop=True)
    before = _worst_error(graph, truth)
    graph.optimize(huber_scale=2.0)
    after = _worst_error(graph, truth)
    assert before > 2.0
    assert after < 0.25  # the odometry disagrees with itself: 0.17 m at the optimum
    assert graph.poses[0] == (0.0, 0.0, 0.0)  # the first node is the fixed gauge


def test_without_a_loop_closure_the_drift_stays() -> None:
    graph, truth = _drifting_graph(loop=False)
    graph.optimize(huber_scale=2.0)
    assert _worst_error(graph, truth) > 2.0


def test_one_false_loop_closure_does_not_wreck_the_graph() -> None:
    graph, truth = _drifting_graph(loop=True, outlier=True)
    assert graph.optimize(huber_scale=2.0) == 1
    assert _worst_error(graph, truth) < 0.25
