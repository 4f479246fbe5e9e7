"""Goals on other maps: the route across lifts and connections, run as states with timeouts.

A part of :class:`~polynav.runtime.robot_runtime.RobotRuntime` by subject. A goal whose map is
not the current one is routed (:mod:`polynav.routing.router`) and run leg by leg on each control
tick; to callers it is one attempt (one ``navigation_started`` and one end event, one id) whose
status shows its legs and lift phase (``route``), with :mod:`~polynav.runtime.lift_events` for
what happens inside.

The lift sequence of a lift leg (``docs/lifts.md``), each step a :class:`LiftPhase`:

1. ``going_to_lift``: drive to the car's waiting spot (its outside point where it has none).
2. ``waiting_for_session``: there, ask for the car's session (a lease on ``lift:<car>``), and
   wait while another robot holds the car (first come, first served;
   given up after :data:`SESSION_TIMEOUT`, and at once if the car goes out of service).
3. ``calling``: the car is asked to this floor with its doors open, and the robot drives to
   the outside point; ``waiting_for_car`` until the car stands open here (given up after
   :data:`CALL_TIMEOUT`: the car is excluded and the goal re-routed). A car that stands open
   is driven into at once, without stopping at the outside point first.
4. ``entering``: drive to the inside point. A full car is given up for the next one; blocked
   (the navigator failed): get out of the car's way (back to the outside point, so whoever
   or whatever is in the door can come out), then retry after a pause, up to
   :data:`MAX_DOOR_RETRIES`.
5. ``riding``: the car is asked to the target floor; when it stands there the map is switched
   and localization restarted at the lift's known position (``switching_map``). A ride over
   :data:`RIDE_TIMEOUT` fails the goal.
6. ``exiting``: drive out past the outside point of the new floor (no stop there). Blocked:
   back into the car, wait, retry; then the session is ended (``left``) and the route goes
   on.

A car out of service, full, or that never came is excluded and the rest re-routed from where the
robot stands: onto the other car where one serves the floor. Where none does, a car given up
for a passing cause (busy, full, blocked at the door) is queued for again, up to
:data:`MAX_REQUEUES` times; else the goal fails with the router's reason ("lift out of
service").
"""

from __future__ import annotations

import abc
import logging
import math

from polynav.geometry import Pose2D
from polynav.maps.keepout import Keepout
from polynav.maps.map import Map
from polynav.nav.attempt import GoalOptions, NavigationState
from polynav.nav.stack import NavigationStack, StackConfig
from polynav.robot.lift import (
    DoorRequest,
    Lift,
    LiftError,
    LiftMode,
    LiftOutOfService,
    LiftRequest,
    MotionState,
)
from polynav.routing import connections as site_connections
from polynav.routing.errors import NoRoute
from polynav.routing.path_costs import PlannedPathCosts
from polynav.routing.route import DriveLeg, LiftLeg, Route, SwitchLeg
from polynav.routing.router import Router
from polynav.runtime import events
from polynav.runtime.lift_access import LiftAccess
from polynav.runtime.lift_events import (
    HELD,
    LiftPhase,
    LiftPhaseChanged,
    MapSwitched,
    RouteStarted,
)
from polynav.runtime.lift_sessions import LiftSessions
from polynav.runtime.route_run import (
    AT_DOOR,
    AT_POINT,
    CALL_TIMEOUT,
    IN_CAR,
    MAX_DOOR_RETRIES,
    MAX_REQUEUES,
    NEAR_LIFT,
    NEAR_LIFT_OPTIONS,
    OUT_OF_CAR,
    RETRY_PAUSE,
    RIDE_TIMEOUT,
    SESSION_TIMEOUT,
    RouteRun,
    carried,
    overlay,
)
from polynav.runtime.status import StatusSnapshot

log = logging.getLogger(__name__)


