"""A drawn route as a graph, and the shortest way along it between two places.

Users draw routes as ordered point lists (Galileo's path file: one ``x y z`` per line, with
repeated points, jumps back to earlier points and dense hand-drawn strokes). The graph has one
node per distinct point (points closer than ``merge`` are one node) and an edge between
consecutive points when they are at most ``max_edge`` apart, or when both are anchors (named
stops the user means to be joined); a longer jump between ordinary points starts a new stroke.
This is the recommended reading of galileo-http-b §1.4 (A-1): the document does not say how the
points join.

:func:`shortest_route` enters the graph at the node nearest the start and leaves it at the node
nearest the goal (Dijkstra on edge lengths), so a robot follows the drawn route instead of the
free-space shortest path. Pure functions; no I/O.
"""

from __future__ import annotations

import heapq
import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

log = logging.getLogger(__name__)

Point2 = tuple[float, float]


@dataclass(frozen=True, slots=True)
class RouteGraph:
    """Nodes ``(x, y)`` [m] and, per node, its neighbours with the edge length [m]."""

    nodes: tuple[Point2, ...]
    edges: dict[int, list[tuple[int, float]]] = field(default_factory=dict)

    def nearest(self, point: Point2) -> tuple[int, float]:
        """The node nearest ``point`` and its distance [m]."""
        best = min(range(len(self.nodes)), key=lambda i: math.dist(self.nodes[i], point))
        return best, math.dist(self.nodes[best], point)


def build(points: Sequence[Sequence[float]], *, anchors: Sequence[Point2] = (),
          merge: float = 0.01, max_edge: float = 1.0) -> RouteGraph:
    """The graph of a drawn route (see the module docstring).

    Args:
        points: the drawn points in order, ``(x, y[, z])`` [m].
        anchors: places [m] whose consecutive points join whatever their distance.
        merge: points closer than this [m] are one node.
        max_edge: the longest edge between ordinary consecutive points [m].
    """
    nodes: list[Point2] = []
    ids: list[int] = []
    cells: dict[tuple[int, int], list[int]] = {}  # a spatial hash: merging stays O(n)
    for p in points:
        xy = (float(p[0]), float(p[1]))
        cx, cy = math.floor(xy[0] / merge), math.floor(xy[1] / merge)
        found = next((i for dx in (-1, 0, 1) for dy in (-1, 0, 1)
                      for i in cells.get((cx + dx, cy + dy), ())
                      if math.dist(nodes[i], xy) < merge), None)
        if found is None:
            nodes.append(xy)
            found = len(nodes) - 1
            cells.setdefault((cx, cy), []).append(found)
        ids.append(found)
    anchor_nodes = {i for i, n in enumerate(nodes) if any(math.dist(n, a) < merge
                                                           for a in anchors)}
    edges: dict[int, list[tuple[int, float]]] = {i: [] for i in range(len(nodes))}
    for a, b in zip(ids, ids[1:], strict=False):
        if a == b:
            continue
        length = math.dist(nodes[a], nodes[b])
        if length <= max_edge or (a in anchor_nodes and b in anchor_nodes):
            if all(j != b for j, _ in edges[a]):
                edges[a].append((b, length))
                edges[b].append((a, length))
    return RouteGraph(tuple(nodes), edges)


def shortest_route(graph: RouteGraph, start: Point2, goal: Point2) -> list[Point2] | None:
    """The nodes from the one nearest ``start`` to the one nearest ``goal``, or ``None`` when
    the graph is empty or they are not connected."""
    if not graph.nodes:
        return None
    source, _ = graph.nearest(start)
    target, _ = graph.nearest(goal)
    dist = {source: 0.0}
    previous: dict[int, int] = {}
    heap = [(0.0, source)]
    while heap:
        d, node = heapq.heappop(heap)
        if node == target:
            break
        if d > dist.get(node, math.inf):
            continue
        for nxt, length in graph.edges.get(node, []):
            nd = d + length
            if nd < dist.get(nxt, math.inf):
                dist[nxt] = nd
                previous[nxt] = node
                heapq.heappush(heap, (nd, nxt))
    if target not in dist:
        return None
    route = [target]
    while route[-1] != source:
        route.append(previous[route[-1]])
    return [graph.nodes[i] for i in reversed(route)]


def waypoints(route: Sequence[Point2], spacing: float) -> list[Point2]:
    """``route`` thinned to points at least ``spacing`` [m] apart along it (corners sharper
    than 30° kept), always keeping the last point."""
    if not route:
        return []
    out = [route[0]]
    for i in range(1, len(route) - 1):
        prev, here, nxt = out[-1], route[i], route[i + 1]
        a = math.atan2(here[1] - prev[1], here[0] - prev[0])
        b = math.atan2(nxt[1] - here[1], nxt[0] - here[0])
        corner = abs(math.remainder(b - a, math.tau)) > math.radians(30)
        if math.dist(prev, here) >= spacing or (corner and math.dist(prev, here) > 0.05):
            out.append(here)
    if math.dist(out[-1], route[-1]) > 1e-9:
        out.append(route[-1])
    return out
