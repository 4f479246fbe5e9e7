from __future__ import annotations

import pytest

from polynav.errors import ConfigError
from polynav.geometry import Pose2D
from polynav.planning import registry
from polynav.planning.grid_planner import GridPlanner, GridPlannerConfig
from tests.unit.planning.grids import grid_from_ascii


def test_every_registered_name_builds_a_planner_running_that_search() -> None:
    assert set(registry.PLANNERS) == {"astar", "theta_star"}
    config = GridPlannerConfig(cost_weight=1.5)
    for name in registry.PLANNERS:
        planner = registry.create(name, config)
        assert isinstance(planner, GridPlanner)
        assert planner.config.algorithm == name
        assert planner.config.cost_weight == 1.5


def test_created_planners_plan() -> None:
    grid = grid_from_ascii(
        """
        ....
        .#..
        ....
        """
    )
    for name in registry.PLANNERS:
        path = registry.create(name).plan(grid, Pose2D(0.5, 0.5), Pose2D(3.5, 2.5))
        assert path.points[0].tolist() == [0.5, 0.5]
        assert path.points[-1].tolist() == [3.5, 2.5]


def test_unknown_planner_name_is_a_config_error() -> None:
    with pytest.raises(ConfigError) as error:
        registry.create("rrt")
    assert error.value.key == "planner.name"


def test_warm_up_compiles_without_error() -> None:
    registry.warm_up()
