"""The androidmsg status topics (ros1-nav-iface §1.1-1.10): ``std_msgs/Int16`` codes from the
runtime's status and events.

Every status topic is latched (A33 leaves it open; a client that subscribes late learns the
state at once) and published when its code changes; the event codes of
``/androidmsg_navigationstatus`` are published every time they happen. The codes:

* navigation: 1 started, 2 arrived, 3 failed after its retries, 4 a retry (recovery), 6 no such
  point, 7 stopped by ``/navi_stop``, 8 no way now / a person in the way ("please make way"),
  51 the charger not reached, 52 no charger, 81/82 a compute-only plan found or not, 83
  cancelled otherwise, 84 not localized (relocalize first);
* charge: 41 not charging, 44 failed, 45 auto-charging, 46 charging by hand, 47/48 full;
* localization: 9 lost, 10 tracking; init: 12 once the runtime runs; e-stop: 31/32;
  ``/map_status``: 0 navigation, 1 mapping; ``/androidmsg_mapstatus``: 60/61 per map load.
"""

from __future__ import annotations

import threading

from polynav.nav.attempt import FailureReason
from polynav.protocols.ros_graph import Graph, RosError, Topic
from polynav.protocols.rosbridge.androidmsg import ids
from polynav.protocols.site_store import site_store
from polynav.rosmsg import encode
from polynav.runtime import events
from polynav.runtime.robot_runtime import RobotRuntime

INIT = "/androidmsg_initstatus"
ESTOP = "/androidmsg_emergencystatus"
CHARGE = "/androidmsg_chargestatus"
POWER = "/power_report"
LOCATION = "/androidmsg_locationstatus"
WALL_UPDATE = "/wall_update"
NAVIGATION = "/androidmsg_navigationstatus"
VIRTUAL_MAP = "/androidmsg_virtualmapstatus"
MAP_STATUS = "/map_status"
MAP_LOAD = "/androidmsg_mapstatus"

TOPICS = (INIT, ESTOP, CHARGE, POWER, LOCATION, WALL_UPDATE, NAVIGATION, VIRTUAL_MAP,
          MAP_STATUS, MAP_LOAD)

# Navigation codes (§1.7).
STARTED, ARRIVED, FAILED, RECOVERING, NO_POINT, STOPPED, MAKE_WAY = 1, 2, 3, 4, 6, 7, 8
CHARGER_NOT_REACHED, NO_CHARGER = 51, 52
PLAN_FOUND, PLAN_NOT_FOUND, CANCELLED, NOT_LOCALIZED = 81, 82, 83, 84
# Charge codes (§1.3).
NOT_CHARGING, CHARGE_FAILED, AUTO_CHARGING, MANUAL_CHARGING = 41, 44, 45, 46
AUTO_FULL, MANUAL_FULL = 47, 48

_NOT_LOCALIZED = {FailureReason.NOT_LOCALIZED.value, FailureReason.LOCALIZATION_LOST.value}