class LiftCommands(LiftAccess):
    """Cross-map goals and the lift sequence (see the module docstring)."""

    _grid: Map | None
    _keepouts: tuple[Keepout, ...]
    _route: RouteRun | None
    _route_last: RouteRun | None
    _router: Router | None
    _path_costs: PlannedPathCosts | None
    _lift_sessions: LiftSessions | None
    lift_waits: list[float]
    """Each ride's wait [s]: from reaching the lift (asking for its session) to driving in."""

    def _route_running(self) -> bool:
        return self._route is not None

    def route_length(self, start_map: str, start: Pose2D, goal_map: str, goal: Pose2D) -> float:
        """Length [m] of the in-map paths of the route the robot would take from ``start`` to
        ``goal`` (lift rides count nothing), on the stored maps.

        Raises:
            NotFound: unknown map. NoRoute: no route (the reason says why).
        """
        self.store.map_record(start_map)
        self.store.map_record(goal_map)
        route = self._plan_route(start_map, start, goal_map, goal, None, excluded=set())
        costs = self._costs()
        total, here, where = 0.0, start, start_map
        for leg in route.legs:
            if isinstance(leg, DriveLeg):
                total += costs.length(leg.map_name, here, leg.goal)
                here, where = leg.goal, leg.map_name
            elif isinstance(leg, LiftLeg):
                here, where = leg.outside_to, leg.to_map
            else:
                here, where = leg.to_pose, leg.to_map
        assert where == goal_map
        return total

    # -- starting and ending -------------------------------------------------------------------

    def _start_route(self, point: str | None, goal: Pose2D, goal_map: str,
                     options: GoalOptions) -> int:
        """Route to ``goal`` on ``goal_map`` from where the robot stands and start the first
        leg; the route's attempt id. Raises NoRoute (nothing has moved)."""
        stack = self._require_navigating()
        assert self._map_name is not None
        now = self.now()
        route = self._plan_route(self._map_name, stack.estimate.pose, goal_map, goal, point,
                                 excluded=set())
        self._end_route(NavigationState.CANCELED)
        self._cancel_goal()
        attempt_id = self._attempts.reserve_id()
        run = RouteRun(attempt_id, goal, goal_map, point, options, list(route.legs), now,
                       since=now)
        self._route = run
        self._route_last = run
        log.info("route %d to %s/%s: %s", attempt_id, goal_map, point or goal,
                 " -> ".join(leg.kind for leg in route.legs))
        self._publish(events.NavigationStarted(now, attempt_id, goal, point))
        self._publish(RouteStarted(now, attempt_id, tuple(leg.kind for leg in route.legs),
                                   route.cars))
        self._route_tick(now)
        return attempt_id

    def _end_route(self, state: NavigationState, reason: str | None = None) -> bool:
        """End the running route (``state``), releasing any car; whether one ran."""
        run = self._route
        if run is None:
            return False
        now = self.now()
        self._route = None
        if run.nav_id is not None and self._stack is not None:
            self._stack.navigator.cancel(now)
        self._give_up_car(run, now)
        run.state, run.reason, run.ended_at = state, reason, now
        run.nav_id = None
        if state is NavigationState.SUCCEEDED:
            self._publish(events.NavigationSucceeded(now, run.attempt_id, run.distance))
        elif state is NavigationState.FAILED:
            log.warning("%s route %d failed (leg %d of %d, %s): %s", self.robot_id,
                        run.attempt_id, run.index + 1, len(run.legs),
                        run.phase.value if run.phase else "driving", reason)
            self._publish(events.NavigationFailed(now, run.attempt_id, reason or "failed",
                                                  run.distance, True))
        else:
            self._publish(events.NavigationCanceled(now, run.attempt_id, run.distance))
        return True

    def _plan_route(self, start_map: str, start: Pose2D, goal_map: str, goal: Pose2D,
                    point: str | None, *, excluded: set[str]
                    ) -> Route:
        router = self._router
        if router is None:
            router = Router(self.store, self._costs())
            self._router = router
        records = site_connections.parse(self.store.connections())
        return router.route(records, self.lifts, start_map=start_map, start=start,
                            goal_map=goal_map, goal=goal, goal_point=point, exclude=excluded,
                            holder=self.robot_id)

    # -- the tick ------------------------------------------------------------------------------

    def _route_tick(self, now: float) -> None:
        """Move the running route on (after the navigation stack's tick)."""
        run = self._route
        if run is None or self._stack is None:
            return
        leg = run.leg
        if isinstance(leg, DriveLeg):
            self._drive_tick(run, leg, now)
        elif isinstance(leg, LiftLeg):
            self._lift_tick(run, leg, now)
        else:
            self._switch_leg(run, leg, now)

    def _drive_tick(self, run: RouteRun, leg: DriveLeg, now: float) -> None:
        lift = run.next_leg_lift()
        if run.nav_id is None:
            target, options = leg.goal, run.options if run.index == len(run.legs) - 1 else None
            if lift is not None:
                # The car's session is asked for on arrival, not on the way: a robot that held
                # the car while queueing for a corridor on its way there could wait for a robot
                # that waits for the car (hold and wait, docs/fleet.md).
                self._set_phase(run, LiftPhase.GOING_TO_LIFT, now)
                run.car = lift.car
                options = NEAR_LIFT_OPTIONS
                if lift.waiting_from:
                    target = lift.waiting_from
            self._leg_go(run, target, options)
            return
        if lift is not None and self._out_of_service(lift.car):
            self._reroute(run, now, f"lift {lift.car} went out of service")
            return
        result = self._leg_result(run)
        if lift is not None and result is NavigationState.FAILED and self._near(
                lift.waiting_from or lift.outside_from, NEAR_LIFT):
            # Near the lift but not on the spot (another robot waits there): wait here; the
            # call drives to the door once the car is this robot's.
            result = NavigationState.SUCCEEDED
        if result is NavigationState.SUCCEEDED:
            run.advance(now)
            if run.index >= len(run.legs):
                self._end_route(NavigationState.SUCCEEDED)
            elif lift is not None:
                self._set_phase(run, LiftPhase.WAITING_FOR_SESSION, now)
                self._route_tick(now)
        elif result is not None:
            self._end_route(NavigationState.FAILED, self._leg_reason())

    def _lift_tick(self, run: RouteRun, leg: LiftLeg, now: float) -> None:
        sessions = self._sessions()
        car = self.lifts.get(leg.car)
        if car is None:
            self._reroute(run, now, f"lift {leg.car} is gone")
            return
        phase = run.phase
        if phase in (None, LiftPhase.GOING_TO_LIFT):
            self._set_phase(run, LiftPhase.WAITING_FOR_SESSION, now)
            phase = run.phase
        if phase is not LiftPhase.RIDING and phase is not LiftPhase.EXITING:
            if car.state().mode is LiftMode.OUT_OF_SERVICE and phase is not LiftPhase.ENTERING:
                self._reroute(run, now, f"lift {leg.car} went out of service")
                return
        sessions.request(leg.car, now)  # asks, or renews while held
        if phase is LiftPhase.WAITING_FOR_SESSION:
            if sessions.granted(leg.car, now):
                self._call_car(run, leg, car, now)
            elif not run.announced_wait:
                run.announced_wait = True
                self._publish(LiftPhaseChanged(now, run.attempt_id, leg.car, phase,
                                               leg.from_floor, leg.to_floor, HELD))
            elif now - run.since > SESSION_TIMEOUT:
                self._reroute(run, now, f"lift {leg.car} stayed busy")
            elif sessions.rejected(leg.car):
                sessions.request(leg.car, now)
            return
        if phase in (LiftPhase.CALLING, LiftPhase.WAITING_FOR_CAR):
            self._await_car(run, leg, car, now)
        elif phase is LiftPhase.ENTERING:
            self._enter_tick(run, leg, car, now)
        elif phase is LiftPhase.RIDING:
            self._ride_tick(run, leg, car, now)
        elif phase is LiftPhase.EXITING:
            self._exit_tick(run, leg, car, now)

    def _call_car(self, run: RouteRun, leg: LiftLeg, car: Lift, now: float) -> None:
        try:
            car.request(LiftRequest(self.robot_id, leg.from_floor, DoorRequest.OPEN))
        except LiftError as exc:  # out of service, or someone else's session (an operator)
            if isinstance(exc, LiftOutOfService):
                self._reroute(run, now, str(exc))
            elif not run.announced_wait:
                run.announced_wait = True
                self._publish(LiftPhaseChanged(now, run.attempt_id, leg.car, run.phase or (
                    LiftPhase.WAITING_FOR_SESSION), leg.from_floor, leg.to_floor, HELD))
            return
        run.called = True
        self._set_phase(run, LiftPhase.CALLING, now)
        if not self._near(leg.outside_from, AT_POINT):
            self._leg_go(run, leg.outside_from, AT_DOOR)

    def _await_car(self, run: RouteRun, leg: LiftLeg, car: Lift, now: float) -> None:
        if run.nav_id is None and run.resume_at > now:
            return
        if run.nav_id is None and run.retries and not self._near(leg.outside_from, AT_POINT):
            self._leg_go(run, leg.outside_from, AT_DOOR)
            return
        if run.nav_id is not None:
            result = self._leg_result(run)
            if result is None:
                state = car.state()
                if not state.ready_at(leg.from_floor) or state.full:
                    return
                # The car stands open: drive straight in instead of stopping at its door
                # first (the stop costs the car's next user some 8 s of a busy car).
                self._drop_leg_goal(run)
            elif result is not NavigationState.SUCCEEDED:
                run.nav_id = None
                run.retries += 1
                if run.retries > MAX_DOOR_RETRIES:
                    self._reroute(run, now, f"could not reach {leg.car}'s door")
                else:
                    run.resume_at = now + RETRY_PAUSE
                return
            run.nav_id = None
        if run.phase is LiftPhase.CALLING:
            self._set_phase(run, LiftPhase.WAITING_FOR_CAR, now)
        state = car.state()
        if state.ready_at(leg.from_floor):
            if state.full:
                run.excluded.add(leg.car)
                self._reroute(run, now, f"lift {leg.car} is full")
                return
            self._set_phase(run, LiftPhase.ENTERING, now)
            self._leg_go(run, leg.inside_from, IN_CAR)
        elif now - run.since > CALL_TIMEOUT:
            run.excluded.add(leg.car)
            run.faulty.add(leg.car)
            self._reroute(run, now, f"lift {leg.car} did not come within {CALL_TIMEOUT:g} s")

    def _enter_tick(self, run: RouteRun, leg: LiftLeg, car: Lift, now: float) -> None:
        if run.nav_id is None:
            if now >= run.resume_at and car.state().ready_at(leg.from_floor):
                self._leg_go(run, leg.inside_from, IN_CAR)
            return
        result = self._leg_result(run)
        if result is None:
            return
        run.nav_id = None
        if run.avoiding:
            run.avoiding = False
            run.resume_at = now + RETRY_PAUSE
            out = "succeeded" if result is NavigationState.SUCCEEDED else "failed"
            self._publish(LiftPhaseChanged(now, run.attempt_id, leg.car, LiftPhase.ENTERING,
                                           leg.from_floor, leg.to_floor, f"avoided: {out}"))
            return
        if result is NavigationState.SUCCEEDED:
            try:
                car.request(LiftRequest(self.robot_id, leg.to_floor, DoorRequest.OPEN))
            except LiftError as exc:
                run.excluded.add(leg.car)
                self._reroute(run, now, f"lift {leg.car}: {exc}")
                return
            self._set_phase(run, LiftPhase.RIDING, now)
            return
        run.retries += 1
        if run.retries > MAX_DOOR_RETRIES:
            run.excluded.add(leg.car)
            self._reroute(run, now, f"could not enter lift {leg.car}")
            return
        self._publish(LiftPhaseChanged(now, run.attempt_id, leg.car, LiftPhase.ENTERING,
                                       leg.from_floor, leg.to_floor, "blocked: avoid, retry"))
        run.avoiding = True
        self._leg_go(run, leg.outside_from, AT_DOOR)

    def _ride_tick(self, run: RouteRun, leg: LiftLeg, car: Lift, now: float) -> None:
        state = car.state()
        if state.current_floor == leg.to_floor and state.motion is MotionState.STOPPED:
            self._set_phase(run, LiftPhase.SWITCHING_MAP, now)
            self._switch_map(run, leg.to_map, carried(self._pose(), leg.inside_from,
                                                       leg.inside_to))
            self._set_phase(run, LiftPhase.EXITING, now)
        elif now - run.since > RIDE_TIMEOUT:
            self._end_route(NavigationState.FAILED,
                            f"lift {leg.car} did not arrive within {RIDE_TIMEOUT:g} s")

    def _exit_tick(self, run: RouteRun, leg: LiftLeg, car: Lift, now: float) -> None:
        if run.nav_id is None:
            if now >= run.resume_at and car.state().ready_at(leg.to_floor):
                target = leg.inside_to if run.backing_in else leg.outside_to
                self._leg_go(run, target, IN_CAR if run.backing_in else OUT_OF_CAR)
            return
        result = self._leg_result(run)
        if result is None:
            return
        run.nav_id = None
        if run.backing_in:
            run.backing_in = False
            run.resume_at = now + RETRY_PAUSE
            back = "succeeded" if result is NavigationState.SUCCEEDED else "failed"
            self._publish(LiftPhaseChanged(now, run.attempt_id, leg.car, LiftPhase.EXITING,
                                           leg.from_floor, leg.to_floor, f"back in: {back}"))
            return
        if result is NavigationState.SUCCEEDED:
            self._set_phase(run, LiftPhase.LEFT, now)
            self._give_up_car(run, now)
            run.advance(now)
            if run.index >= len(run.legs):
                self._end_route(NavigationState.SUCCEEDED)
            return
        run.retries += 1
        if run.retries > MAX_DOOR_RETRIES:
            self._end_route(NavigationState.FAILED, f"could not leave lift {leg.car}")
            return
        self._publish(LiftPhaseChanged(now, run.attempt_id, leg.car, LiftPhase.EXITING,
                                       leg.from_floor, leg.to_floor, "blocked: back in, retry"))
        run.backing_in = True

    def _switch_leg(self, run: RouteRun, leg: SwitchLeg, now: float) -> None:
        floor = self._floor_of_map(leg.to_map)
        self._place.place(floor, leg.to_pose)  # the same place on the other map
        self._switch_map(run, leg.to_map, leg.to_pose)
        run.advance(now)
        if run.index >= len(run.legs):
            self._end_route(NavigationState.SUCCEEDED)

    # -- helpers -------------------------------------------------------------------------------

    def _set_phase(self, run: RouteRun, phase: LiftPhase, now: float) -> None:
        if run.phase is phase:
            return
        if phase is LiftPhase.WAITING_FOR_SESSION:
            run.wait_started = now
        elif phase is LiftPhase.ENTERING and run.wait_started is not None:
            self.lift_waits.append(now - run.wait_started)
            run.wait_started = None
        run.phase = phase
        run.since = now
        run.retries = 0
        lift = run.leg if isinstance(run.leg, LiftLeg) else run.next_leg_lift()
        if lift is None:
            return
        log.info("%s route %d: %s (%s, %s -> %s)", self.robot_id, run.attempt_id, phase.value,
                 lift.car, lift.from_floor, lift.to_floor)
        self._publish(LiftPhaseChanged(now, run.attempt_id, lift.car, phase, lift.from_floor,
                                       lift.to_floor))

    def _leg_go(self, run: RouteRun, goal: Pose2D, options: GoalOptions | None = None) -> None:
        stack = self._stack
        assert stack is not None
        self._attempts.pending_point = None
        run.nav_id = stack.go_to(goal, self.now(), options)

    def _leg_result(self, run: RouteRun) -> NavigationState | None:
        """How the leg's navigator goal ended, ``None`` while it runs."""
        stack = self._stack
        if stack is None or run.nav_id is None:
            return None
        attempt = stack.navigator.attempt
        if attempt is None or attempt.attempt_id != run.nav_id:
            return NavigationState.FAILED
        if not attempt.state.finished:
            return None
        run.distance += attempt.distance_travelled
        return attempt.state

    def _drop_leg_goal(self, run: RouteRun) -> None:
        """Stop counting the running leg goal (a new one replaces it), keeping its distance."""
        stack = self._stack
        attempt = stack.navigator.attempt if stack is not None else None
        if attempt is not None and attempt.attempt_id == run.nav_id:
            run.distance += attempt.distance_travelled
        run.nav_id = None

    def _leg_reason(self) -> str:
        stack = self._stack
        attempt = stack.navigator.attempt if stack is not None else None
        if attempt is None:
            return "failed"
        if attempt.state is NavigationState.CANCELED:
            return "canceled"
        return attempt.reason.value if attempt.reason else (attempt.message or "failed")

    def _out_of_service(self, car: str) -> bool:
        lift = self.lifts.get(car)
        return lift is None or lift.state().mode is LiftMode.OUT_OF_SERVICE

    def _give_up_car(self, run: RouteRun, now: float) -> None:
        """End this robot's session with the car it asked for, and give the lease back."""
        if run.car is None:
            return
        car = self.lifts.get(run.car)
        if car is not None and car.state().session_id == self.robot_id:
            try:
                car.request(LiftRequest(self.robot_id, end_session=True))
            except LiftError:
                log.debug("lift %s: session already over", run.car)
        self._sessions().release(run.car, now)
        run.car = None

    def _reroute(self, run: RouteRun, now: float, why: str) -> None:
        """Give up the car in use (``why``) and route the rest from where the robot stands."""
        lift = run.leg if isinstance(run.leg, LiftLeg) else run.next_leg_lift()
        if lift is not None:
            run.excluded.add(lift.car)
            self._publish(LiftPhaseChanged(now, run.attempt_id, lift.car,
                                           run.phase or LiftPhase.GOING_TO_LIFT,
                                           lift.from_floor, lift.to_floor, why))
        log.warning("%s route %d: %s; re-routing", self.robot_id, run.attempt_id, why)
        if run.nav_id is not None and self._stack is not None:
            self._drop_leg_goal(run)  # the way driven so far counts
            self._stack.navigator.cancel(now)
        self._give_up_car(run, now)
        route: Route | None
        try:
            route = self._rest_of_route(run, run.excluded)
        except NoRoute as exc:
            route = self._requeue(run)
            if route is None:
                self._end_route(NavigationState.FAILED, str(exc))
                return
        run.legs, run.index = list(route.legs), 0
        run.phase, run.since, run.retries, run.called = None, now, 0, False
        run.announced_wait = False
        self._publish(RouteStarted(now, run.attempt_id, tuple(leg.kind for leg in route.legs),
                                   route.cars))

    def _requeue(self, run: RouteRun) -> Route | None:
        """With no other car left, the route over the cars given up for a passing cause.

        A car that was busy, full or blocked at its door will likely serve later, and the only
        car for a floor is the only way there: the robot queues for it again (at most
        :data:`MAX_REQUEUES` times) instead of failing the goal. Cars out of service, and cars
        that did not come when called (broken, or an operator's), stay excluded.
        """
        again = {car for car in run.excluded - run.faulty if not self._out_of_service(car)}
        if not again or run.requeues >= MAX_REQUEUES:
            return None
        try:
            route = self._rest_of_route(run, run.excluded - again)
        except NoRoute:
            return None
        run.requeues += 1
        run.excluded -= again
        log.info("%s route %d: no other car; queueing again for %s", self.robot_id,
                 run.attempt_id, ", ".join(sorted(again)))
        return route

    def _rest_of_route(self, run: RouteRun, excluded: set[str]) -> Route:
        """The route from where the robot stands to ``run``'s goal, leaving ``excluded`` out.

        Raises:
            NoRoute: no car that is left takes it there.
        """
        assert self._map_name is not None and self._stack is not None
        return self._plan_route(self._map_name, self._stack.estimate.pose, run.goal_map,
                                run.goal, run.goal_point, excluded=excluded)

    def _switch_map(self, run: RouteRun, map_name: str, pose: Pose2D) -> None:
        """Navigate on ``map_name`` from now on, localized at ``pose`` (no mode change)."""
        old = self._map_name
        grid = self.store.load_map(map_name)
        keepouts = tuple(self.store.keepouts(map_name))
        self._map_name = map_name
        self._grid = grid
        self._keepouts = keepouts
        stack = self._new_stack()
        now = self.now()
        stack.initialize(pose, now)
        self._stack = stack
        run.nav_id = None
        floor = self._floor_of_map(map_name)
        log.info("route %d: map %s -> %s at %s", run.attempt_id, old, map_name, pose)
        self._publish(events.PoseInitialized(now, pose))
        self._publish(MapSwitched(now, run.attempt_id, old or "", map_name, floor))

    def _floor_of_map(self, map_name: str) -> str:
        record = self.store.map_record(map_name)
        return self._place.floor_of(self.store, map_name, getattr(record, "floor", None))

    def _near(self, pose: Pose2D, distance: float) -> bool:
        here = self._pose()
        return math.hypot(here.x - pose.x, here.y - pose.y) <= distance

    def _pose(self) -> Pose2D:
        stack = self._stack
        assert stack is not None
        return stack.estimate.pose

    def _route_overlay(self, snapshot: StatusSnapshot) -> StatusSnapshot:
        """The snapshot as callers see a cross-map goal: one attempt, its legs, its phase."""
        run = self._route or self._route_last
        if run is None or (self._route is None and (self._attempts.attempt_id or 0)
                           > run.attempt_id):
            return snapshot
        return overlay(snapshot, run)

    # -- parts the runtime supplies ------------------------------------------------------------

    @abc.abstractmethod
    def _new_stack(self) -> NavigationStack:
        """A navigation stack on the current map (the runtime's)."""

    @abc.abstractmethod
    def stack_config(self) -> StackConfig:
        """The stack's configuration now (the runtime's)."""

    @abc.abstractmethod
    def _publish(self, event: events.RuntimeEvent) -> None:
        """Publish a runtime event (the runtime's)."""
