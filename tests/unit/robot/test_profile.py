"""Robot profiles: the built-ins load; every class of bad profile is refused, its field named."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest
import yaml

from polynav.robot.profile import (
    ProfileError,
    RobotProfile,
    builtin_profiles,
    load_profile,
    parse_profile,
)
from polynav.robot.sim.config import SimConfig


def _doc(**changes: Any) -> dict[str, Any]:
    doc: dict[str, Any] = {
        "name": "test",
        "footprint": {"polygon": [[0.3, 0.2], [-0.2, 0.2], [-0.2, -0.2], [0.3, -0.2]]},
        "limits": {"max_linear_velocity": 1.5, "max_angular_velocity": 2.0},
        "cruise": {"linear_velocity": 1.5, "angular_velocity": 1.5},
        "lidar": {"pose": {"x": 0.1, "y": 0.0, "theta": 0.0}, "beams": 180},
    }
    doc.update(changes)
    return doc


def test_builtin_profiles_are_the_demo_delivery_and_research_base() -> None:
    assert builtin_profiles() == ["delivery", "demo", "research-base"]
    for name in builtin_profiles():
        assert load_profile(name).name == name


def test_demo_profile_is_todays_simulator() -> None:
    assert load_profile("demo").sim_config() == SimConfig()
    assert load_profile().name == "demo"


def test_research_base_is_a_051_by_043_rectangle_at_2_mps() -> None:
    p = load_profile("research-base")
    assert p.limits.max_linear_velocity == 2.0
    assert p.inscribed_radius == pytest.approx(0.215)
    assert p.circumscribed_radius == pytest.approx(math.hypot(0.255, 0.215))
    sim = p.sim_config()
    assert len(sim.footprint_polygon) == 4
    assert sim.robot_radius == pytest.approx(p.circumscribed_radius)
    assert sim.lidar_x == pytest.approx(0.12)


def test_profile_loads_from_a_file(tmp_path: Path) -> None:
    path = tmp_path / "robot.yaml"
    path.write_text(yaml.safe_dump(_doc()))
    p = load_profile(path)
    assert p.name == "test" and p.lidar.beams == 180 and p.lidar.x == pytest.approx(0.1)
    assert p.to_dict()["lidar"]["pose"] == {"x": 0.1, "y": 0.0, "theta": 0.0}


@pytest.mark.parametrize(
    ("changes", "field"),
    [
        ({"limits": {"max_linear_velocity": -1.0}}, "robot.limits.max_linear_velocity"),
        ({"limits": {"angular_deceleration": 0}}, "robot.limits.angular_deceleration"),
        ({"cruise": {"linear_velocity": 2.0}}, "robot.cruise.linear_velocity"),
        ({"footprint": {"polygon": [[0.3, 0.2], [-0.2, -0.2], [-0.2, 0.2], [0.3, -0.2]]}},
         "robot.footprint.polygon"),
        ({"footprint": {"polygon": [[1.0, 1.0], [2.0, 1.0], [2.0, 2.0]]}},
         "robot.footprint.polygon"),
        ({"footprint": {"radius": 0.2, "polygon": [[0, 0], [1, 0], [0, 1]]}}, "robot.footprint"),
        ({"footprint": {"radius": -0.2}}, "robot.footprint.radius"),
        ({"footprint": {"radius": "big"}}, "robot.footprint.radius"),
        ({"footprint": {"polygon": [[0.3, 0.2], [0.1]]}}, "robot.footprint.polygon[1]"),
        ({"lidar": {"pose": {"x": 0.5, "y": 0.0}}}, "robot.lidar.pose"),
        ({"lidar": {"pose": {"x": 0.0, "y": 0.0, "theta": 4.0}}}, "robot.lidar.pose.theta"),
        ({"lidar": {"range_min": 5.0, "range_max": 4.0}}, "robot.lidar.range_min"),
        ({"lidar": {"beams": 1.5}}, "robot.lidar.beams"),
        ({"lidar": {"fov": 7.0}}, "robot.lidar.fov"),
        ({"lidar": {"rate": 500.0}}, "robot.lidar.rate"),
        ({"odometry": {"rotation_noise": -0.1}}, "robot.odometry.rotation_noise"),
        ({"imu": {"rate": 0.0}}, "robot.imu.rate"),
        ({"charger": {"distance_tolerance": 0.0}}, "robot.charger.distance_tolerance"),
        ({"charger": {"notch_depth": 0.0}}, "robot.charger.notch_depth"),
        ({"charger": {"plate_width": 0.2}}, "robot.charger.notch_width"),
        ({"reverse": {"allowed": "yes"}}, "robot.reverse.allowed"),
        ({"reverse": {"rear_view": -1.0}}, "robot.reverse.rear_view"),
        ({"reverse": {"mirrors": 2}}, "robot.reverse.mirrors"),
        ({"reverse": True}, "robot.reverse"),
        ({"limits": {"max_speed": 1.0}}, "robot.limits.max_speed"),
        ({"wheels": 4}, "robot.wheels"),
        ({"name": ""}, "robot.name"),
        ({"limits": [1, 2]}, "robot.limits"),
        ({"limits": {"max_linear_velocity": True}}, "robot.limits.max_linear_velocity"),
        ({"limits": {"max_linear_velocity": float("nan")}}, "robot.limits.max_linear_velocity"),
    ],
)
def test_bad_profile_is_refused_naming_the_field(changes: dict[str, Any], field: str) -> None:
    with pytest.raises(ProfileError) as err:
        parse_profile(_doc(**changes))
    assert err.value.field == field
    assert field in str(err.value)


def test_missing_footprint_is_refused() -> None:
    doc = _doc()
    del doc["footprint"]
    with pytest.raises(ProfileError, match="robot.footprint"):
        parse_profile(doc)


def test_unreadable_or_unknown_profile_is_refused(tmp_path: Path) -> None:
    with pytest.raises(ProfileError, match="no profile file or built-in"):
        load_profile("nosuchrobot")
    with pytest.raises(ProfileError, match="no such file"):
        load_profile(tmp_path / "absent.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: [unclosed")
    with pytest.raises(ProfileError, match="not valid YAML"):
        load_profile(bad)
    scalar = tmp_path / "scalar.yaml"
    scalar.write_text("42")
    with pytest.raises(ProfileError, match="expected a mapping"):
        load_profile(scalar)


def test_profile_built_in_python_is_validated() -> None:
    good = parse_profile(_doc())
    with pytest.raises(ProfileError, match="robot.lidar.pose"):
        RobotProfile(name="x", footprint=good.footprint,
                     lidar=type(good.lidar)(x=2.0))


def test_the_rear_is_seen_as_far_as_a_lidar_that_looks_behind_unless_the_profile_says() -> None:
    round_lidar = parse_profile(_doc())
    assert round_lidar.reverse.allowed and round_lidar.rear_view == 12.0
    forward = parse_profile(_doc(lidar={"pose": {"x": 0.1, "y": 0.0, "theta": 0.0},
                                        "fov": math.pi}))
    assert forward.rear_view == 0.0
    told = parse_profile(_doc(reverse={"allowed": False, "rear_view": 0.8}))
    assert not told.reverse.allowed and told.rear_view == 0.8
    assert told.to_dict()["reverse"] == {"allowed": False, "rear_view": 0.8}
    assert parse_profile(told.to_document()) == told


def test_a_disks_costmap_is_inscribed_half_a_cell_wider_and_a_polygons_is_not() -> None:
    from polynav.nav.stack import DISK_CELL_MARGIN, stack_config_for

    assert stack_config_for(load_profile("delivery")).costmap.inscribed_cell_margin == (
        DISK_CELL_MARGIN)
    assert stack_config_for(load_profile("research-base")).costmap.inscribed_cell_margin == 0.0


def test_the_stack_reverses_only_as_the_profile_allows_and_backs_out_only_as_far_as_it_sees(
) -> None:
    from polynav.nav.stack import BLIND_BACKOUT, stack_config_for

    assert stack_config_for(parse_profile(_doc())).navigator.reverse_allowed
    may_not = stack_config_for(parse_profile(_doc(reverse={"allowed": False})))
    assert not may_not.navigator.reverse_allowed
    blind = stack_config_for(parse_profile(_doc(reverse={"rear_view": 0.0})))
    assert blind.navigator.recovery_backout_distance == BLIND_BACKOUT


def test_the_payload_says_what_the_robot_carries_and_how_it_drives_loaded() -> None:
    from polynav.robot.profile import Payload, parse_profile

    doc = {"name": "mule", "footprint": {"radius": 0.25},
           "payload": {"max_mass": 80.0, "linear_velocity": 0.3}}
    mule = parse_profile(doc)
    assert mule.payload == Payload(max_mass=80.0, linear_velocity=0.3)
    assert parse_profile(mule.to_document()).payload == mule.payload
    assert parse_profile({"name": "x", "footprint": {"radius": 0.25}}).payload is None
    for field, value, words in (("max_mass", -1.0, "must be >= 0"),
                                ("linear_velocity", 5.0, "above cruise.linear_velocity"),
                                ("angular_velocity", 0.0, "must be > 0")):
        with pytest.raises(ProfileError) as error:
            parse_profile({**doc, "payload": {field: value}})
        assert error.value.field == f"robot.payload.{field}" and words in error.value.reason