class StatusTopics:
    """Publishes the status topics of one runtime on one graph."""

    def __init__(self, graph: Graph, runtime: RobotRuntime) -> None:
        self._graph = graph
        self._runtime = runtime
        self._events = runtime.bus.subscribe(maxlen=1000)
        self._lock = threading.Lock()
        self._last: dict[str, int] = {}
        self._stopping = False  # a /navi_stop is on its way: its cancel is code 7
        self._charging_goal: int | None = None  # the attempt /autocharge started
        self._auto = False  # the current charge was started by the robot (auto-charge)

    def declare(self) -> None:
        for name in TOPICS:
            self._graph.add_topic(Topic(name, "std_msgs/Int16", latched=True))

    def close(self) -> None:
        self._runtime.bus.unsubscribe(self._events)

    # -- codes from the handlers (worker threads) ----------------------------------------------

    def code(self, topic: str, value: int) -> None:
        """Publish ``value`` on ``topic`` now (an event code: sent even when repeated)."""
        with self._lock:
            self._last[topic] = value
        self._graph.publish(topic, encode.int16(value))

    def stopping(self) -> None:
        """``/navi_stop`` is cancelling: the cancel it causes reports 7, not 83."""
        self._stopping = True

    def charging_started(self, attempt_id: int) -> None:
        """``/autocharge`` sent the robot to its charger as attempt ``attempt_id``."""
        self._charging_goal = attempt_id
        self._auto = True
        self.code(CHARGE, AUTO_CHARGING)

    # -- on the runtime's loop -----------------------------------------------------------------

    def on_step(self, now: float) -> None:
        for event in self._events.get_nowait():
            self._on_event(event)
        snap = self._runtime.status()
        self._state(INIT, 12)
        self._state(ESTOP, 31 if snap.estop_hardware or snap.estop_software else 32)
        self._state(POWER, int(round(snap.battery_percent)))
        self._state(MAP_STATUS, 1 if snap.mode == "mapping" else 0)
        if snap.localization_state == "tracking":
            self._state(LOCATION, 10)
        elif snap.localization_state == "lost":
            self._state(LOCATION, 9)
        full = snap.battery_percent >= self._runtime.settings().full_battery_percent
        if snap.charging:
            if self._auto:
                self._state(CHARGE, AUTO_FULL if full else AUTO_CHARGING)
            else:
                self._state(CHARGE, MANUAL_FULL if full else MANUAL_CHARGING)
        elif self._last.get(CHARGE) in (None, AUTO_FULL, MANUAL_FULL, MANUAL_CHARGING):
            self._auto = False
            self._state(CHARGE, NOT_CHARGING)

    def _state(self, topic: str, value: int) -> None:
        if self._last.get(topic) != value:
            self.code(topic, value)

    def _on_event(self, event: events.RuntimeEvent) -> None:
        if isinstance(event, events.NavigationStarted):
            self.code(NAVIGATION, STARTED)
        elif isinstance(event, events.NavigationSucceeded):
            self.code(NAVIGATION, ARRIVED)
        elif isinstance(event, events.NavigationRetry):
            self.code(NAVIGATION, RECOVERING)
        elif isinstance(event, (events.PlanningFailed, events.NavigationWaiting)):
            self.code(NAVIGATION, MAKE_WAY)
        elif isinstance(event, events.NavigationFailed):
            if event.attempt_id == self._charging_goal:
                self._charging_goal = None
                self._auto = False
                self.code(NAVIGATION, CHARGER_NOT_REACHED)
                self.code(CHARGE, CHARGE_FAILED)
            else:
                self.code(NAVIGATION, NOT_LOCALIZED if event.reason in _NOT_LOCALIZED
                          else FAILED)
        elif isinstance(event, events.NavigationCanceled):
            self.code(NAVIGATION, STOPPED if self._stopping else CANCELLED)
            self._stopping = False
        elif isinstance(event, events.AutoChargeStarted):
            self._auto = True
            self.code(CHARGE, AUTO_CHARGING)
        elif isinstance(event, events.AutoChargeEnded) and not event.charged:
            self._auto = False
            self.code(CHARGE, CHARGE_FAILED)
        elif isinstance(event, events.ModeChanged) and event.new == "navigating":
            self.code(MAP_LOAD, 60)


class Entries:
    """What every group of entries works on: the runtime, its site store read through the
    interface's ids, and the status topics it reports on."""

    def __init__(self, runtime: RobotRuntime, status: StatusTopics) -> None:
        self._runtime = runtime
        self._status = status
        self._store = site_store(runtime)
        self._site = ids.Site(self._store)

    def _map_in_use(self) -> str:
        """The map navigated on, else the map of the robot's floor.

        Raises:
            RosError: the robot is on no map of the site.
        """
        snap = self._runtime.status()
        if snap.map is not None:
            return snap.map
        floor = self._site.floor_named(snap.floor)
        if floor is None:
            raise RosError("the robot is on no map of the site")
        return floor.map_name
