from __future__ import annotations

import numpy as np
import numpy.typing as npt
import pytest

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.maps.keepout import (
    CircleZone,
    ForbiddenZone,
    GuidedZone,
    Keepout,
    VirtualWall,
    rasterize,
)
from polynav.maps.map import MapInfo

INFO = MapInfo(resolution=1.0, width=8, height=6)


def cells(mask: npt.NDArray[np.bool_]) -> set[tuple[int, int]]:
    """Covered cells as (ix, iy)."""
    return {(int(ix), int(iy)) for iy, ix in zip(*np.nonzero(mask), strict=True)}


def draw(*keepouts: Keepout, info: MapInfo = INFO) -> set[tuple[int, int]]:
    return cells(rasterize(keepouts, info))


def test_thin_wall_covers_the_one_row_it_runs_through() -> None:
    wall = VirtualWall(points=((0.5, 2.5), (5.5, 2.5)), thickness=0.0)
    assert draw(wall) == {(ix, 2) for ix in range(6)}


def test_thick_wall_covers_cells_within_half_thickness_with_round_caps() -> None:
    wall = VirtualWall(points=((0.5, 2.5), (5.5, 2.5)), thickness=2.0)
    row = {(ix, 2) for ix in range(7)}  # the cap reaches (6.5, 2.5), 1.0 past the end
    sides = {(ix, iy) for ix in range(6) for iy in (1, 3)}
    assert draw(wall) == row | sides


def test_diagonal_wall_is_a_four_connected_chain_without_diagonal_gaps() -> None:
    wall = VirtualWall(points=((0.5, 0.5), (3.5, 3.5)), thickness=0.0)
    assert draw(wall) == {(0, 0), (0, 1), (1, 1), (1, 2), (2, 2), (2, 3), (3, 3)}


def test_polyline_wall_draws_every_segment() -> None:
    wall = VirtualWall(points=((0.5, 0.5), (0.5, 2.5), (3.5, 2.5)))
    assert draw(wall) == {(0, 0), (0, 1), (0, 2), (1, 2), (2, 2), (3, 2)}


def test_wall_world_points_go_through_the_map_origin_and_resolution() -> None:
    info = MapInfo(resolution=0.5, width=8, height=6, origin=Pose2D(-2.0, 1.0, 0.0))
    wall = VirtualWall(points=((-1.9, 1.1), (-0.1, 1.1)))
    assert draw(wall, info=info) == {(0, 0), (1, 0), (2, 0), (3, 0)}


def test_zone_drawn_on_cell_borders_covers_exactly_the_cells_inside() -> None:
    square = ForbiddenZone(polygon=((1.0, 1.0), (4.0, 1.0), (4.0, 4.0), (1.0, 4.0)))
    assert draw(square) == {(ix, iy) for ix in range(1, 4) for iy in range(1, 4)}


def test_concave_zone_leaves_its_notch_free() -> None:
    # An L: the square [0, 4] x [0, 4] without its top-right quarter [2, 4] x [2, 4].
    ell = ForbiddenZone(polygon=((0, 0), (4, 0), (4, 2), (2, 2), (2, 4), (0, 4)))
    full = {(ix, iy) for ix in range(4) for iy in range(4)}
    notch = {(ix, iy) for ix in (2, 3) for iy in (2, 3)}
    assert draw(ell) == full - notch


def test_zone_thinner_than_a_cell_still_covers_the_cells_of_its_outline() -> None:
    sliver = ForbiddenZone(polygon=((1.1, 1.2), (3.9, 1.2), (3.9, 1.4), (1.1, 1.4)))
    assert draw(sliver) == {(1, 1), (2, 1), (3, 1)}


def test_circle_covers_cells_whose_centre_is_within_the_radius() -> None:
    plus = {(3, 3), (2, 3), (4, 3), (3, 2), (3, 4)}
    assert draw(CircleZone(x=3.5, y=3.5, radius=1.0)) == plus


def test_tiny_circle_still_covers_the_cell_holding_its_centre() -> None:
    assert draw(CircleZone(x=3.2, y=3.9, radius=0.1)) == {(3, 3)}


def test_guided_zone_covers_its_polygon_but_the_lane_along_its_route() -> None:
    band = ((0.0, 2.0), (8.0, 2.0), (8.0, 4.0), (0.0, 4.0))  # rows 2 and 3, all columns
    zone = GuidedZone(band, ((5.5, 0.5), (5.5, 5.5)), lane_width=1.0)
    lane = {(5, 2), (5, 3)}  # cell centres within 0.5 of x = 5.5
    assert draw(zone) == {(ix, iy) for ix in range(8) for iy in (2, 3)} - lane
    with pytest.raises(InvalidRequest, match="keepout.route"):
        GuidedZone(band, ((1.0, 1.0),))
    with pytest.raises(InvalidRequest, match="keepout.lane_width"):
        GuidedZone(band, ((1.0, 1.0), (2.0, 2.0)), lane_width=0.0)


def test_shapes_outside_the_map_are_clipped() -> None:
    wall = VirtualWall(points=((-5.0, 0.5), (2.5, 0.5)), thickness=0.0)
    zone = ForbiddenZone(polygon=((6.0, 4.0), (20.0, 4.0), (20.0, 20.0), (6.0, 20.0)))
    far = CircleZone(x=50.0, y=50.0, radius=1.0)
    expected = {(0, 0), (1, 0), (2, 0)} | {(6, 4), (7, 4), (6, 5), (7, 5)}
    assert draw(wall, zone, far) == expected


def test_points_given_as_lists_become_tuples_so_keepouts_are_hashable() -> None:
    wall = VirtualWall(points=[[0, 0], [1, 1]], thickness=0.2)  # type: ignore[arg-type]
    assert wall.points == ((0.0, 0.0), (1.0, 1.0))
    assert hash(wall) == hash(VirtualWall(points=((0.0, 0.0), (1.0, 1.0)), thickness=0.2))


@pytest.mark.parametrize(
    "make",
    [
        lambda: VirtualWall(points=()),
        lambda: VirtualWall(points=((0, 0), (1, 1)), thickness=-0.1),
        lambda: VirtualWall(points=((0, 0), (1,))),
        lambda: VirtualWall(points=((0, 0), (float("inf"), 1))),
        lambda: ForbiddenZone(polygon=((0, 0), (1, 1))),
        lambda: CircleZone(x=0.0, y=0.0, radius=0.0),
        lambda: CircleZone(x=float("nan"), y=0.0, radius=1.0),
    ],
    ids=[
        "no-points",
        "negative-thickness",
        "short-point",
        "infinite",
        "two-corners",
        "zero-radius",
        "nan-centre",
    ],
)
def test_malformed_keepouts_are_rejected(make: object) -> None:
    with pytest.raises(InvalidRequest):
        make()  # type: ignore[operator]
