"""The people layer: soft discs around people that move with them and never lower a cost."""

from __future__ import annotations

import math

import numpy as np

from polynav.geometry import Pose2D
from polynav.maps import costs
from polynav.maps.costmap import Costmap, CostmapConfig
from polynav.maps.layers.people import PeopleLayer
from polynav.maps.map import Map, MapInfo
from polynav.nav.people import PeopleConfig, PeopleView, Person, aside_spots, densify
from polynav.robot.interface import PersonDetection

INFO = MapInfo(0.1, 60, 40, Pose2D(0.0, 0.0, 0.0))


def _costmap(layer: PeopleLayer) -> Costmap:
    data = np.zeros((INFO.height, INFO.width), dtype=np.int8)
    data[:, 0] = 100  # a wall along x = 0
    return Costmap(Map(INFO, data), CostmapConfig(obstacle_layer=False), extra_layers=(layer,))


def test_discs_follow_the_people_and_leave_no_trace() -> None:
    layer = PeopleLayer(INFO, radius=0.5, cost=180)
    costmap = _costmap(layer)
    layer.set_people([(3.0, 2.0)])
    costmap.update()
    assert costmap.cost_at(3.0, 2.0) == 180 and costmap.cost_at(3.45, 2.0) == 180
    assert costmap.cost_at(3.6, 2.0) == costs.FREE
    layer.set_people([(1.5, 1.0)])
    costmap.update()
    assert costmap.cost_at(3.0, 2.0) == costs.FREE  # the old disc is gone
    assert costmap.cost_at(1.5, 1.0) == 180
    layer.set_people([])
    costmap.update()
    assert int(np.count_nonzero(costmap.costs == 180)) == 0


def test_a_disc_never_lowers_a_wall_or_its_inflation() -> None:
    layer = PeopleLayer(INFO, radius=0.5, cost=180)
    costmap = _costmap(layer)
    before = costmap.costs.copy()
    layer.set_people([(0.2, 2.0), (-5.0, 2.0), (math.nan, 1.0)])  # on the wall, off the map
    costmap.update()
    assert costmap.cost_at(0.05, 2.0) == costs.LETHAL
    assert np.all(costmap.costs >= before)


def test_detections_are_placed_with_the_robot_pose_and_predicted_ahead() -> None:
    seen = [PersonDetection(1, 2.0, 0.0, 1.0, 0.0)]  # 2 m ahead, walking away at 1 m/s
    view = PeopleView.from_detections(seen, Pose2D(1.0, 1.0, math.pi / 2))
    (person,) = view.people
    assert (round(person.x, 9), round(person.y, 9)) == (1.0, 3.0)
    assert (round(person.vx, 9), round(person.vy, 9)) == (0.0, 1.0)
    assert [(round(x, 9), round(y, 9)) for x, y in view.positions(1.0, 0.5)] == [
        (1.0, 3.0), (1.0, 3.5), (1.0, 4.0)]
    assert view.nearest(1.0, 1.0) == 2.0
    assert not PeopleView() and PeopleView().nearest(0.0, 0.0) == math.inf


def test_a_long_segment_is_sampled_so_a_person_mid_way_is_near_it() -> None:
    path = np.array([[0.0, 0.0], [10.0, 0.0]])
    view = PeopleView.from_detections([PersonDetection(1, 5.0, 0.3, 0.0, 0.0)], Pose2D())
    assert not view.near_any(path, 1.0)
    dense = densify(path, 0.1)
    assert dense.shape == (101, 2) and view.near_any(dense, 1.0)


class _Room:
    """A 6 m x 3 m room with its walls (cost_at as a costmap answers it)."""

    def cost_at(self, x: float, y: float) -> int:
        inside = 0.3 <= x <= 5.7 and 0.3 <= y <= 2.7
        return costs.FREE if inside else costs.LETHAL


def test_aside_spots_are_off_the_way_of_a_person_walking_at_the_robot() -> None:
    robot = Pose2D(3.0, 1.5, 0.0)
    walker = PeopleView((Person(4.0, 1.5, -0.8, 0.0),))  # 1 m ahead, coming this way
    config = PeopleConfig()
    spots = aside_spots(_Room(), robot, walker, config)
    assert spots, "the room has space to step aside"
    for spot in spots:
        assert abs(spot.y - 1.5) >= config.social_distance - 1e-9  # off their line
        assert _Room().cost_at(spot.x, spot.y) == costs.FREE
    distances = [spot.distance_to(robot) for spot in spots]
    assert distances == sorted(distances) and distances[0] <= 1.0


def test_in_a_narrow_corridor_the_only_spots_are_past_the_person() -> None:
    class Corridor:
        def cost_at(self, x: float, y: float) -> int:
            return costs.FREE if abs(y - 1.5) <= 0.4 else costs.LETHAL

    robot = Pose2D(3.0, 1.5, 0.0)
    walker = PeopleView((Person(4.0, 1.5, -0.8, 0.0),))
    # None beside their way: only behind them, where the planner finds no way through them.
    spots = aside_spots(Corridor(), robot, walker, PeopleConfig())
    assert all(spot.x >= 4.0 + PeopleConfig().social_distance - 1e-9 for spot in spots)
