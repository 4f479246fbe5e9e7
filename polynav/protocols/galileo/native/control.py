"""The native commands run on the robot, with the state rules of galileo-wire-protocols §1.4.

One :class:`NativeControl` per Galileo context serves every wire that carries the command bytes
(serial, ``/galileo/cmds`` on the WebSocket and on rosbridge, the UDP fast protocol) and the
Modbus registers, so they share the goal list and its dynamically inserted goals. Each command
goes through the same Galileo operations the HTTP API uses (navigation start/stop, tasks, loop,
charge, mapping), so a robot driven over the serial line looks the same to an HTTP client.

A command that is invalid in the current state is ignored, as the robot ignores it (§1.4: no
reply exists on the serial line); :class:`Outcome` says why for the log and for the wires that
can answer (Modbus).

Decisions (``docs/decisions.md``, "Galileo native commands"):

* Goals are the target points of the path in use (indices 0..k-1) followed by the goals ``g i``
  inserted on the map in use (k, k+1, ...); ``g r 0`` removes the inserted ones. An inserted goal
  has no heading: the robot arrives facing the way it drove (from where it was when sent).
* ``a sign angle``: the heading to turn to, in degrees of the map frame (A20 leaves absolute vs
  relative open; the command needs the visual localisation, which only an absolute heading
  does); progress in ``angleGoalStatus``.
* Teleop ``f b c d`` move at the percentage of the robot's maximum speed, ``s`` stops; like
  ``/cmd_vel`` they must keep coming (the runtime's dead-man stop), a serial client sends them
  at its control rate.
* ``m 5`` patrols the path's target points with the dwell ``m 5 t`` set (default 0 s).
* ``j 0`` drives to the charge pile and docks (the local charging of a robot near it), ``j 1``
  ends the charge task, ``j 2`` stores the pile where the robot stands.
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable
from dataclasses import dataclass, field

from polynav.errors import PolynavError
from polynav.geometry import Pose2D, wrap_angle
from polynav.protocols.galileo import charge, goals, loop, mapping, navigation
from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo import task_objects as objects
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.diagnostics import diagnostics
from polynav.protocols.galileo.messages import TargetStatus, VisualStatus
from polynav.protocols.galileo.native.commands import NativeCommand, UnknownCommand, parse_command
from polynav.protocols.galileo.native.marks import marks
from polynav.protocols.galileo.params import Params
from polynav.protocols.galileo.status import target_fields, visual_status

log = logging.getLogger(__name__)

ANGLE_TASK = "angle task"
#: Longest dwell ``m 5 t`` can set (one byte).
MAX_LOOP_WAIT = 255


@dataclass(frozen=True, slots=True)
class Outcome:
    """Whether a command was carried out; ``reason`` says why not (or what it did)."""

    accepted: bool
    reason: str = ""


ACCEPTED = Outcome(True)


def _ignored(reason: str) -> Outcome:
    return Outcome(False, reason)


@dataclass
class _Remembered:
    """What the native commands leave set for later ones: the goals ``g i`` inserted, per map,
    and the loop's dwell time ``m 5 t``."""

    inserted: dict[str, list[tuple[float, float]]] = field(default_factory=dict)
    loop_wait: int = 0
    lock: threading.Lock = field(default_factory=threading.Lock)


