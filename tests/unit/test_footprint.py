from __future__ import annotations

import math

import numpy as np
import pytest

from polynav import footprint as fp_mod
from polynav.errors import ConfigError
from polynav.footprint import Footprint
from polynav.footprint.outline import signed_area
from polynav.geometry import Pose2D
from polynav.maps import costs
from tests.unit.control.unicycle import Grid, empty_grid

RECT = Footprint.rectangle(0.5, 0.3)  # 0.5 m long, 0.3 m wide, centred on the origin


def grid_with_cells(cells: list[tuple[int, int]], value: int = costs.LETHAL) -> Grid:
    """A 4 m grid at 0.05 m from (-2, -2), with ``value`` in the given (ix, iy) cells."""
    grid = empty_grid(size_m=4.0, resolution=0.05)
    for ix, iy in cells:
        grid.costs[iy, ix] = value
    return grid


def cell_at(x: float, y: float) -> tuple[int, int]:
    """The cell holding world (x, y) on :func:`grid_with_cells`' grid."""
    return (math.floor((x + 2.0) / 0.05), math.floor((y + 2.0) / 0.05))


# --- validation ---------------------------------------------------------------------------------


def test_circle_radii_are_its_radius() -> None:
    fp = Footprint.circle(0.25)
    assert fp.is_circle
    assert (fp.inscribed_radius, fp.circumscribed_radius) == (0.25, 0.25)


def test_rectangle_radii_are_half_width_and_half_diagonal() -> None:
    assert not RECT.is_circle
    assert RECT.inscribed_radius == pytest.approx(0.15)
    assert RECT.circumscribed_radius == pytest.approx(math.hypot(0.25, 0.15))


def test_offset_rectangle_radii_are_measured_from_the_base_origin() -> None:
    fp = Footprint.rectangle(0.6, 0.4, offset_x=0.1)  # x from -0.2 to 0.4
    assert fp.inscribed_radius == pytest.approx(0.2)
    assert fp.circumscribed_radius == pytest.approx(math.hypot(0.4, 0.2))


def test_clockwise_polygon_is_stored_counter_clockwise() -> None:
    fp = Footprint.polygon([(1, 1), (1, -1), (-1, -1), (-1, 1)])
    assert signed_area(fp.vertices) > 0
    assert fp == Footprint.polygon([(-1, 1), (-1, -1), (1, -1), (1, 1)])


def test_vertices_are_read_only() -> None:
    with pytest.raises(ValueError):
        RECT.vertices[0, 0] = 5.0


@pytest.mark.parametrize(
    ("vertices", "reason"),
    [
        ([(1, 0), (0, 1)], "at least 3 vertices"),
        ([(1, 1), (-1, 1), (-1, 1), (-1, -1), (1, -1)], "coincide"),
        ([(1, 1), (-1, 1), (-1, -1), (1, -1), (-1, -1)], "self-intersecting"),
        ([(1, 1), (-1, -1), (-1, 1), (1, -1)], "self-intersecting"),  # a bow tie
        ([(2, 1), (3, 1), (3, 2), (2, 2)], "contain the base origin"),
        ([(0, 0), (1, 0), (2, 0)], "self-intersecting"),  # a line folds back on itself
        ([(1, float("nan")), (-1, 1), (-1, -1)], "finite"),
        ([(1, 2, 3), (4, 5, 6), (7, 8, 9)], "[x, y] pairs"),
        ("abc", "[x, y] pairs"),
    ],
)
def test_bad_polygons_are_refused_naming_the_field(vertices: object, reason: str) -> None:
    with pytest.raises(ConfigError, match=r"robot\.footprint\.vertices") as err:
        Footprint.polygon(vertices, key="robot.footprint")  # type: ignore[arg-type]
    assert reason in err.value.reason


