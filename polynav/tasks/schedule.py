"""When a schedule starts its task: the modes, their checks and the next due start.

Pure calendar arithmetic on naive date-times of the robot's calendar (the runtime maps its
clock onto it: ``calendar_epoch`` + clock seconds, docs/decisions.md "Task schedules"). The
modes mirror Puwei's task modes (puwei-api.md, ``mode`` 1-3) so that its adapter maps onto
them field by field:

* ``once`` (Puwei 1, "timed"): one start at a date-time (``at``).
* ``weekly`` (Puwei 2): on ``weekdays`` (Puwei's ``opt``, Sunday = 0) at each of ``times``.
* ``monthly`` (Puwei 3): on ``days`` of the month (1-31, Puwei's ``opt``) at each of
  ``times``; a month without the day (day 31 in April, 30 in February) is skipped.

``times`` are times of day, as Puwei's ``hour`` and ``minute`` lists make them (every hour
with every minute). ``loop`` is how many times the schedule starts the task, 0 for ever
(Puwei's ``loop`` is not defined further, A-28: this is our reading). Puwei's mode 0
("immediate") is a start, not a schedule.
"""

from __future__ import annotations

import calendar
import datetime as dt
import enum
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from typing import Any

from polynav.errors import InvalidRequest

#: A schedule waiting for a busy robot gives up after this long [s] (docs/decisions.md).
BUSY_WAIT = 300.0


class ScheduleMode(enum.Enum):
    ONCE = "once"
    WEEKLY = "weekly"
    MONTHLY = "monthly"


WEEKDAYS = ("monday", "tuesday", "wednesday", "thursday", "friday", "saturday", "sunday")
"""Weekday names by Python's number (Monday = 0); three-letter forms are accepted too."""


def parse_weekday(name: object) -> int:
    """Python's weekday number (Monday = 0) of ``"monday"`` or ``"mon"`` (any case).

    Raises:
        InvalidRequest: not a weekday.
    """
    if isinstance(name, str):
        key = name.strip().lower()
        for number, day in enumerate(WEEKDAYS):
            if key in (day, day[:3]):
                return number
    raise InvalidRequest("weekdays", f"unknown weekday {name!r}; known: {', '.join(WEEKDAYS)}")


def puwei_weekday(opt: int) -> int:
    """Python's weekday number of Puwei's ``opt`` weekday (Sunday = 0 ... Saturday = 6).

    Raises:
        InvalidRequest: not 0-6.
    """
    if isinstance(opt, bool) or not isinstance(opt, int) or not 0 <= opt <= 6:
        raise InvalidRequest("weekdays", f"a Puwei weekday is 0 (Sunday) to 6, got {opt!r}")
    return (opt - 1) % 7


def parse_time(text: object) -> dt.time:
    """A time of day from ``"HH:MM"`` or ``"HH:MM:SS"``.

    Raises:
        InvalidRequest: another form, or an hour, minute or second out of range.
    """
    if isinstance(text, str):
        parts = text.split(":")
        if 2 <= len(parts) <= 3 and all(p.isdigit() and len(p) == 2 for p in parts):
            hour, minute, second = (int(p) for p in (*parts, "00")[:3])
            if hour > 23 or minute > 59 or second > 59:
                raise InvalidRequest("times", f"{text!r} is out of range (00:00 to 23:59:59)")
            return dt.time(hour, minute, second)
    raise InvalidRequest("times", f"a time of day is 'HH:MM' or 'HH:MM:SS', got {text!r}")


def parse_datetime(text: object) -> dt.datetime:
    """A calendar date-time from ISO ``YYYY-MM-DDTHH:MM[:SS]`` (no time zone: the robot's
    calendar is local).

    Raises:
        InvalidRequest: another form, or a date that does not exist (30 February).
    """
    if not isinstance(text, str):
        raise InvalidRequest("at", f"a date-time is 'YYYY-MM-DDTHH:MM[:SS]', got {text!r}")
    try:
        when = dt.datetime.fromisoformat(text)
    except ValueError as exc:
        raise InvalidRequest("at", f"{text!r} is not a date-time that exists "
                                   f"(YYYY-MM-DDTHH:MM[:SS]): {exc}") from None
    if when.tzinfo is not None:
        raise InvalidRequest("at", "give the robot's local date-time, without a time zone")
    return when


