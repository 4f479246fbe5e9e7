"""Which robot takes a mission: free, online, not in error, with battery, nearest."""

from __future__ import annotations

import pytest

from polynav.errors import ConfigError
from polynav.fleet.manager.dispatch import Candidate, DispatchConfig, Target, choose, cost

LEVELS = {"floor1": 1, "floor2": 2, "floor3": 3}
CONFIG = DispatchConfig(min_battery=20.0, floor_cost=100.0)
TARGET = Target("floor1", 10.0, 0.0)


def robot(serial: str, *, x: float = 0.0, map_name: str | None = "floor1", online: bool = True,
          busy: bool = False, in_error: bool = False, battery: float = 80.0) -> Candidate:
    return Candidate(serial, online, busy, in_error, battery, map_name, x, 0.0)


def test_the_nearest_free_robot_on_the_floor_is_chosen() -> None:
    robots = [robot("far", x=0.0), robot("near", x=7.0), robot("nearer", x=12.0)]
    assert choose(robots, TARGET, levels=LEVELS, config=CONFIG) == "nearer"


@pytest.mark.parametrize("reason", [
    {"online": False}, {"busy": True}, {"in_error": True}, {"battery": 20.0},
    {"map_name": None},
])
def test_a_robot_that_may_not_go_is_passed_over_for_a_farther_one(
        reason: dict[str, object]) -> None:
    robots = [robot("near", x=10.0, **reason), robot("far", x=-50.0)]  # type: ignore[arg-type]
    assert choose(robots, TARGET, levels=LEVELS, config=CONFIG) == "far"


def test_no_robot_when_none_may_go() -> None:
    assert choose([robot("r1", busy=True)], TARGET, levels=LEVELS, config=CONFIG) is None
    assert choose([], TARGET, levels=LEVELS, config=CONFIG) is None


def test_another_floor_costs_floor_cost_per_floor_between() -> None:
    assert cost(robot("a", x=10.0, map_name="floor3"), TARGET, LEVELS, CONFIG) == 200.0
    assert cost(robot("a", x=13.0, map_name="floor2"), TARGET, LEVELS, CONFIG) == 103.0
    # A map of no known floor counts as one floor away.
    assert cost(robot("a", x=10.0, map_name="annex"), TARGET, LEVELS, CONFIG) == 100.0
    robots = [robot("upstairs", x=10.0, map_name="floor2"), robot("across", x=-80.0)]
    assert choose(robots, TARGET, levels=LEVELS, config=CONFIG) == "across"
    robots = [robot("upstairs", x=10.0, map_name="floor2"), robot("across", x=-95.0)]
    assert choose(robots, TARGET, levels=LEVELS, config=CONFIG) == "upstairs"


def test_a_tie_goes_to_the_robot_named_first() -> None:
    robots = [robot("r2", x=12.0), robot("r1", x=8.0)]
    assert choose(robots, TARGET, levels=LEVELS, config=CONFIG) == "r1"


@pytest.mark.parametrize(("kwargs", "key"), [
    ({"min_battery": 100.0}, "min_battery"), ({"min_battery": -1.0}, "min_battery"),
    ({"floor_cost": -1.0}, "floor_cost"),
])
def test_config_out_of_range_is_refused_naming_its_key(kwargs: dict[str, float],
                                                       key: str) -> None:
    with pytest.raises(ConfigError, match=key):
        DispatchConfig(**kwargs)