def test_polygon_folding_back_on_its_neighbour_edge_is_self_intersecting() -> None:
    # Edges 2 and 3 run up and then back down the same line.
    with pytest.raises(ConfigError, match="self-intersecting"):
        Footprint.polygon([(-1, -1), (1, -1), (1, 1), (1, -0.5), (-1, 1)])


@pytest.mark.parametrize("radius", [0.0, -0.1, float("inf"), float("nan")])
def test_bad_circles_are_refused(radius: float) -> None:
    with pytest.raises(ConfigError, match=r"footprint\.radius"):
        Footprint.circle(radius)


def test_bad_rectangle_sides_are_refused() -> None:
    with pytest.raises(ConfigError, match=r"footprint\.width"):
        Footprint.rectangle(0.5, -0.3)


def test_non_convex_polygon_is_accepted() -> None:
    # An L-shaped body with the origin in its corner block.
    fp = Footprint.polygon([(-0.2, -0.2), (0.6, -0.2), (0.6, 0.1), (0.1, 0.1), (0.1, 0.5),
                            (-0.2, 0.5)])
    assert fp.inscribed_radius == pytest.approx(math.hypot(0.1, 0.1))  # the inner corner
    assert fp.circumscribed_radius == pytest.approx(math.hypot(0.6, 0.2))


# --- placement ----------------------------------------------------------------------------------


def test_outline_is_placed_at_the_pose() -> None:
    out = RECT.outline(Pose2D(1.0, 2.0, math.pi / 2))
    np.testing.assert_allclose(
        out, [[0.85, 2.25], [0.85, 1.75], [1.15, 1.75], [1.15, 2.25]], atol=1e-12
    )


def test_contains_point_follows_heading() -> None:
    pose = Pose2D(1.0, 0.0, math.pi / 2)  # long axis along world y
    assert RECT.contains_point(pose, 1.0, 0.24)
    assert not RECT.contains_point(pose, 1.24, 0.0)
    assert Footprint.circle(0.2).contains_point(pose, 1.1, 0.1)


def test_covers() -> None:
    body = RECT
    assert Footprint.circle(0.30).covers(body)
    assert not Footprint.circle(0.25).covers(body)
    assert Footprint.rectangle(0.6, 0.4).covers(body)
    assert not Footprint.rectangle(0.6, 0.28).covers(body)
    assert body.covers(Footprint.circle(0.15))
    assert not body.covers(Footprint.circle(0.16))
    assert body.covers(body)


# --- collision ----------------------------------------------------------------------------------


def test_free_grid_never_collides() -> None:
    grid = empty_grid(size_m=4.0, resolution=0.05)
    assert not fp_mod.collides(RECT, grid, Pose2D(0.3, 0.1, 0.7))


def test_rectangle_hits_a_cell_ahead_but_not_the_same_cell_beside() -> None:
    # A one-cell post whose square spans x in [0.25, 0.30]: the nose at x = 0.25 touches it.
    grid = grid_with_cells([cell_at(0.27, 0.0)])
    assert fp_mod.collides(RECT, grid, Pose2D(0.0, 0.0, 0.0))
    assert not fp_mod.collides(RECT, grid, Pose2D(-0.01, 0.0, 0.0))
    # Turned a quarter, the half width (0.15 m) is far from it.
    assert not fp_mod.collides(RECT, grid, Pose2D(0.0, 0.0, math.pi / 2))


def test_rotated_grid_origin_is_honoured() -> None:
    # A grid rotated a quarter turn: its cell (ix, iy) lies at world (-(iy+.5)r, (ix+.5)r).
    base = empty_grid(size_m=4.0, resolution=0.05)
    info = base.info.__class__(0.05, 80, 80, Pose2D(2.0, -2.0, math.pi / 2))
    grid = Grid(info, base.costs)
    ix, iy = info.world_to_cell(0.27, 0.0)
    grid.costs[iy, ix] = costs.LETHAL
    assert fp_mod.collides(RECT, grid, Pose2D(0.0, 0.0, 0.0))
    assert not fp_mod.collides(RECT, grid, Pose2D(0.0, 0.0, math.pi / 2))


