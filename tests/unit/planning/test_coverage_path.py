"""Boustrophedon coverage (polynav.planning.coverage): lanes, headland, holes, swath modes."""

from __future__ import annotations

import math

import pytest

from polynav.errors import InvalidRequest
from polynav.planning import coverage
from polynav.planning.coverage import CoverageRequest

SQUARE = coverage.ring("border", [[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0], [0, 0, 0]])


def _inside(point: tuple[float, float], ring: coverage.Ring) -> bool:
    x, y = point
    inside = False
    for (x0, y0), (x1, y1) in zip(ring, [*ring[1:], ring[0]], strict=True):
        if (y0 > y) != (y1 > y) and x < x0 + (y - y0) * (x1 - x0) / (y1 - y0):
            inside = not inside
    return inside


def test_square_lanes_are_spacing_apart_and_alternate() -> None:
    path = coverage.coverage_path(CoverageRequest(SQUARE, spacing=1.0, swath_angle=0.0))
    assert len(path) == 20
    assert path[:4] == [(0.0, 0.5), (10.0, 0.5), (10.0, 1.5), (0.0, 1.5)]
    ys = sorted({round(y, 9) for _, y in path})
    assert ys == [k + 0.5 for k in range(10)]


def test_headland_keeps_lanes_off_the_edges() -> None:
    path = coverage.coverage_path(CoverageRequest(SQUARE, spacing=1.0, headland=0.5,
                                                  swath_angle=0.0))
    xs = [x for x, _ in path]
    assert min(xs) == pytest.approx(0.5) and max(xs) == pytest.approx(9.5)
    assert {round(y, 6) for _, y in path} == {k + 0.5 for k in range(10)}
    thick = coverage.coverage_path(CoverageRequest(SQUARE, spacing=1.0, headland=1.0,
                                                   swath_angle=0.0))
    assert min(y for _, y in thick) == pytest.approx(1.5)


def test_swaths_cover_the_worked_area() -> None:
    border = coverage.ring("border", [[0, 0], [8, 1], [9, 7], [3, 9], [-1, 5]])
    request = CoverageRequest(border, spacing=0.6, swath_angle=math.radians(30))
    lanes = coverage.lanes(request)
    d = (math.cos(math.radians(30)), math.sin(math.radians(30)))
    for i in range(40):
        for j in range(40):
            p = (-1 + 10 * i / 39, 10 * j / 39)
            if not _inside(p, border):
                continue
            best = min(
                abs((p[0] - a[0]) * -d[1] + (p[1] - a[1]) * d[0])
                for pieces in lanes for a, _ in pieces
            )
            assert best <= 0.3 + 1e-6, p


def test_holes_are_left_out() -> None:
    hole = coverage.ring("holes", [[4, 4], [6, 4], [6, 6], [4, 6]])
    request = CoverageRequest(SQUARE, holes=(hole,), spacing=1.0, swath_angle=0.0, step=0.25)
    path = coverage.coverage_path(request)
    assert not any(_inside(p, hole) and 4 < p[0] < 6 for p in path)
    lane = [p for p in path if abs(p[1] - 4.5) < 1e-9]
    assert min(x for x, _ in lane) == 0.0 and max(x for x, _ in lane) == 10.0
    pieces = coverage.lanes(request)[4]
    assert [(round(a[0], 6), round(b[0], 6)) for a, b in pieces] == [(0, 4), (6, 10)]


def test_swath_modes() -> None:
    rect = coverage.ring("border", [[0, 0], [10, 0], [10, 2], [0, 2]])
    assert coverage.lane_angle(CoverageRequest(rect, swath_angle=coverage.LONGEST_EDGE)) == 0.0
    shortest = coverage.lane_angle(CoverageRequest(rect, swath_angle=coverage.SHORTEST_EDGE))
    assert shortest == pytest.approx(math.pi / 2)
    assert coverage.lane_angle(CoverageRequest(rect, swath_angle=coverage.AUTO)) == 0.0
    tilted = coverage.ring("border", [[0, 0], [8, 6], [7.4, 6.8], [-0.6, 0.8]])
    auto = coverage.lane_angle(CoverageRequest(tilted, swath_angle=coverage.AUTO))
    assert auto == pytest.approx(math.atan2(6, 8))
    assert coverage.lane_angle(CoverageRequest(rect, swath_angle=math.radians(135))) == \
        pytest.approx(math.radians(135))


@pytest.mark.parametrize("points", [[[0, 0], [1, 1]], [[0, 0], [1, 1], [2, 2]],
                                    [[0, 0], [1, 0], [float("nan"), 1]]])
def test_bad_polygons_are_refused(points: list[list[float]]) -> None:
    with pytest.raises(InvalidRequest):
        coverage.ring("border", points)


def test_bad_spacing_and_headland_are_refused() -> None:
    with pytest.raises(InvalidRequest, match="op_width"):
        coverage.coverage_path(CoverageRequest(SQUARE, spacing=0.0))
    with pytest.raises(InvalidRequest, match="headland"):
        coverage.coverage_path(CoverageRequest(SQUARE, headland=-1.0))
    with pytest.raises(InvalidRequest, match="lanes"):
        coverage.coverage_path(CoverageRequest(SQUARE, spacing=1e-4))
