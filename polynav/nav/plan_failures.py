"""What the navigator does when a plan fails or the controller stops before a passage.

A mixin over :class:`~polynav.nav.navigator.Navigator` (the navigator stays one class to its
users). Three moments are decided here:

- **The controller stops for something the lidar has just seen on the route ahead**: the robot
  plans again at once and, if the new route goes round it, follows it without the block's wait
  (:meth:`PlanFailures._steer_round`; once per place per goal, never with a person in the way).
- **The controller stops before a passage** (``BLOCKED``, and no person in the way): if the body
  touches the static or marked world along the route ahead, that passage is closed for this goal
  (:mod:`~polynav.nav.passages`) and the robot plans again at once, round it; where it cannot
  turn (a pocket narrower than its diagonal) it first backs out along the way in
  (:mod:`~polynav.nav.back_out`). A block that closes a new passage is progress, not a failure:
  it does not count against the place's retries (within the closures' limit and time budget,
  :class:`~polynav.nav.passages.ClosedPassages`). A caller that sets its own retry limit
  (Yunji's ``max_continuous_retries``, a lift leg) runs its own policy: nothing is closed, and
  every block is one of its retries. Anything else is a failure, counted by place and time
  (:mod:`~polynav.nav.retry_budget`), with the recovery ladder.
- **A plan fails**: the lidar's marks are cleared once and the plan tried again; a goal held by
  something not on the map is waited for (:mod:`~polynav.nav.goal_wait`); people in a narrow way
  are waited for. When no way is left, a robot that cannot turn backs out first; when passages
  have been closed, every way they leave has been tried: they are opened again and the robot
  retries, counted by place and time, so that something that has moved on (another robot, a
  trolley) does not end the goal, and one that stays ends it ``stuck`` with the passages named.
  Without closures, a way the map has but something seen closes (another robot at a
  corridor's mouth) is retried the same way; a plan that finds no way on the map itself fails
  ``no path`` / ``goal occupied`` at once.
"""

from __future__ import annotations

import logging
import math
from typing import TYPE_CHECKING

from polynav.control.interface import Controller
from polynav.control.tracked_path import TrackedPath
from polynav.footprint import Footprint
from polynav.geometry import Pose2D
from polynav.maps.costmap import Costmap
from polynav.nav import events, route_choice
from polynav.nav.attempt import FailureReason, NavigationAttempt
from polynav.nav.back_out import BackOut
from polynav.nav.goal_wait import GoalWait
from polynav.nav.passages import ClosedPassages, first_touch
from polynav.nav.people_wait import PeopleWait
from polynav.nav.phases import NavPhase
from polynav.nav.recoveries import ClearCostmap, Recovery
from polynav.nav.unknown_walls import walled_in_by_unknown
from polynav.planning.errors import (
    GoalOccupied,
    NoPath,
    OutsideMap,
    PlanningError,
    StartOccupied,
    failure_cause,
)
from polynav.planning.interface import GlobalPlanner
from polynav.planning.path import Path

if TYPE_CHECKING:
    from polynav.nav.navigator_config import NavigatorConfig

log = logging.getLogger(__name__)


