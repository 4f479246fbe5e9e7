"""Which robot takes a mission: the free one nearest its first stop, with battery to spare.

Pure: the fleet manager hands in what it knows of each robot (:class:`Candidate`) and where
the mission starts (:class:`Target`); :func:`choose` gives the robot, or None when none may
take it. A robot may take a mission when it is online, not doing one already, not in a fatal
error, and its battery is above :attr:`DispatchConfig.min_battery`. Among those the nearest
wins: straight-line distance on the mission's floor, and a robot on another floor is counted
:attr:`DispatchConfig.floor_cost` farther per floor between (a lift ride costs more than a
walk across the floor, whatever the lift's distance). Ties go to the robot named first, so
the same inputs always give the same robot.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from polynav.errors import ConfigError

_KEY = "fleet.manager.dispatch."


@dataclass(frozen=True, slots=True)
class DispatchConfig:
    """How robots are weighed for a mission.

    Attributes:
        min_battery: a robot at or below this charge [%] takes no mission.
        floor_cost: the distance [m] one floor between a robot and the mission counts for.
    """

    min_battery: float = 20.0
    floor_cost: float = 100.0

    def __post_init__(self) -> None:
        if not 0.0 <= self.min_battery < 100.0:
            raise ConfigError(_KEY + "min_battery", f"must be in [0, 100), got "
                                                    f"{self.min_battery}")
        if not self.floor_cost >= 0.0:
            raise ConfigError(_KEY + "floor_cost", f"must be >= 0, got {self.floor_cost}")


@dataclass(frozen=True, slots=True)
class Candidate:
    """A robot as the fleet manager last heard of it.

    Attributes:
        serial: its serial number.
        online: its connection is ONLINE (or it is in this process).
        busy: it runs an order, or the manager has given it a mission.
        in_error: it reports a fatal error.
        battery: its charge [%].
        map_name: the map it is on, None if it has not said where it is.
        x, y: where on that map [m].
    """

    serial: str
    online: bool
    busy: bool
    in_error: bool
    battery: float
    map_name: str | None
    x: float = 0.0
    y: float = 0.0


@dataclass(frozen=True, slots=True)
class Target:
    """Where a mission starts: its first stop's map and position [m]."""

    map_name: str
    x: float
    y: float


def available(robot: Candidate, config: DispatchConfig) -> bool:
    """Whether ``robot`` may take a mission now (module docstring)."""
    return (robot.online and not robot.busy and not robot.in_error
            and robot.map_name is not None and robot.battery > config.min_battery)


def cost(robot: Candidate, target: Target, levels: Mapping[str, int],
         config: DispatchConfig) -> float:
    """How far [m] ``robot`` is from ``target``, a floor between counting ``floor_cost``.

    A map missing from ``levels`` counts as one floor away from any other map.
    """
    distance = math.hypot(robot.x - target.x, robot.y - target.y)
    if robot.map_name == target.map_name:
        return distance
    here, there = levels.get(robot.map_name or ""), levels.get(target.map_name)
    floors = abs(here - there) if here is not None and there is not None else 1
    return distance + config.floor_cost * max(1, floors)


def choose(robots: Sequence[Candidate], target: Target, *, levels: Mapping[str, int],
           config: DispatchConfig) -> str | None:
    """The serial of the robot to send to ``target``, None when no robot may go.

    Args:
        robots: every robot of the fleet.
        target: where the mission starts.
        levels: each map's floor level (the site's floors), for robots on another map.
        config: the battery threshold and the cost of a floor.
    """
    best: tuple[float, str] | None = None
    for robot in robots:
        if not available(robot, config):
            continue
        key = (cost(robot, target, levels, config), robot.serial)
        if best is None or key < best:
            best = key
    return None if best is None else best[1]
