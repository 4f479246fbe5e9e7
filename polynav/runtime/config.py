"""The runtime's modes, its configuration, and what it reads from the site."""

from __future__ import annotations

import datetime as dt
import enum
import ipaddress
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Protocol

from polynav.automation.runner import AutomationLimits
from polynav.errors import ConfigError, InvalidRequest, check_positive
from polynav.maps.keepout import Keepout
from polynav.maps.map import Map
from polynav.runtime.http_callbacks import HttpCallbacks
from polynav.site import Point
from polynav.store.records import AutomationRecord, ConnectionRecord, ScheduleRecord, TaskRecord


class Mode(enum.Enum):
    FREE = "free"
    MAPPING = "mapping"
    NAVIGATING = "navigating"
    BUSY = "busy"


_HOST_NAME = re.compile(r"[A-Za-z0-9]([A-Za-z0-9-]{0,62})(\.[A-Za-z0-9]([A-Za-z0-9-]{0,62}))*")


def _is_network(text: str) -> bool:
    try:
        ipaddress.ip_network(text, strict=False)
    except ValueError:
        return False
    return True


@dataclass(frozen=True, slots=True)
class RuntimeConfig:
    """How the runtime runs.

    Attributes:
        control_rate: navigation stack ticks per simulated second [Hz].
        status_rate: the default rate [Hz] adapters stream status at; at most ``control_rate``
            (the snapshot itself is refreshed every control tick and after every command).
        speed: simulated seconds per wall second when the loop thread paces itself.
        teleop_timeout: a teleop command holds this long [s] (the dead-man).
        seed: seeds the simulator's noise.
        people: whether the simulated world's people walk.
        max_lag: when the loop falls behind its pace by more than this [s of wall time] (a
            slow machine, a speed beyond what it can compute, a debugger), it gives up catching
            up rather than race; simulated time then runs as fast as it can.
        automations: whether automation tasks (user programs, Galileo's Blockly tasks) may
            run; off by default, since a program is code sent over the network. Each runs in
            its own process within ``automation_limits``.
        task_callback_hosts: hosts a task's ``callback_action`` may call beside the loopback
            ones (``localhost``, 127.0.0.0/8, ::1), each a host name (matched exactly,
            case-insensitive) or an IP network (``10.0.0.0/8``, ``192.0.2.7``). Empty by
            default: a task given by any client must not make the robot a proxy into the
            site's network.
        dispatch_servers: (id, base URL) of the dispatch servers maps are exchanged with
            (``upload_map_action``, ``download_map_action``; :mod:`~polynav.runtime.map_exchange`),
            each on a host a callback may reach. None by default.
        calendar_epoch: the local calendar date-time (naive) that the runtime clock's 0
            stands for; schedules run on ``calendar_epoch + clock`` (docs/decisions.md, "Task
            schedules"). ``None``: the wall clock when the runtime is made. Simulated runs
            from tests pass a fixed one.
    """

    control_rate: float = 20.0
    status_rate: float = 10.0
    speed: float = 1.0
    teleop_timeout: float = 0.5
    seed: int = 0
    people: bool = True
    max_lag: float = 0.5
    automations: bool = False
    automation_limits: AutomationLimits = field(default_factory=AutomationLimits)
    task_callback_hosts: tuple[str, ...] = ()
    dispatch_servers: tuple[tuple[str, str], ...] = ()
    calendar_epoch: dt.datetime | None = None

    def __post_init__(self) -> None:
        epoch = self.calendar_epoch
        if epoch is not None and epoch.tzinfo is not None:
            raise ConfigError("runtime.calendar_epoch", "a local date-time without a time zone")
        for host in self.task_callback_hosts:
            if not (isinstance(host, str) and (_HOST_NAME.fullmatch(host) or _is_network(host))):
                raise ConfigError("runtime.task_callback_hosts",
                                  f"each must be a host name or an IP network, got {host!r}")
        hosts = HttpCallbacks(self.task_callback_hosts)
        for entry in self.dispatch_servers:
            if not (isinstance(entry, tuple) and len(entry) == 2 and entry[0]):
                raise ConfigError("runtime.dispatch_servers", f"each is (id, url), got {entry!r}")
            try:
                hosts.check(entry[1])
            except InvalidRequest as exc:
                raise ConfigError("runtime.dispatch_servers", f"{entry[0]}: {exc.reason}"
                                  ) from None
        check_positive(self, "runtime.", ("control_rate", "status_rate", "speed",
                                          "teleop_timeout", "max_lag"))
        if self.status_rate > self.control_rate:
            raise ConfigError("runtime.status_rate", "must be <= control_rate")


class FloorData(Protocol):
    """A floor as the runtime reads it (:class:`polynav.store.records.FloorRecord`)."""

    @property
    def level(self) -> int: ...

    @property
    def map_name(self) -> str: ...


class SiteData(Protocol):
    """What the runtime reads from the site store (:class:`polynav.store.SiteStore`)."""

    def floors(self) -> Sequence[object]: ...

    def floor(self, name: str) -> FloorData: ...

    def map_record(self, name: str) -> object: ...

    def load_map(self, name: str) -> Map: ...

    def points(
        self, *, map_name: str | None = None, floor: str | None = None
    ) -> Sequence[Point]: ...

    def point(self, map_name: str, name: str) -> Point: ...

    def keepouts(self, map_name: str) -> Sequence[Keepout]: ...

    def connections(self) -> Sequence[ConnectionRecord]: ...

    def settings(self) -> dict[str, object]: ...

    def update_settings(self, changes: Mapping[str, object]) -> dict[str, object]: ...

    def save_map(self, name: str, grid: Map, *, floor: str | None = None) -> object: ...

    def tasks(self) -> Sequence[TaskRecord]: ...

    def put_task(self, record: TaskRecord) -> None: ...

    def set_task_state(self, task_id: str, state: str, note: str, updated: str) -> None: ...

    def delete_task(self, task_id: str) -> None: ...

    def schedules(self, task_id: str | None = None) -> Sequence[ScheduleRecord]: ...

    def put_schedule(self, record: ScheduleRecord) -> None: ...

    def delete_schedule(self, schedule_id: str) -> None: ...

    def automations(self) -> Sequence[AutomationRecord]: ...

    def automation(self, automation_id: str) -> AutomationRecord: ...

    def put_automation(self, record: AutomationRecord) -> AutomationRecord: ...

    def delete_automation(self, automation_id: str) -> None: ...
