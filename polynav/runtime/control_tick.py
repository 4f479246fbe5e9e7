"""The runtime's part that runs one physics step's work: timers, the dead-man and the control
tick, with the state checks that publish events (e-stop, localization, battery).

This is the runtime's periodic job, kept apart from its construction, reads and commands so
that the order of one tick (navigation stack, route and lift, no-entry signs, doors, mapping,
direct motion, watchers, tasks, device) reads in one place. The tick loop is the only caller
(:mod:`~polynav.runtime.loop`, or the fleet's shared world through :meth:`ControlTick.tick`).
"""

from __future__ import annotations

import abc
from typing import TYPE_CHECKING

from polynav.geometry import Twist
from polynav.localization.interface import LocalizationState
from polynav.runtime import events
from polynav.runtime.internals import RuntimeParts
from polynav.runtime.step_hooks import StepHooks
from polynav.runtime.watchers import BatteryWatcher, LocalizationWatcher

if TYPE_CHECKING:
    from polynav.runtime.auto_charge import AutoCharge
    from polynav.runtime.device import Device
    from polynav.runtime.device_commands import Peripherals
    from polynav.runtime.door_passage import DoorPassage
    from polynav.runtime.no_entry import NoEntrySigns

_EPS = 1e-9


class ControlTick(RuntimeParts):
    """Everything of one physics step but the physics (set up by the runtime)."""

    _hooks: StepHooks
    _control_period: float
    _next_control: float
    _localization: LocalizationWatcher
    _battery: BatteryWatcher
    _no_entry: NoEntrySigns
    _auto_charge: AutoCharge
    doors_rule: DoorPassage
    device: Device
    peripherals: Peripherals

    @abc.abstractmethod
    def _route_tick(self, now: float) -> None:
        """Follow a goal on another map's route (lift commands)."""

    @abc.abstractmethod
    def _hold_tick(self, now: float) -> None:
        """Keep or let go a lift held for the robot (lift access)."""

    @abc.abstractmethod
    def _free_ahead(self, direction: float, remaining: float) -> float:
        """The free distance ahead of a local move (motion commands)."""

    @abc.abstractmethod
    def _refresh(self) -> None:
        """Rebuild the status snapshot now (the runtime)."""

    def tick(self) -> None:
        """Everything of one physics step but the physics: timers, the dead-man and, when due,
        a control tick. Robots sharing one simulated world are each ticked, then the world is
        stepped once (:mod:`polynav.house.building`); call it between steps only."""
        now = self.now()
        self._hooks.run_due(now)
        self._motion.brake_if_expired(now)  # the dead-man
        if now >= self._next_control - _EPS:
            self._control(now)
            self._next_control += self._control_period
            if self._next_control <= now:
                self._next_control = now + self._control_period

    def _control(self, now: float) -> None:
        estop = self._check_estop(now)
        stack = self._stack
        if stack is not None:
            if self._settings_dirty and not self._goal_active():
                stack = self._rebuild_stack()
            stack.software_estop = self._software_estop
            stack.tick(now)
            self._attempts.follow(stack.navigator.attempt)
            self._route_tick(now)
            stack = self._stack  # a lift ride switches maps: a new stack
        self._hold_tick(now)
        self._no_entry.tick(now, stack, self._attempts.attempt_id)
        self.doors_rule.tick(now)
        explored = self._map_tick(now, estop)
        override = self._motion.override(now, estop, self._free_ahead)
        commanded = Twist()
        if override is not None:
            self._robot.drive(override)
            commanded = override
        elif explored is not None:
            self._robot.drive(explored)
            commanded = explored
        elif stack is None:
            self._robot.drive(Twist())
        else:
            commanded = stack.command
        self._check_localization(now)
        if stack is not None and self._grid is not None:  # LOST is published, then searched
            lost = stack.estimate.state is LocalizationState.LOST
            self._recovery.tick(now, lost, self._grid, self._robot.read_scan())
        self._check_battery(now)
        self._auto_charge.tick(now)
        self.tasks.tick(now)
        self.device.tick(now, commanded)
        self.peripherals.tick(now)
        self._refresh()

    def _map_tick(self, now: float, estop: bool) -> Twist | None:
        """Feed the mapping session; the exploration's velocity while it explores."""
        session = self._mapping
        if session is None:
            return None
        odometry, scan = self._robot.read_odometry(), self._robot.read_scan()
        session.tick(odometry, scan)
        exploration = self._exploration
        if exploration is None or exploration.done:
            return None
        twist = exploration.tick(now, session.live_map, session.pose, odometry.twist, scan,
                                 estop)
        if exploration.done:
            self._publish(events.ExplorationFinished(now, exploration.targets))
        return twist

    # -- state checks that publish events ----------------------------------------------------

    def _check_estop(self, now: float) -> bool:
        event = self._estop.update(now, self._robot.estop_pressed(), self._software_estop)
        if event is not None:
            self._publish(event)
        return self._estop.active

    def _check_localization(self, now: float) -> None:
        if self._stack is None:
            state, quality = LocalizationState.UNINITIALIZED.value, 0.0
        else:
            estimate = self._stack.estimate
            state, quality = estimate.state.value, estimate.quality
        event = self._localization.update(now, state, quality)
        if event is not None:
            self._publish(event)

    def _check_battery(self, now: float) -> None:
        battery = self._robot.read_battery()
        for event in self._battery.update(now, battery, self._settings.low_battery_percent):
            self._publish(event)