def test_overlapped_cells_are_the_lethal_cells_under_the_body_on_a_rotated_grid() -> None:
    base = empty_grid(size_m=4.0, resolution=0.05)
    info = base.info.__class__(0.05, 80, 80, Pose2D(2.0, -2.0, math.pi / 2))
    grid = Grid(info, base.costs)
    nose, beside = info.world_to_cell(0.22, 0.0), info.world_to_cell(0.0, 0.22)
    for ix, iy in (nose, beside):
        grid.costs[iy, ix] = costs.LETHAL
    assert fp_mod.overlapped_cells(RECT, grid, Pose2D(0.0, 0.0, 0.0)).tolist() == [list(nose)]
    assert fp_mod.overlapped_cells(RECT, grid, Pose2D(0.0, 0.0, math.pi / 2)).tolist() == [
        list(beside)]


def test_only_lethal_cells_are_obstacles_unless_unknown_is_asked_for() -> None:
    grid = grid_with_cells([cell_at(0.2, 0.0)], value=costs.INSCRIBED)
    assert not fp_mod.collides(RECT, grid, Pose2D())
    unknown = grid_with_cells([cell_at(0.2, 0.0)], value=costs.UNKNOWN)
    assert not fp_mod.collides(RECT, unknown, Pose2D())
    assert fp_mod.collides(RECT, unknown, Pose2D(), unknown_is_lethal=True)


def test_off_grid_is_free_unless_unknown_is_lethal() -> None:
    grid = empty_grid(size_m=4.0, resolution=0.05)
    edge = Pose2D(1.9, 0.0, 0.0)  # the nose pokes 0.15 m past the grid's edge
    assert not fp_mod.collides(RECT, grid, edge)
    assert fp_mod.collides(RECT, grid, edge, unknown_is_lethal=True)


def test_circle_collision_is_exact_to_the_cell_square() -> None:
    grid = grid_with_cells([cell_at(0.52, 0.02)])  # square [0.50, 0.55] x [0.0, 0.05]
    circle = Footprint.circle(0.25)
    assert fp_mod.collides(circle, grid, Pose2D(0.25, 0.0, 0.0))
    assert not fp_mod.collides(circle, grid, Pose2D(0.24, 0.0, 0.0))


def test_first_collision_along_poses() -> None:
    grid = grid_with_cells([cell_at(1.02, 0.0)])  # square [1.00, 1.05] x [0.0, 0.05]
    xs = np.arange(0.0, 1.5, 0.025)
    poses = np.column_stack((xs, np.zeros_like(xs), np.zeros_like(xs)))
    hit = fp_mod.first_collision(RECT, grid, poses)
    assert hit is not None
    # The nose (x + 0.25) first reaches the cell's near face at x = 0.75 m.
    assert xs[hit] == pytest.approx(0.75)
    assert fp_mod.first_collision(RECT, grid, poses[:hit]) is None
    mask = fp_mod.collision_mask(RECT, grid, poses)
    assert int(np.flatnonzero(mask)[0]) == hit
    assert fp_mod.first_collision(RECT, grid, np.zeros((0, 3))) is None


def test_turn_in_place_sweeps_the_corners() -> None:
    # A post 0.2 m to the left of centre: clear of the 0.15 m half width at rest, but the
    # long sides (0.25 m out) sweep through it on a half turn, which ends clear again.
    grid = grid_with_cells([cell_at(0.02, 0.22)])
    start = Pose2D(0.0, 0.0, 0.0)
    assert not fp_mod.collides(RECT, grid, start)
    assert not fp_mod.collides(RECT, grid, Pose2D(0.0, 0.0, math.pi))
    sweep = fp_mod.rotation_poses(RECT, start, math.pi, 0.05)
    assert np.max(np.abs(np.diff(sweep[:, 2]))) * RECT.circumscribed_radius <= 0.025 + 1e-12
    assert fp_mod.first_collision(RECT, grid, sweep) is not None
    # A circle of the inscribed radius turns freely: the disk does not change as it turns.
    disk = Footprint.circle(RECT.inscribed_radius)
    assert fp_mod.first_collision(disk, grid, fp_mod.rotation_poses(disk, start, 3.0, 0.05)) is None


