"""Carts and cabins: dock to one, carry it anywhere the robot goes, leave it, with retries.

A **dock** (:meth:`CartCommands.dock`) takes a cart or cabin by its name or by the site point
it stands at. It is checked before anything moves (a name or point with no load, a load
heavier than the profile's ``payload.max_mass``, a robot that carries something already or is
not navigating: a clear error, nothing changed); then:

1. *going*: a goal to the load's entry pose (behind it on its axis, facing in), through lifts
   if it is on another floor;
2. *seeing*: its legs are looked for in the scan near where it should stand
   (:func:`~polynav.docking.legs.find_legs`), so a load some centimetres off is still met;
3. *entering*: the robot drives in along the seen axis (a path-tracking law on the lateral and
   heading errors), re-seeing the legs on every scan, and stops over the load's centre;
4. *taking*: a cabin's tag is read first (an id other than the one asked for is refused: the
   robot backs out and the dock fails ``wrong_cabin``); a cart is lifted by raising the jacking
   axis, a cabin latched.

A try that fails seeing or aligning backs out to the entry pose and tries again, up to
:data:`DOCK_TRIES` tries (A-N9); the events say each retry and the final outcome.

While loaded the navigation stack plans and drives with the carried footprint (the hull of the
body and the load, :func:`~polynav.worlds.carts.carried_footprint`) and the profile's loaded
speeds; goals, patrols and lift rides work as ever. A **leave** (:meth:`CartCommands.leave`)
optionally carries the load to a point first, then lowers the jack (or opens the latch) and
drives straight out from under it; a way out that stays blocked fails the try, retried up to
:data:`LEAVE_TRIES` tries.

On the simulator the jacking axis is linked to the world's carts on every step, whoever moves
it (a Galileo ``jacking_move_to`` too): raised under a cart it lifts it, lowered it sets it
down (:mod:`polynav.robot.sim.jack_link`). The simulator's world is where loads are known from:
a real robot's site has no carts yet, and docking there is refused with that reason.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from typing import TYPE_CHECKING

from polynav.docking.detector import points_of_scan
from polynav.docking.legs import find_legs
from polynav.errors import Conflict, InvalidRequest, PolynavError
from polynav.geometry import Pose2D, Twist, angle_diff
from polynav.nav.attempt import GoalOptions
from polynav.nav.stack import StackConfig
from polynav.robot.devices import AxisMode
from polynav.runtime.cart_events import CartAction, CartFailure, CartStep
from polynav.runtime.cart_jobs import CartJob, Load, Phase, loaded_config
from polynav.worlds.carts import CartKind, WorldCart, entry_pose

if TYPE_CHECKING:
    from polynav.runtime.robot_runtime import RobotRuntime

log = logging.getLogger(__name__)

DOCK_TRIES = 3
"""Tries of one dock (seeing and aligning; the way there is the navigator's own retries)."""
LEAVE_TRIES = 3
"""Tries of one leave (letting go and driving out)."""
ENTRY_CLEARANCE = 0.6
"""[m] from the load's back legs to the robot's centre where it waits to drive in."""
ALIGN_DISTANCE = 0.03
"""[m] a dock ends this near the load's centre as seen, or the try fails."""
ALIGN_HEADING = 0.05
"""[rad] and this near its heading."""
JACK_UP = 0.05
"""[m] the jacking axis's height that carries a cart."""
SEE_SCANS = 8
"""Scans looked at for the legs before a try fails ``not_seen``."""
STALL_TIME = 3.0
"""[s] without progress driving in or out: the way is blocked."""
TAKE_TIME = 15.0
"""[s] for the jack or latch to take or let go of the load."""
ENTER_SPEED = 0.15
"""[m/s] driving in and out."""


class CartCommands:
    """The robot's carts and cabins service (see the module docstring)."""

    def __init__(self, runtime: RobotRuntime) -> None:
        self._rt = runtime
        self._job: CartJob | None = None
        self.load: Load | None = None
        self._known: dict[str, tuple[str, Pose2D]] = {}  # where each load was left
        self.count = 0
        """Docks and leaves started so far (their numbers: task actions, dialects' ids)."""
        self._outcomes: dict[int, tuple[bool, str, str]] = {}
        self.last_goal: int | None = None
        """The attempt id of the last dock's or leave's goal (its way there), if it had one."""
        runtime.add_step_listener(self._on_step)

    # -- queries -----------------------------------------------------------------------------

    @property
    def busy(self) -> bool:
        return self._job is not None

    def loads(self) -> list[WorldCart]:
        """The carts and cabins of the robot's world (none on a real robot)."""
        sim = self._rt._sim
        return list(sim.world.carts) if sim is not None else []

    def where(self, cart: WorldCart) -> tuple[str, Pose2D]:
        """Where the robot believes ``cart`` stands: its floor and pose (the world's start, or
        where a robot of this runtime left it)."""
        return self._known.get(cart.name, (cart.floor, cart.pose))

    def outcome(self, number: int) -> tuple[bool, str, str] | None:
        """Once dock or leave ``number`` ended: whether it succeeded, the load's name and the
        reason it failed; ``None`` while it runs (or for a number never started)."""
        return self._outcomes.get(number)

    def status(self) -> dict[str, object]:
        """What the robot carries and what it is doing with carts, JSON-ready."""
        job = self._job
        load = self.load
        return {
            "load": None if load is None else {"name": load.cart.name,
                                               "kind": load.cart.kind.value,
                                               "mass": load.cart.mass},
            "action": None if job is None else {"action": job.action, "cart": job.cart.name,
                                                "load": job.cart.kind.value,
                                                "phase": job.phase.value,
                                                "attempt": job.attempt},
        }

    # -- commands ----------------------------------------------------------------------------

    def dock(self, *, cart: str | None = None, point: str | None = None,
             cabin_id: str | None = None) -> WorldCart:
        """Dock to the cart or cabin named ``cart``, or to the one standing at site point
        ``point`` of the current map; for a cabin, ``cabin_id`` is the id its tag must carry
        (``None``: any).

        Raises:
            InvalidRequest: neither or both of ``cart`` and ``point``; no such load; nothing
                stands at the point.
            Conflict: not NAVIGATING; busy with a load or carrying one; a load heavier than
                the profile carries, or a robot that carries nothing; carried by another robot.
        """
        if (cart is None) == (point is None):
            raise InvalidRequest("cart", "give exactly one of cart and point")

        def run() -> WorldCart:
            target = self._resolve(cart, point)
            self._check_can_take(target)
            if cabin_id is not None and target.kind is not CartKind.CABIN:
                raise InvalidRequest("cabin_id", f"{target.name} is a cart: only a cabin has "
                                                 "an id to check")
            floor, pose = self.where(target)
            rt = self._rt
            entry = entry_pose(pose, target.length, ENTRY_CLEARANCE)
            map_name = rt._sim.world.floor(floor).map_name if rt._sim is not None else floor
            goal_id = rt._start_goal(None, entry, map_name, None)
            self.count += 1
            self.last_goal = goal_id
            self._job = CartJob("dock", target, Phase.GOING, goal_id=goal_id, since=rt.now(),
                             cabin_id=cabin_id, number=self.count)
            self._publish(CartStep.STARTED)
            log.info("dock to %s %s: going to its entry %s on %s", target.kind.value,
                     target.name, entry, floor)
            return target

        return self._rt.run_between_ticks(run)

    def leave(self, *, point: str | None = None, map_name: str | None = None,
              then: Callable[[], None] | None = None) -> WorldCart:
        """Leave the load: carried to ``point`` (on ``map_name``, default the current map)
        first if one is given, then let go of and driven out from under; ``then`` runs on the
        loop once the load is left (a dialect's move that leaves first).

        Raises:
            Conflict: the robot carries nothing, or is busy docking or leaving.
            NotFound: no such point (when given).
        """
        def run() -> WorldCart:
            load = self.load
            if load is None:
                raise Conflict("the robot carries no cart or cabin to leave")
            if self._job is not None:
                raise Conflict(f"busy: a {self._job.action} of {self._job.cart.name} is under way")
            rt = self._rt
            job = CartJob("leave", load.cart, Phase.RELEASING, since=rt.now(), then=then)
            if point is not None:
                job.goal_id = rt._start_goal(point, None, map_name, GoalOptions())
                job.phase = Phase.CARRYING
            self.count += 1
            self.last_goal = job.goal_id
            job.number = self.count
            self._job = job
            self._publish(CartStep.STARTED)
            if job.phase is Phase.RELEASING:
                self._let_go()
            return load.cart

        return self._rt.run_between_ticks(run)

    def cancel(self) -> bool:
        """Stop a dock or leave under way (the robot halts where it is); whether one ran."""
        def run() -> bool:
            job = self._job
            if job is None:
                return False
            if job.phase in (Phase.GOING, Phase.CARRYING):
                self._rt._cancel_goal()
            self._rt._motion.halt()
            self._end(CartStep.FAILED, CartFailure.CANCELED, "canceled")
            return True

        return self._rt.run_between_ticks(run)

    # -- the navigation stack while loaded ------------------------------------------------------

    def stack_config(self, config: StackConfig) -> StackConfig:
        """``config`` for the robot as it is now: loaded, the carried footprint and the
        profile's loaded speeds (:func:`~polynav.runtime.cart_jobs.loaded_config`)."""
        return loaded_config(config, self._rt.profile, self.load)

    # -- internals ---------------------------------------------------------------------------

    def _resolve(self, cart: str | None, point: str | None) -> WorldCart:
        loads = self.loads()
        if not loads and self._rt._sim is None:
            raise Conflict("this robot's site has no carts or cabins: they are known from the "
                           "simulated world only")
        if cart is not None:
            for c in loads:
                if c.name == cart:
                    return c
            raise InvalidRequest("cart", f"no cart or cabin {cart!r}")
        assert point is not None
        rt = self._rt
        map_name = rt.map_name
        if map_name is None:
            raise Conflict("not navigating: start navigation on a map first")
        found = rt.store.point(map_name, point)
        floor = rt._floor_now()
        for c in loads:
            where_floor, where = self.where(c)
            if where_floor == floor and where.distance_to(found.pose) <= 0.3:
                return c
        raise InvalidRequest("point", f"nothing to dock to at point {point!r}: no cart or "
                                      "cabin stands there")

    def _check_can_take(self, cart: WorldCart) -> None:
        rt = self._rt
        if rt.map_name is None:
            raise Conflict("not navigating: start navigation on a map first")
        if self._job is not None:
            raise Conflict(f"busy: a {self._job.action} of {self._job.cart.name} is under way")
        if self.load is not None:
            raise Conflict(f"the robot already carries {self.load.cart.name}")
        if rt._goal_active():
            raise Conflict("a goal is active: cancel it before docking")
        payload = rt.profile.payload
        if payload is None:
            raise Conflict(f"robot {rt.profile.name!r} carries nothing (its profile has no "
                           "payload)")
        if cart.mass > payload.max_mass:
            raise Conflict(f"{cart.kind.value} {cart.name} weighs {cart.mass:g} kg: this robot "
                           f"carries at most {payload.max_mass:g} kg")
        sim = rt._sim
        if sim is not None:
            held = sim.scene.carts.carts[cart.name].carrier
            if held is not None:
                raise Conflict(f"{cart.name} is carried by {held}")

    def _publish(self, step: CartStep, reason: CartFailure | None = None,
                 detail: str = "") -> None:
        job = self._job
        assert job is not None
        self._rt.publish(CartAction(self._rt.now(), job.action, job.cart.name,
                                    job.cart.kind.value, step, job.attempt, reason, detail))

    def _end(self, step: CartStep, reason: CartFailure | None = None, detail: str = "") -> None:
        job = self._job
        if job is None:
            return
        self._publish(step, reason, detail)
        self._outcomes[job.number] = (step is CartStep.SUCCEEDED, job.cart.name,
                                      "" if reason is None else f"{reason.value}: {detail}")
        log.info("%s of %s %s%s", job.action, job.cart.name, step.value,
                 f": {reason.value}: {detail}" if reason else "")
        self._job = None
        if step is CartStep.SUCCEEDED and job.then is not None:
            try:
                job.then()
            except PolynavError as exc:
                log.warning("after leaving %s: %s", job.cart.name, exc)

    # -- stepping ----------------------------------------------------------------------------

    def _on_step(self, now: float) -> None:
        job = self._job
        if job is None:
            return
        try:
            self._tick(job, now)
        except Conflict as exc:  # the robot stopped navigating, an e-stop...
            self._rt._motion.halt()
            self._end(CartStep.FAILED, CartFailure.CANCELED, str(exc))

    def _tick(self, job: CartJob, now: float) -> None:
        rt = self._rt
        if job.phase in (Phase.GOING, Phase.CARRYING):
            state = self._goal_state(job)
            if state is None:
                return
            if state != "succeeded":
                if job.action == "leave":
                    self._end(CartStep.FAILED, CartFailure.NOT_REACHED,
                              f"the way to the point {state}")
                else:
                    self._end(CartStep.FAILED, CartFailure.NOT_REACHED,
                              f"the way to {job.cart.name} {state}")
                return
            if job.action == "leave":
                self._let_go()
                return
            self._enter_phase(job, Phase.SEEING, now)
            return
        stack = rt.navigation_stack
        if stack is None:
            raise Conflict("navigation stopped")
        estimate = stack.estimate.pose
        if job.phase is Phase.SEEING:
            self._see(job, now, estimate)
        elif job.phase is Phase.ENTERING:
            self._drive_in(job, now, estimate)
        elif job.phase is Phase.TAKING:
            self._take(job, now, estimate)
        elif job.phase is Phase.RELEASING:
            self._released(job, now, estimate)
        elif job.phase is Phase.EXITING:
            self._drive_out(job, now)

    def _goal_state(self, job: CartJob) -> str | None:
        status = self._rt.status()
        if status.attempt_id != job.goal_id:
            return None
        state = status.navigation_state
        return state if state in ("succeeded", "failed", "canceled") else None

    def _enter_phase(self, job: CartJob, phase: Phase, now: float) -> None:
        job.phase = phase
        job.since = now
        job.scans = 0
        odometry = self._rt.robot.read_odometry().pose
        job.start_odometry = odometry
        job.progress = 0.0
        job.progress_at = now

    def _seen(self, job: CartJob, estimate: Pose2D) -> Pose2D | None:
        """The load's pose in the newest scan (map frame), if a new scan shows its legs."""
        scan = self._rt.robot.read_scan()
        if scan is None or scan.stamp == job.last_scan:
            return None
        job.last_scan = scan.stamp
        job.scans += 1
        sensor = estimate.compose(scan.sensor_pose)
        expected = job.target or self.where(job.cart)[1]
        c = job.cart
        found = find_legs(points_of_scan(scan, estimate), (sensor.x, sensor.y), expected,
                          c.length, c.width, c.leg_radius)
        return None if found is None else found.pose

    def _see(self, job: CartJob, now: float, estimate: Pose2D) -> None:
        seen = self._seen(job, estimate)
        if seen is not None:
            job.target = seen
            log.info("%s seen at %s (%.3f m from where it should be)", job.cart.name, seen,
                     seen.distance_to(self.where(job.cart)[1]))
            self._enter_phase(job, Phase.ENTERING, now)
            return
        if job.scans >= SEE_SCANS:
            floor, pose = self.where(job.cart)
            self._retry_or_fail(job, now, CartFailure.NOT_SEEN,
                                f"no legs of {job.cart.name} near ({pose.x:.2f}, {pose.y:.2f}) "
                                f"on {floor}")

    def _drive_in(self, job: CartJob, now: float, estimate: Pose2D) -> None:
        seen = self._seen(job, estimate)
        target = job.target
        assert target is not None
        if seen is not None:  # blend: one noisy scan moves the target half way
            target = Pose2D(0.5 * (target.x + seen.x), 0.5 * (target.y + seen.y),
                            target.theta + 0.5 * angle_diff(seen.theta, target.theta))
            job.target = target
        error = estimate.relative_to(target)  # the robot in the load's frame
        if error.x >= -0.005:
            self._rt._motion.halt()
            heading = angle_diff(estimate.theta, target.theta)
            if math.hypot(error.x, error.y) > ALIGN_DISTANCE or abs(heading) > ALIGN_HEADING:
                self._retry_or_fail(job, now, CartFailure.NOT_ALIGNED,
                                    f"{math.hypot(error.x, error.y):.3f} m, {heading:.3f} rad "
                                    f"off {job.cart.name}'s centre")
                return
            self._enter_phase(job, Phase.TAKING, now)
            self._start_taking(job)
            return
        if self._stalled(job, now):
            self._retry_or_fail(job, now, CartFailure.BLOCKED, "the way in is blocked")
            return
        v = min(ENTER_SPEED, max(0.03, 0.8 * -error.x))
        heading = angle_diff(estimate.theta, target.theta)
        w = -2.0 * heading - math.atan2(2.0 * error.y, v + 0.05)
        self._rt._motion.teleop(Twist(v, max(-0.5, min(0.5, w))), now)

    def _stalled(self, job: CartJob, now: float) -> bool:
        odometry = self._rt.robot.read_odometry().pose
        assert job.start_odometry is not None
        covered = odometry.distance_to(job.start_odometry)
        if covered > job.progress + 0.01:
            job.progress, job.progress_at = covered, now
        return now - job.progress_at > STALL_TIME

    def _start_taking(self, job: CartJob) -> None:
        rt, sim = self._rt, self._rt._sim
        if job.cart.kind is CartKind.CABIN:
            tag = sim.cabin_tag() if sim is not None else None
            if job.cabin_id is not None and tag != job.cabin_id:
                job.failure = (CartFailure.WRONG_CABIN,
                               f"the latch read cabin id {tag!r}, not {job.cabin_id!r}")
                self._back_out(job)
                return
            if sim is not None:
                sim.latch()
            return
        rt.peripherals.devices.jacking.move(rt.now(), AxisMode.POSITION, target=JACK_UP,
                                            speed=0.03)

    def _take(self, job: CartJob, now: float, estimate: Pose2D) -> None:
        sim = self._rt._sim
        held = sim.load if sim is not None else None
        if held is not None and held.name == job.cart.name:
            target = job.target or held.pose
            self.load = Load(job.cart, target.relative_to(estimate))
            self._rt._settings_dirty = True  # the stack takes the carried footprint
            self._end(CartStep.SUCCEEDED)
            return
        if now - job.since > TAKE_TIME:
            job.failure = (CartFailure.NOT_TAKEN, f"the {self._holder(job)} did not take "
                                                  f"{job.cart.name}")
            self._lower(job)
            self._back_out(job)

    def _holder(self, job: CartJob) -> str:
        return "latch" if job.cart.kind is CartKind.CABIN else "jack"

    def _lower(self, job: CartJob) -> None:
        rt, sim = self._rt, self._rt._sim
        if job.cart.kind is CartKind.CABIN:
            if sim is not None:
                sim.unlatch()
            return
        rt.peripherals.devices.jacking.move(rt.now(), AxisMode.POSITION, target=0.0, speed=0.03)

    def _let_go(self) -> None:
        job = self._job
        assert job is not None
        self._enter_phase(job, Phase.RELEASING, self._rt.now())
        self._lower(job)

    def _released(self, job: CartJob, now: float, estimate: Pose2D) -> None:
        sim = self._rt._sim
        if sim is not None and sim.load is not None:
            if now - job.since > TAKE_TIME:
                self._retry_or_fail(job, now, CartFailure.NOT_RELEASED,
                                    f"the {self._holder(job)} did not let go of "
                                    f"{job.cart.name}")
            return
        load = self.load
        if load is not None:
            floor = self._rt._floor_now() or job.cart.floor
            self._known[job.cart.name] = (floor, estimate.compose(load.offset))
            self.load = None
            self._rt._settings_dirty = True
        self._back_out(job)

    def _back_out(self, job: CartJob) -> None:
        self._enter_phase(job, Phase.EXITING, self._rt.now())

    def _drive_out(self, job: CartJob, now: float) -> None:
        distance = 0.5 * job.cart.length + ENTRY_CLEARANCE - 0.1
        odometry = self._rt.robot.read_odometry().pose
        assert job.start_odometry is not None
        if odometry.distance_to(job.start_odometry) >= distance:
            self._rt._motion.halt()
            if job.failure is not None:
                reason, detail = job.failure
                job.failure = None
                if reason is CartFailure.WRONG_CABIN or job.attempt >= DOCK_TRIES:
                    self._end(CartStep.FAILED, reason, detail)
                    return
                job.attempt += 1
                self._publish(CartStep.RETRIED, reason, detail)
                job.target = None
                self._enter_phase(job, Phase.SEEING, now)
                return
            self._end(CartStep.SUCCEEDED)
            return
        if self._stalled(job, now):
            self._rt._motion.halt()
            tries = LEAVE_TRIES if job.action == "leave" else DOCK_TRIES
            if job.attempt >= tries:
                self._end(CartStep.FAILED, CartFailure.BLOCKED,
                          f"the way out from under {job.cart.name} is blocked")
                return
            job.attempt += 1
            self._publish(CartStep.RETRIED, CartFailure.BLOCKED,
                          f"the way out from under {job.cart.name} is blocked")
            job.progress_at = now  # try driving out again from here
            return
        self._rt._motion.teleop(Twist(-ENTER_SPEED, 0.0), now)

    def _retry_or_fail(self, job: CartJob, now: float, reason: CartFailure, detail: str) -> None:
        """A dock's try failed: back out to the entry pose and try again, or give up."""
        self._rt._motion.halt()
        if job.phase is Phase.SEEING:  # not in yet: look again from where it stands
            if job.attempt >= DOCK_TRIES:
                self._end(CartStep.FAILED, reason, detail)
                return
            job.attempt += 1
            self._publish(CartStep.RETRIED, reason, detail)
            self._enter_phase(job, Phase.SEEING, now)
            return
        if job.phase is Phase.RELEASING:
            if job.attempt >= LEAVE_TRIES:
                self._end(CartStep.FAILED, reason, detail)
                return
            job.attempt += 1
            self._publish(CartStep.RETRIED, reason, detail)
            self._let_go()
            return
        job.failure = (reason, detail)
        self._back_out(job)