class NativeControl:
    """The native commands of one Galileo robot."""

    def __init__(self, ctx: Context) -> None:
        self._ctx = ctx
        self._remembered = _Remembered()
        self._commands: dict[str, Callable[[NativeCommand], Outcome]] = {
            "m 0": lambda c: self.start_navigation(),
            "m 4": lambda c: self.stop_navigation(),
            "m 9": lambda c: self.reload_navigation(),
            "g": lambda c: self.go_to_goal(int(c.args[0])),
            "i 0": lambda c: self.pause(),
            "i 1": lambda c: self.resume(),
            "i 2": lambda c: self.cancel(),
            "g i": lambda c: self.insert_goal(c.args[0], c.args[1]),
            "g r 0": lambda c: self.reset_goals(),
            "f": lambda c: self.teleop_percent(c.args[0], 0.0),
            "b": lambda c: self.teleop_percent(-c.args[0], 0.0),
            "c": lambda c: self.teleop_percent(0.0, c.args[0]),
            "d": lambda c: self.teleop_percent(0.0, -c.args[0]),
            "s": lambda c: self.teleop_velocity(0.0, 0.0),
            "shutdown": lambda c: self.shutdown(),
            "a": lambda c: self.turn_to((-1 if c.args[0] else 1) * c.args[1]),
            "m 5": lambda c: self.start_loop(),
            "m 6": lambda c: self.stop_loop(),
            "m 5 t": lambda c: self.set_loop_wait(int(c.args[0])),
            "m 7": lambda c: self.enable_dispatch(),
            "m 8": lambda c: self.disable_dispatch(),
            "m 10": lambda c: self.reload_dispatch(),
            "V 0": lambda c: self.start_mapping(),
            "V 1": lambda c: self.stop_mapping(),
            "V 2": lambda c: self.save_map(),
            "V 3": lambda c: self.update_map(),
            "j 0": lambda c: self.start_charge(),
            "j 1": lambda c: self.stop_charge(),
            "j 2": lambda c: self.save_charge_dock(),
            "H 0": lambda c: self.set_greeting(True),
            "H 1": lambda c: self.set_greeting(False),
        }

    # -- the bytes ---------------------------------------------------------------------------

    def apply(self, payload: bytes) -> Outcome:
        """Run the command ``payload`` carries; never raises."""
        try:
            command = parse_command(payload)
        except UnknownCommand as exc:
            log.info("galileo native: ignored %s", exc)
            diagnostics(self._ctx).count("native.unknown")
            return _ignored(str(exc))
        return self.run(command)

    def run(self, command: NativeCommand) -> Outcome:
        """Run a decoded command; never raises."""
        try:
            outcome = self._commands[command.name](command)
        except PolynavError as exc:
            outcome = _ignored(str(exc))
        diagnostics(self._ctx).count("native.run" if outcome.accepted else "native.ignored")
        if outcome.accepted:
            log.info("galileo native: %s %s", command.name, command.args or "")
        else:
            log.info("galileo native: %s %s ignored: %s", command.name, command.args or "",
                     outcome.reason)
        return outcome

    # -- state read-outs ---------------------------------------------------------------------

    def _target_status(self) -> TargetStatus:
        snap = self._ctx.runtime.status()
        if marks(self._ctx).bad_goal_now(snap.attempt_id) is not None:
            return TargetStatus.ERROR
        target = self._ctx.target_of(snap.attempt_id)
        return TargetStatus(target_fields(snap, target)["targetStatus"])

    def _navigating(self) -> bool:
        return self._ctx.runtime.status().mode == "navigating"

    def _localized(self) -> bool:
        return visual_status(self._ctx.runtime.status()) in (VisualStatus.TRACKING,
                                                               VisualStatus.LOST)

    # -- goals -------------------------------------------------------------------------------

    def goal_count(self) -> int:
        """Target points of the path in use, and the goals inserted on the map in use."""
        map_name, path = self._map_and_path()
        stops = len(sessions.routes(self._ctx).route(map_name, path).stops)
        with self._remembered.lock:
            return stops + len(self._remembered.inserted.get(map_name, []))

    def _map_and_path(self) -> tuple[str, str]:
        map_name = sessions.current_map(self._ctx)
        return map_name, sessions.current_path(self._ctx, map_name)

    def go_to_goal(self, number: int) -> Outcome:
        """``g n`` (§1.4.3): cancel a working or paused goal, then go to goal ``number``, or
        show ``targetStatus`` 3 when there is no such goal."""
        if not self._navigating() or not self._localized():
            return _ignored("the visual system is not initialised (navigation not started)")
        sessions.require_goals_allowed(self._ctx)  # not in dispatch mode
        if self._target_status() in (TargetStatus.WORKING, TargetStatus.PAUSED):
            self._ctx.runtime.cancel()
        map_name, path = self._map_and_path()
        stops = len(sessions.routes(self._ctx).route(map_name, path).stops)
        with self._remembered.lock:
            inserted = list(self._remembered.inserted.get(map_name, []))
        if not 0 <= number < stops + len(inserted):
            marks(self._ctx).mark_bad_goal(number, self._ctx.runtime.status().attempt_id)
            return _ignored(f"goal {number} does not exist ({stops + len(inserted)} goals)")
        marks(self._ctx).clear_bad_goal()
        if number < stops:
            final = goals.nav_to_target(self._ctx, map_name, path, number)
        else:
            x, y = inserted[number - stops]
            here = self._ctx.runtime.status().pose
            heading = math.atan2(y - here.y, x - here.x) if (x, y) != (here.x, here.y) \
                else here.theta
            final = {**goals.nav_to_pose(Pose2D(x, y, heading), map_name),
                     "path": path, "index": number}
        actions = goals.plan_actions(self._ctx, map_name, final, path)
        objects.run(self._ctx, goals.NAVIGATION_TASK, actions, kind=objects.NAVIGATION)
        return ACCEPTED

    def insert_goal(self, x: float, y: float) -> Outcome:
        """``g i x y``: append a goal at (x, y) of the map in use."""
        if not (math.isfinite(x) and math.isfinite(y)):
            return _ignored(f"goal ({x}, {y}) is not a finite coordinate")
        map_name = sessions.current_map(self._ctx)
        with self._remembered.lock:
            self._remembered.inserted.setdefault(map_name, []).append((float(x), float(y)))
        return ACCEPTED

    def reset_goals(self) -> Outcome:
        """``g r 0``: forget the inserted goals of the map in use."""
        map_name = sessions.current_map(self._ctx)
        with self._remembered.lock:
            self._remembered.inserted.pop(map_name, None)
        return ACCEPTED

    def move_to(self, x: float, y: float, theta: float) -> Outcome:
        """A goal at a pose of the map in use (Modbus 40008, SDK v2 ``MoveTo``)."""
        if not all(math.isfinite(v) for v in (x, y, theta)):
            return _ignored("the goal pose must be finite")
        if not self._navigating() or not self._localized():
            return _ignored("the visual system is not initialised (navigation not started)")
        marks(self._ctx).clear_bad_goal()
        goals.start_nav_task(self._ctx, Params({"x": x, "y": y, "theta": theta}))
        return ACCEPTED

    def pause(self) -> Outcome:
        """``i 0``: only a working goal."""
        if self._target_status() is not TargetStatus.WORKING:
            return _ignored("no working goal to pause")
        task = objects.running(self._ctx)
        if task is not None:
            self._ctx.runtime.tasks.pause(task["id"])
        else:
            self._ctx.runtime.pause()
        return ACCEPTED

    def resume(self) -> Outcome:
        """``i 1``: only a paused goal."""
        if self._target_status() is not TargetStatus.PAUSED:
            return _ignored("no paused goal to resume")
        task = objects.running(self._ctx)
        if task is not None and task["state"] == "PAUSED":
            self._ctx.runtime.tasks.resume(task["id"])
        else:
            self._ctx.runtime.resume()
        return ACCEPTED

    def cancel(self) -> Outcome:
        """``i 2``: a goal that is not free (working, paused or in error) becomes free."""
        status = self._target_status()
        if status in (TargetStatus.FREE, TargetStatus.INVALID):
            return _ignored("no goal to cancel")
        if marks(self._ctx).clear_bad_goal():
            return ACCEPTED
        if status is TargetStatus.ERROR:
            return ACCEPTED  # a failed goal: nothing moves, the state reads free from now on
        self._ctx.runtime.cancel()
        return ACCEPTED

    # -- motion ------------------------------------------------------------------------------

    def teleop_percent(self, linear_percent: float, angular_percent: float) -> Outcome:
        settings = self._ctx.runtime.settings()
        return self.teleop_velocity(linear_percent / 100.0 * settings.max_linear_velocity,
                                    angular_percent / 100.0 * settings.max_angular_velocity)

    def teleop_velocity(self, linear: float, angular: float) -> Outcome:
        """Drive at ``linear`` [m/s] and ``angular`` [rad/s] (teleop, Modbus 40001/40003)."""
        if not (math.isfinite(linear) and math.isfinite(angular)):
            return _ignored("speeds must be finite")
        self._ctx.runtime.teleop(linear, angular)
        return ACCEPTED

    def turn_to(self, degrees: float) -> Outcome:
        """``a``: turn in place to ``degrees`` of the map frame (only when localized and no goal
        works or waits)."""
        if not self._localized():
            return _ignored("the visual system is not initialised")
        if self._target_status() not in (TargetStatus.FREE, TargetStatus.ERROR,
                                         TargetStatus.INVALID):
            return _ignored("a goal is working or paused")
        sessions.require_goals_allowed(self._ctx)
        turn = wrap_angle(math.radians(degrees) - self._ctx.runtime.status().pose.theta)
        action = {"type": "local_move_action", "angle": turn, "distance": 0.0, "method": 0}
        task = objects.run(self._ctx, ANGLE_TASK, [action], kind=objects.NAVIGATION)
        marks(self._ctx).mark_angle_task(str(task["id"]))
        return ACCEPTED

    def shutdown(self) -> Outcome:
        """``AA 44``: power the host off."""
        self._ctx.runtime.device.power.shutdown(reboot=False)
        return ACCEPTED

    # -- navigation and dispatch -------------------------------------------------------------

    def start_navigation(self) -> Outcome:
        """``m 0``: on the session's map and path; ignored while mapping or navigating."""
        mode = self._ctx.runtime.status().mode
        if mode in ("mapping", "navigating"):
            return _ignored(f"the robot is {mode}")
        navigation.navigation_start(self._ctx, Params({}))
        return ACCEPTED

    def stop_navigation(self) -> Outcome:
        """``m 4``."""
        if not self._navigating():
            return _ignored("navigation is not started")
        navigation.navigation_stop(self._ctx, Params({}))
        return ACCEPTED

    def reload_navigation(self) -> Outcome:
        """``m 9``: reload the path (and map) the session has set."""
        if not self._navigating():
            return _ignored("navigation is not started")
        navigation.reload(self._ctx, Params({"map": sessions.current_map(self._ctx)}))
        return ACCEPTED

    def enable_dispatch(self) -> Outcome:
        """``m 7``."""
        navigation.start_schedule_mode(self._ctx, Params({}))
        return ACCEPTED

    def disable_dispatch(self) -> Outcome:
        """``m 8``."""
        navigation.stop_schedule_mode(self._ctx, Params({}))
        return ACCEPTED

    def reload_dispatch(self) -> Outcome:
        """``m 10``: reload keeping the map, in dispatch mode."""
        if not sessions.session(self._ctx).dispatch:
            return _ignored("the robot is not in dispatch mode")
        return self.reload_navigation()

    # -- loop --------------------------------------------------------------------------------

    def start_loop(self) -> Outcome:
        """``m 5``: patrol the path's target points (navigation must be started)."""
        if not self._navigating():
            return _ignored("navigation is not started")
        if objects.running(self._ctx, objects.LOOP) is not None:
            return _ignored("the loop already runs")
        loop.post_loop_task(self._ctx, Params({"wait_time": self.loop_wait}))
        return ACCEPTED

    def stop_loop(self) -> Outcome:
        """``m 6``."""
        if loop.delete_loop_task(self._ctx, Params({})) is None:
            return _ignored("no loop runs")
        return ACCEPTED

    @property
    def loop_wait(self) -> int:
        with self._remembered.lock:
            return self._remembered.loop_wait

    def set_loop_wait(self, seconds: int) -> Outcome:
        """``m 5 t``: the dwell [s] at each goal of the next loop."""
        if not 0 <= seconds <= MAX_LOOP_WAIT:
            return _ignored(f"a dwell is 0..{MAX_LOOP_WAIT} s, not {seconds}")
        with self._remembered.lock:
            self._remembered.loop_wait = seconds
        return ACCEPTED

    # -- mapping -----------------------------------------------------------------------------

    def start_mapping(self) -> Outcome:
        """``V 0``: only when neither mapping nor navigating."""
        mode = self._ctx.runtime.status().mode
        if mode in ("mapping", "navigating"):
            return _ignored(f"the robot is {mode}")
        mapping.map_start(self._ctx, Params({}))
        return ACCEPTED

    def stop_mapping(self) -> Outcome:
        """``V 1``: save (as ``map/stop`` does) and stop."""
        if self._ctx.runtime.status().mode != "mapping":
            return _ignored("the robot is not mapping")
        mapping.map_stop(self._ctx, Params({}))
        return ACCEPTED

    def save_map(self) -> Outcome:
        """``V 2``: save the map so far under its working name, and go on mapping."""
        if self._ctx.runtime.status().mode != "mapping":
            return _ignored("the robot is not mapping")
        name = mapping.saving_name(self._ctx)
        mapping.save_current_map_image(self._ctx, Params({"name": name}))
        return ACCEPTED

    def update_map(self) -> Outcome:
        """``V 3``: map on top of the map in use (only when neither mapping nor navigating)."""
        mode = self._ctx.runtime.status().mode
        if mode in ("mapping", "navigating"):
            return _ignored(f"the robot is {mode}")
        mapping.map_update(self._ctx, Params({}))
        return ACCEPTED

    # -- charging and greeting ---------------------------------------------------------------

    def start_charge(self) -> Outcome:
        """``j 0``: to the pile and onto it."""
        if self._ctx.runtime.status().charging:
            return _ignored("already charging")
        charge.go_charge(self._ctx, Params({}))
        return ACCEPTED

    def stop_charge(self) -> Outcome:
        """``j 1``."""
        charge.stop_charge(self._ctx, Params({}))
        return ACCEPTED

    def save_charge_dock(self) -> Outcome:
        """``j 2``: the pile is where the robot stands."""
        charge.post_charge_pose(self._ctx, Params({}))
        return ACCEPTED

    def set_greeting(self, on: bool) -> Outcome:
        """``H 0`` / ``H 1``."""
        self._ctx.runtime.peripherals.set_greeting(on)
        return ACCEPTED


def native_control(ctx: Context) -> NativeControl:
    """The native control of ``ctx``'s robot (one per context)."""
    return ctx.state("galileo.native.control", lambda: NativeControl(ctx))