@dataclass(frozen=True, slots=True)
class ScheduleSpec:
    """When a schedule starts its task (the module docstring).

    Attributes:
        mode: once, weekly or monthly.
        at: the date-time of a ``once`` schedule.
        times: the times of day of a weekly or monthly schedule, sorted, no repeats.
        weekdays: Python weekday numbers (Monday = 0) of a weekly one, sorted.
        days: days of the month (1-31) of a monthly one, sorted.
        loop: how many starts, 0 for ever (a ``once`` schedule starts once).
    """

    mode: ScheduleMode
    at: dt.datetime | None = None
    times: tuple[dt.time, ...] = ()
    weekdays: tuple[int, ...] = ()
    days: tuple[int, ...] = ()
    loop: int = 0

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> ScheduleSpec:
        """Check and read the JSON form (:meth:`to_json`).

        Raises:
            InvalidRequest: an unknown mode, a field the mode does not take or lacks, an
                unknown weekday, a day no month has, a time or date out of range.
        """
        try:
            mode = ScheduleMode(data.get("mode"))
        except ValueError:
            raise InvalidRequest("mode", f"one of once, weekly, monthly; got "
                                         f"{data.get('mode')!r}") from None
        loop = data.get("loop", 0)
        if isinstance(loop, bool) or not isinstance(loop, int) or loop < 0:
            raise InvalidRequest("loop", f"a count of starts >= 0 (0 for ever), got {loop!r}")
        given = {k for k, v in data.items() if v not in (None, [])}
        wanted = {ScheduleMode.ONCE: {"at"}, ScheduleMode.WEEKLY: {"times", "weekdays"},
                  ScheduleMode.MONTHLY: {"times", "days"}}[mode]
        for key in sorted(({"at", "times", "weekdays", "days"} - wanted) & given):
            raise InvalidRequest(key, f"a {mode.value} schedule takes {', '.join(sorted(wanted))}"
                                      f", not {key}")
        for key in sorted(wanted - given):
            raise InvalidRequest(key, f"a {mode.value} schedule needs {key}")
        if mode is ScheduleMode.ONCE:
            if loop > 1:
                raise InvalidRequest("loop", "a once schedule starts its task once")
            return cls(mode, at=parse_datetime(data["at"]), loop=1)
        times = tuple(sorted({parse_time(t) for t in _items(data, "times")}))
        if mode is ScheduleMode.WEEKLY:
            weekdays = tuple(sorted({parse_weekday(d) for d in _items(data, "weekdays")}))
            return cls(mode, times=times, weekdays=weekdays, loop=loop)
        days = tuple(sorted({_day(d) for d in _items(data, "days")}))
        return cls(mode, times=times, days=days, loop=loop)

    def to_json(self) -> dict[str, Any]:
        """The JSON form: ``mode``, ``loop`` and the mode's fields (``at`` ISO, ``times``
        ``"HH:MM:SS"``, ``weekdays`` names, ``days`` numbers)."""
        out: dict[str, Any] = {"mode": self.mode.value, "loop": self.loop}
        if self.at is not None:
            out["at"] = self.at.isoformat(timespec="seconds")
        if self.times:
            out["times"] = [t.isoformat(timespec="seconds") for t in self.times]
        if self.weekdays:
            out["weekdays"] = [WEEKDAYS[d] for d in self.weekdays]
        if self.days:
            out["days"] = list(self.days)
        return out

    def next_fire(self, after: dt.datetime) -> dt.datetime | None:
        """The first start strictly after ``after``; ``None`` when there is none (a once
        schedule whose time has passed)."""
        if self.mode is ScheduleMode.ONCE:
            assert self.at is not None
            return self.at if self.at > after else None
        if self.mode is ScheduleMode.WEEKLY:
            dates: Iterable[dt.date] = (after.date() + dt.timedelta(days=d) for d in range(8))
            dates = (d for d in dates if d.weekday() in self.weekdays)
        else:
            dates = self._month_days(after.date())
        for date in dates:
            for time in self.times:
                when = dt.datetime.combine(date, time)
                if when > after:
                    return when
        return None

    def _month_days(self, start: dt.date) -> Iterable[dt.date]:
        """The schedule's days from ``start`` on, over the next 14 months (any day 1-31 comes
        at least every second month, so a start is always found)."""
        year, month = start.year, start.month
        for _ in range(14):
            last = calendar.monthrange(year, month)[1]
            for day in self.days:
                if day <= last and dt.date(year, month, day) >= start:
                    yield dt.date(year, month, day)
            year, month = (year + 1, 1) if month == 12 else (year, month + 1)


def check_not_past(spec: ScheduleSpec, now: dt.datetime) -> dt.datetime:
    """The first start of ``spec`` after ``now``.

    Raises:
        InvalidRequest: a once schedule at or before ``now``.
    """
    first = spec.next_fire(now)
    if first is None:
        assert spec.at is not None
        raise InvalidRequest("at", f"{spec.at.isoformat(timespec='seconds')} is in the past "
                                   f"(the robot's calendar says "
                                   f"{now.isoformat(timespec='seconds')})")
    return first


def _items(data: Mapping[str, Any], key: str) -> list[Any]:
    value = data.get(key)
    if not isinstance(value, list) or not value:
        raise InvalidRequest(key, "a non-empty list")
    return value


def _day(value: object) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= 31:
        raise InvalidRequest("days", f"a day of the month is 1 to 31 (a month without it is "
                                     f"skipped); no month has day {value!r}")
    return value
