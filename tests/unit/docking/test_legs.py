"""The legs detector on synthetic scans: a cart found off where it should stand, nothing found
where there are no legs, or only two, or a box."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from polynav.docking.legs import LegsConfig, find_legs, leg_candidates
from polynav.errors import ConfigError
from polynav.geometry import Pose2D, angle_diff
from polynav.worlds.carts import leg_positions

LENGTH, WIDTH, R = 0.9, 0.7, 0.03


def _scan(origin: tuple[float, float], circles: list[tuple[float, float, float]],
          walls: list[tuple[float, float, float, float]] = (),  # type: ignore[assignment]
          noise: float = 0.005, seed: int = 1) -> npt.NDArray[np.float64]:
    """Endpoints of a 360-beam scan from ``origin`` against circles and wall segments."""
    rng = np.random.default_rng(seed)
    ox, oy = origin
    out = []
    for a in np.arange(360) * math.pi / 180.0:
        ux, uy = math.cos(a), math.sin(a)
        best = 12.0
        for cx, cy, r in circles:
            px, py = cx - ox, cy - oy
            t = px * ux + py * uy
            d2 = px * px + py * py - t * t
            if t > 0 and d2 <= r * r:
                best = min(best, t - math.sqrt(r * r - d2))
        for x0, y0, x1, y1 in walls:
            ex, ey = x1 - x0, y1 - y0
            den = ux * ey - uy * ex
            if abs(den) < 1e-12:
                continue
            ax, ay = x0 - ox, y0 - oy
            t = (ax * ey - ay * ex) / den
            s = (ax * uy - ay * ux) / den
            if t > 0 and 0 <= s <= 1:
                best = min(best, t)
        if best < 12.0:
            best += rng.normal(0.0, noise)
            out.append((ox + best * ux, oy + best * uy))
    return np.array(out)


def _cart(pose: Pose2D) -> list[tuple[float, float, float]]:
    return [(x, y, R) for x, y in leg_positions(pose, LENGTH, WIDTH)]


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_cart_10_cm_and_5_degrees_off_is_found_within_a_centimetre(seed: int) -> None:
    expected = Pose2D(3.0, 2.0, 0.0)
    true = Pose2D(3.08, 1.94, math.radians(5.0))
    origin = (1.95, 2.0)  # behind the cart, on its expected axis
    walls = [(4.5, 0.0, 4.5, 4.0), (0.0, 0.5, 6.0, 0.5)]
    points = _scan(origin, _cart(true), walls, seed=seed)
    found = find_legs(points, origin, expected, LENGTH, WIDTH, R)
    assert found is not None
    assert found.legs == 4
    assert found.pose.distance_to(true) < 0.01
    assert abs(angle_diff(found.pose.theta, true.theta)) < 0.01


def test_a_cart_seen_from_off_its_axis_is_found() -> None:
    true = Pose2D(3.0, 2.0, math.pi / 2)
    origin = (2.4, 0.6)  # behind it and to the side, in a room
    walls = [(0.5, 0.0, 0.5, 5.0), (5.0, 0.0, 5.0, 5.0), (0.0, 4.0, 6.0, 4.0)]
    points = _scan(origin, _cart(true), walls)
    found = find_legs(points, origin, Pose2D(3.05, 2.05, math.pi / 2 - 0.1), LENGTH, WIDTH, R)
    assert found is not None and found.legs >= 3
    assert found.pose.distance_to(true) < 0.015


def test_nothing_two_posts_or_a_box_is_not_a_cart() -> None:
    expected = Pose2D(3.0, 2.0, 0.0)
    origin = (1.95, 2.0)
    empty = _scan(origin, [], [(4.5, 0.0, 4.5, 4.0)])
    assert find_legs(empty, origin, expected, LENGTH, WIDTH, R) is None
    two = _scan(origin, _cart(expected)[:2], [(4.5, 0.0, 4.5, 4.0)])
    assert find_legs(two, origin, expected, LENGTH, WIDTH, R) is None
    box = _scan(origin, [], [(2.55, 1.65, 2.55, 2.35), (2.55, 1.65, 3.45, 1.65),
                             (2.55, 2.35, 3.45, 2.35)])
    assert find_legs(box, origin, expected, LENGTH, WIDTH, R) is None
    # Legs of another size of cart (1.4 x 0.7) do not fit this one's rectangle.
    other = [(x, y, R) for x, y in leg_positions(expected, 1.4, WIDTH)]
    assert find_legs(_scan(origin, other), origin, expected, LENGTH, WIDTH, R) is None


def test_leg_candidates_are_leg_sized_blobs_centred_behind_their_near_surface() -> None:
    origin = (0.0, 0.0)
    points = _scan(origin, [(1.0, 0.0, R)], [(0.0, 2.0, 3.0, 2.0)], noise=0.0)
    legs = leg_candidates(points, origin, R)
    assert legs.shape == (1, 2)
    assert legs[0] == pytest.approx((1.0, 0.0), abs=0.01)


def test_a_bad_config_is_refused() -> None:
    with pytest.raises(ConfigError):
        LegsConfig(min_legs=5)
    with pytest.raises(ConfigError):
        LegsConfig(search_radius=0.0)
