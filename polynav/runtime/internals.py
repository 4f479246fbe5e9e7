"""The seam between the runtime's parts by subject.

:class:`~polynav.runtime.robot_runtime.RobotRuntime` is one class to its callers, written in a
few modules (:mod:`~polynav.runtime.navigation_commands`, :mod:`~polynav.runtime.goal_commands`,
:mod:`~polynav.runtime.motion_commands`, ...) so
that no file carries every subject. :class:`RuntimeParts` is their common base: it declares the
state they share and the runtime's own methods they call, so that the type checker holds each
part to what it may touch; :class:`RobotRuntime` supplies them.
"""

from __future__ import annotations

import abc
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, TypeVar

from polynav.errors import InvalidRequest
from polynav.geometry import Pose2D
from polynav.maps.keepout import Keepout
from polynav.maps.map import Map
from polynav.nav.attempt import GoalOptions, NavigationState
from polynav.nav.events import NavigationEvent
from polynav.nav.stack import NavigationStack, StackConfig
from polynav.robot.interface import Robot
from polynav.runtime.config import Mode, RuntimeConfig, SiteData
from polynav.runtime.direct_motion import DirectMotion
from polynav.runtime.events import RuntimeEvent
from polynav.runtime.exploration import Exploration
from polynav.runtime.mapping_jobs import MappingJobs
from polynav.runtime.mapping_session import MappingSession
from polynav.runtime.navigation_events import AttemptBook
from polynav.runtime.patrols import Patrols
from polynav.runtime.placement import Placement
from polynav.runtime.relocalization import LostRecovery
from polynav.runtime.settings import RobotSettings
from polynav.runtime.task_commands import TaskCommands
from polynav.runtime.watchers import EStopWatcher

if TYPE_CHECKING:
    from polynav.runtime.cart_commands import CartCommands

T = TypeVar("T")


@dataclass(frozen=True, slots=True)
class MapStart:
    """A saved map the robot starts on (to navigate, or to extend it), as the operator named
    it: the map's stored name, its floor in the simulated world, its grid, and the robot's
    pose on it when a point or a pose was given."""

    name: str
    floor: str
    grid: Map
    initial: Pose2D | None


class RuntimeParts(abc.ABC):
    """State and methods the parts share (set and defined by the runtime)."""

    store: SiteData
    config: RuntimeConfig
    _robot: Robot
    _place: Placement
    _mode: Mode
    _stack: NavigationStack | None
    _map_name: str | None
    _grid: Map | None
    _keepouts: tuple[Keepout, ...]
    _mapless: bool
    _base_stack_config: StackConfig
    _recovery: LostRecovery
    _settings: RobotSettings
    _settings_dirty: bool
    _software_estop: bool
    _estop: EStopWatcher
    _motion: DirectMotion
    _attempts: AttemptBook
    _patrols: Patrols
    tasks: TaskCommands
    _mapping: MappingSession | None
    _exploration: Exploration | None
    _mapping_jobs: MappingJobs
    carts: CartCommands

    def _map_start(self, map_name: str, point: str | None, pose: Pose2D | None) -> MapStart:
        """Read map ``map_name`` to start on, placed by ``point`` or ``pose`` (not both).

        Raises:
            NotFound: unknown map or point.
            InvalidRequest: both ``point`` and ``pose``; a map on no simulated floor.
        """
        if point is not None and pose is not None:
            raise InvalidRequest("point", "give a point or a pose, not both")
        record = self.store.map_record(map_name)
        name = str(getattr(record, "name", map_name))
        floor = self._place.floor_of(self.store, name, getattr(record, "floor", None))
        initial = self.store.point(name, point).pose if point is not None else pose
        return MapStart(name, floor, self.store.load_map(name), initial)

    @abc.abstractmethod
    def now(self) -> float:
        """The runtime's clock [s]."""

    @abc.abstractmethod
    def _publish(self, event: RuntimeEvent) -> None:
        """Publish a runtime event."""

    @abc.abstractmethod
    def _check_localization(self, now: float) -> None:
        """Publish a localization change."""

    @abc.abstractmethod
    def _end_mapping(self) -> None:
        """Drop the mapping session (mapping commands)."""

    @abc.abstractmethod
    def _new_mapless_stack(self, config: StackConfig) -> NavigationStack:
        """A navigation stack without a map (mapless commands)."""

    @abc.abstractmethod
    def _on_nav_event(self, event: NavigationEvent) -> None:
        """Report a navigator event as the runtime's."""

    @abc.abstractmethod
    def _call(self, fn: Callable[[], T]) -> T:
        """Run ``fn`` between ticks."""

    @abc.abstractmethod
    def _rebuild_stack(self) -> NavigationStack:
        """A navigation stack with the current settings."""

    @abc.abstractmethod
    def _check_estop(self, now: float) -> bool:
        """Publish an e-stop change; whether an e-stop is active."""

    @abc.abstractmethod
    def _start_goal(
        self,
        point: str | None,
        pose: Pose2D | None,
        map_name: str | None,
        options: GoalOptions | None,
    ) -> int:
        """Start a goal (goal commands)."""

    @abc.abstractmethod
    def _start_route(self, point: str | None, goal: Pose2D, goal_map: str,
                     options: GoalOptions) -> int:
        """Start a goal on another map (lift commands)."""

    @abc.abstractmethod
    def _end_route(self, state: NavigationState, reason: str | None = None) -> bool:
        """End the running goal on another map, if any (lift commands)."""

    @abc.abstractmethod
    def _route_running(self) -> bool:
        """Whether a goal on another map runs (lift commands)."""

    @abc.abstractmethod
    def _cancel_goal(self) -> bool:
        """Cancel the goal, if any (goal commands)."""

    @abc.abstractmethod
    def _goal_active(self) -> bool:
        """Whether a goal runs or is paused (goal commands)."""

    @abc.abstractmethod
    def _require_navigating(self) -> NavigationStack:
        """The stack, or Conflict unless NAVIGATING (goal commands)."""

    @abc.abstractmethod
    def _stop_navigation(self) -> None:
        """Unload the map and become FREE (nothing when FREE)."""

    @abc.abstractmethod
    def _halt_motion(self) -> None:
        """End teleop and local moves (motion commands)."""

    @abc.abstractmethod
    def _set_mode(self, mode: Mode) -> None:
        """Change mode, publishing the change."""

    @abc.abstractmethod
    def _floor_now(self) -> str | None:
        """The floor the robot is on."""

    @abc.abstractmethod
    def _status_pose(self) -> Pose2D:
        """The pose the status shows now."""