class PlanFailures:
    """Blocks and failed plans; mixed into the navigator, whose state it shares."""

    config: NavigatorConfig
    _costmap: Costmap
    _controller: Controller
    _planner: GlobalPlanner
    _wait: PeopleWait
    _goal_wait: GoalWait
    _clear: ClearCostmap
    _cleared_for_plan: bool
    _passages: ClosedPassages
    _back_out: BackOut
    _recovery: Recovery | None
    _target: Pose2D
    _path: Path | None
    _tracked: TrackedPath | None
    _along: float
    _footprint: Footprint
    _steered_at: list[tuple[float, float]]

    if TYPE_CHECKING:

        def _require(self) -> NavigationAttempt: ...

        def _emit(self, event: events.NavigationEvent) -> None: ...

        def _emit_retry(self, cause: str, recovery: str, now: float) -> None: ...

        def _fail(self, reason: FailureReason, message: str, now: float) -> None: ...

        def _retry(self, cause: str, pose: Pose2D, now: float) -> None: ...

        def _enter(self, phase: NavPhase, now: float) -> None: ...

        def _update(self, **changes: object) -> None: ...

        def _wait_for_people(self, pose: Pose2D, now: float) -> None: ...

        def _plan_path(self, pose: Pose2D) -> Path: ...

        def _follow_plan(self, path: Path, pose: Pose2D, now: float) -> None: ...

    def _steer_round(self, pose: Pose2D, now: float) -> bool:
        """The controller has just stopped for something on the route ahead: if the lidar
        closed it since it was planned, follow a new route round at once, without the block's
        wait, recovery and turn; ``True`` if so.

        Without a map the route crosses unknown floor, and a post seen there closes it when
        the robot comes within its stopping distance (3 m at 2 m/s): before, each such post
        cost the robot a stop, the block's wait, a turn in place and the run up to speed again
        (research-base, lattice courses without a map: one block in two courses, most of them
        posts unseen when the route was planned). Only where the body touches something along
        the route (not the arc or a turn), for a caller without its own retry limit, with no
        person in the way (people walk on: the wait is for them), once per place per goal, and
        only when the new route's first touch lies clearly farther on than the old one's: a
        planner that would take the same way again leaves the block its usual course.
        """
        touch = self._passages.noted_touch
        if touch is None or self._require().options.max_retries is not None:
            return False
        place = (touch.pose.x, touch.pose.y)
        if any(math.hypot(place[0] - x, place[1] - y) < route_choice.CLOSED_ROUTE_PLACE
               for x, y in self._steered_at):
            return False
        if self._wait.blocks(pose, self._path):
            return False
        self._steered_at.append(place)
        try:
            path = self._plan_path(pose)
        except PlanningError:
            return False
        # On the planner's costs: a shut door the new route crosses is one it will open.
        again = first_touch(self._footprint, self._costmap.planning_costs(),
                            TrackedPath.from_points(path.points), 0.0, pose,
                            self._passages.look_ahead)
        if again is not None and again.ahead < touch.ahead + route_choice.CLOSED_ROUTE_PLACE:
            return False
        log.info("the route ahead was closed at (%.2f, %.2f), %.2f m on: steering round it",
                 place[0], place[1], touch.ahead)
        self._follow_plan(path, pose, now)
        return True

    def _way_on_the_map(self, pose: Pose2D) -> bool:
        """Whether the map and keepouts alone (with the closed passages) leave a way to the
        target: a plan on :meth:`~polynav.maps.costmap.Costmap.map_costs`."""
        grid = self._passages.planning_grid(self._costmap.map_costs(), pose)
        try:
            self._planner.plan(grid, pose, self._target,
                               goal_tolerance=self._require().options.near_tolerance)
        except PlanningError:
            return False
        return True

    def _on_blocked(self, pose: Pose2D, now: float) -> None:
        """The controller stopped and nobody is in the way: close the passage or retry."""
        # A caller with its own retry limit (Yunji's max_continuous_retries, a lift leg) runs
        # its own policy: every block is one of its retries, and nothing is closed.
        own_limit = self._require().options.max_retries is not None
        passage = None if own_limit else self._passages.close(now)
        if passage is None:
            if not self._back_out.can_turn(pose) and self._back_out.may_start(pose):
                self._controller.reset()
                self._start_back_out("blocked where it cannot turn", pose, now)
            else:
                self._retry("blocked", pose, now)
            return
        cause = f"blocked at {passage.name}"
        self._controller.reset()
        self._update(retries=self._require().retries + 1)
        if not self._back_out.can_turn(pose) and self._back_out.may_start(pose):
            self._start_back_out(cause, pose, now)
            return
        self._emit_retry(cause, "re-plan round it", now)
        self._enter(NavPhase.PLAN, now)

    def _start_back_out(self, cause: str, pose: Pose2D, now: float) -> None:
        self._emit_retry(cause, self._back_out.name, now)
        self._recovery = self._back_out
        self._back_out.start(pose, now)
        self._enter(NavPhase.RECOVER, now)

    def _on_plan_error(self, exc: PlanningError, pose: Pose2D, now: float) -> None:
        log.warning("planning failed: %s", exc)
        cause = failure_cause(exc, self._costmap.cost_at(pose.x, pose.y))
        if (cause == "no_path" and self._costmap.config.track_unknown
                and walled_in_by_unknown(self._costmap.costs, self._costmap.info, pose,
                                         self._target)):
            cause = "walled_in_unknown"
        self._emit(events.PlanFailed(now, self._require(), cause=cause))
        if isinstance(exc, (NoPath, GoalOccupied)) and self._wait.blocks(pose, self._path):
            self._wait_for_people(pose, now)
            return
        if isinstance(exc, OutsideMap):
            self._fail(FailureReason.NO_PATH, f"outside the map: {exc}", now)
        elif isinstance(exc, (NoPath, GoalOccupied)):
            self._no_way(exc, pose, now)
        elif isinstance(exc, StartOccupied):
            self._retry("start occupied", pose, now)
        else:
            self._fail(FailureReason.NO_PATH, str(exc), now)

    def _no_way(self, exc: NoPath | GoalOccupied, pose: Pose2D, now: float) -> None:
        # Marks from the lidar may be what closes the way; with them cleared only the map,
        # the keepouts and the closed passages decide, and a second failure is final.
        reason = FailureReason.NO_PATH if isinstance(exc, NoPath) else FailureReason.GOAL_OCCUPIED
        if not self._cleared_for_plan:
            self._cleared_for_plan = True
            self._clear.start(pose, now)
            self._emit_retry(reason.value, self._clear.name, now)
        elif self._wait.people:
            # Cleared, and still no way, with people in view: in a narrow passage they may be
            # what closes it. Wait for them, looking for a way meanwhile.
            self._wait_for_people(pose, now)
        elif isinstance(exc, GoalOccupied) and self._goal_wait.may_clear(self._target):
            if self._goal_wait.begin(now):
                self._emit(events.NavigationWaiting(now, self._require(), cause="goal occupied"))
            self._enter(NavPhase.GOAL_WAIT, now)
        elif isinstance(exc, NoPath) and not self._back_out.can_turn(pose):
            # A pocket narrower than the body's diagonal: no way on forward from here. Back out
            # the way it came; with no way in known (it started here), the ladder backs up.
            if self._back_out.may_start(pose):
                self._start_back_out("no way on from here", pose, now)
            else:
                self._retry("no way on from here", pose, now)
        elif self._passages.passages and isinstance(exc, NoPath):
            # Every way the closures leave has been tried: what closed them may have moved on
            # (another robot, a trolley). Open them again and retry, counted by place and time,
            # so the goal fails stuck, naming them, once the place's retries are spent.
            self._passages.reopen_all()
            self._retry("no way left but closed passages", pose, now)
        elif (isinstance(exc, NoPath) and self._require().options.max_retries is None
              and self._way_on_the_map(pose)):
            # The building has a way: what closes it stands in it now (another robot passing a
            # room's door, a trolley) and may move on. Retry, counted by place and time, so
            # that a robot a corridor was closed to for a moment does not give its goal up in
            # under a second (bench fleet seed 2), and one closed for good ends ``stuck``. A
            # caller with its own retry limit (a lift leg) hears the failure at once.
            self._retry("no way past what stands in it", pose, now)
        else:
            self._fail(reason, str(exc) or reason.value, now)
