"""The simulated sign camera: range, field of view, the sign's face, and walls in between."""

from __future__ import annotations

import math

import numpy as np
import pytest

from polynav.geometry import Pose2D
from polynav.maps.map import MapInfo
from polynav.robot.profile import ProfileError, SignCamera, parse_profile
from polynav.robot.sim.sign_camera import seen_signs
from polynav.worlds.world import NoEntrySign

INFO = MapInfo(resolution=0.1, width=100, height=40, origin=Pose2D())
OPEN = np.zeros((40, 100), dtype=bool)
ROBOT = Pose2D(1.0, 2.0, 0.0)  # looking along +x
FACING_ROBOT = NoEntrySign(4.0, 2.0, math.pi)


def _seen(sign: NoEntrySign, occupied: np.ndarray = OPEN, robot: Pose2D = ROBOT,
          reach: float = 4.0, fov: float = 1.2) -> list[tuple[float, float]]:
    return [(round(d.x, 3), round(d.y, 3)) for d in seen_signs(
        robot, (sign,), reach=reach, fov=fov, occupied=occupied, info=INFO)]


def test_a_sign_ahead_facing_the_robot_is_seen_in_the_robot_frame() -> None:
    assert _seen(FACING_ROBOT) == [(3.0, 0.0)]
    assert _seen(FACING_ROBOT, robot=Pose2D(1.0, 2.0, 0.3)) != []
    turned = seen_signs(Pose2D(1.0, 2.0, 0.3), (FACING_ROBOT,), reach=4.0, fov=1.2,
                        occupied=OPEN, info=INFO)[0]
    assert math.isclose(turned.x, 3.0 * math.cos(0.3), abs_tol=1e-9)
    assert math.isclose(turned.y, -3.0 * math.sin(0.3), abs_tol=1e-9)


def test_beyond_reach_outside_the_view_or_from_behind_it_is_not() -> None:
    assert _seen(FACING_ROBOT, reach=2.5) == []
    assert _seen(FACING_ROBOT, robot=Pose2D(1.0, 2.0, math.pi / 2)) == []
    assert _seen(NoEntrySign(4.0, 2.0, 0.0)) == []  # its back to the robot


def test_a_wall_between_hides_it() -> None:
    walled = OPEN.copy()
    walled[:, 25] = True  # x 2.5..2.6
    assert _seen(FACING_ROBOT, occupied=walled) == []


def test_a_profile_gives_its_sign_camera_and_refuses_a_bad_one() -> None:
    base = {"name": "r", "footprint": {"radius": 0.25}}
    assert parse_profile(base).sign_camera is None
    profile = parse_profile({**base, "sign_camera": {"range": 3.0, "fov": 1.0}})
    assert profile.sign_camera == SignCamera(3.0, 1.0)
    assert parse_profile(profile.to_document()).sign_camera == profile.sign_camera
    assert profile.sim_config().sign_camera_range == 3.0
    with pytest.raises(ProfileError, match="sign_camera.fov"):
        parse_profile({**base, "sign_camera": {"fov": 0.0}})
    with pytest.raises(ProfileError, match="sign_camera.lens"):
        parse_profile({**base, "sign_camera": {"lens": 1.0}})