def test_clearance_measures_the_gap_to_the_nearest_lethal_cell() -> None:
    grid = grid_with_cells([cell_at(0.62, 0.0)])  # near face at x = 0.60
    assert fp_mod.clearance(RECT, grid, Pose2D(), horizon=1.0) == pytest.approx(0.35)
    assert fp_mod.clearance(RECT, grid, Pose2D(), horizon=0.2) == pytest.approx(0.2)
    assert fp_mod.clearance(RECT, grid, Pose2D(0.36, 0.0, 0.0), horizon=1.0) == 0.0
    disk = Footprint.circle(0.25)
    assert fp_mod.clearance(disk, grid, Pose2D(), horizon=1.0) == pytest.approx(0.35)
    many = fp_mod.clearances(
        RECT, grid, np.array([[0.0, 0.0, 0.0], [0.0, 0.0, math.pi / 2]]), horizon=1.0
    )
    assert many.tolist() == pytest.approx([0.35, 0.45])


def test_clearance_agrees_with_brute_force_on_random_scenes() -> None:
    rng = np.random.default_rng(3)
    body = Footprint.polygon([(0.3, 0.0), (0.1, 0.2), (-0.2, 0.15), (-0.2, -0.15), (0.1, -0.2)])
    for _ in range(20):
        cells = [(int(rng.integers(20, 60)), int(rng.integers(20, 60))) for _ in range(6)]
        grid = grid_with_cells(cells)
        pose = Pose2D(float(rng.uniform(-0.5, 0.5)), float(rng.uniform(-0.5, 0.5)),
                      float(rng.uniform(-math.pi, math.pi)))
        # Brute force: sample every cell's square densely, and the outline densely.
        outline = body.outline(pose)
        dense = np.concatenate([np.linspace(outline[i], outline[(i + 1) % 5], 200)
                                for i in range(5)])
        best = 1.0
        hit = False
        for ix, iy in cells:
            u = np.linspace(0.0, 0.05, 21)
            sq = np.array([(-2.0 + ix * 0.05 + a, -2.0 + iy * 0.05 + b) for a in u for b in u])
            hit |= any(body.contains_point(pose, float(x), float(y)) for x, y in sq)
            d = np.min(np.hypot(dense[:, None, 0] - sq[None, :, 0],
                                dense[:, None, 1] - sq[None, :, 1]))
            best = min(best, float(d))
        got = fp_mod.clearance(body, grid, pose, horizon=1.0)
        assert fp_mod.collides(body, grid, pose) == (hit or best < 1e-9)
        if not hit:
            assert got == pytest.approx(best, abs=0.004)


def test_warm_up_runs() -> None:
    fp_mod.warm_up()


def test_a_padded_footprint_moves_every_edge_out_by_the_margin() -> None:
    rect = Footprint.rectangle(0.51, 0.43).padded(0.05)
    np.testing.assert_allclose(np.sort(np.abs(rect.vertices), axis=0)[-1], [0.305, 0.265])
    assert rect.inscribed_radius == pytest.approx(0.265)
    assert Footprint.circle(0.25).padded(0.05).radius == pytest.approx(0.30)
    triangle = Footprint.polygon([[0.3, 0.0], [-0.1, 0.2], [-0.1, -0.2]])
    grown = triangle.padded(0.02)
    assert grown.inscribed_radius == pytest.approx(triangle.inscribed_radius + 0.02)
