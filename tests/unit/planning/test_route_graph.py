"""Drawn routes as graphs (polynav.planning.route_graph): merging, strokes, anchors, shortest."""

from __future__ import annotations

import math

from polynav.planning import route_graph


def test_repeated_points_merge_and_far_jumps_split_strokes() -> None:
    points = [(0, 0, 0), (0.5, 0, 0), (0.5, 0, 0), (1.0, 0, 0), (5, 5, 0), (5.5, 5, 0)]
    graph = route_graph.build(points)
    assert len(graph.nodes) == 5
    assert route_graph.shortest_route(graph, (0, 0), (5.5, 5)) is None  # two strokes
    anchored = route_graph.build(points, anchors=[(1.0, 0.0), (5.0, 5.0)])
    way = route_graph.shortest_route(anchored, (0, 0), (5.5, 5))
    assert way == [(0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (5.0, 5.0), (5.5, 5.0)]


def test_shortest_route_takes_the_shorter_branch() -> None:
    # A square loop drawn once round: from one corner the way to the opposite corner is
    # either side; a shortcut across is drawn too.
    loop = [(x * 0.5, 0) for x in range(9)] + [(4, y * 0.5) for y in range(1, 9)] + \
        [(4 - x * 0.5, 4) for x in range(1, 9)] + [(0, 4 - y * 0.5) for y in range(1, 9)]
    graph = route_graph.build([(x, y, 0) for x, y in loop])
    way = route_graph.shortest_route(graph, (0.1, 0.1), (4, 4))
    assert way is not None and way[0] == (0.0, 0.0) and way[-1] == (4.0, 4.0)
    length = sum(math.dist(a, b) for a, b in zip(way, way[1:], strict=False))
    assert math.isclose(length, 8.0)


def test_waypoints_keep_spacing_corners_and_the_end() -> None:
    way = [(x * 0.1, 0.0) for x in range(31)] + [(3.0, y * 0.1) for y in range(1, 11)]
    points = route_graph.waypoints(way, 1.0)
    assert points[0] == (0.0, 0.0) and points[-1] == (3.0, 1.0)
    assert (3.0, 0.0) in [(round(x, 6), round(y, 6)) for x, y in points]
    assert all(math.dist(a, b) > 0.05 for a, b in zip(points, points[1:], strict=False))
