"""Schedule modes: the next due start (pure calendar arithmetic) and the checks on input."""

from __future__ import annotations

import datetime as dt

import pytest

from polynav.errors import InvalidRequest
from polynav.tasks.schedule import ScheduleMode, ScheduleSpec, check_not_past, puwei_weekday

MONDAY_9 = dt.datetime(2030, 1, 7, 9, 0)  # 7 January 2030 is a Monday


def test_weekly_crosses_the_week_boundary_to_the_next_monday() -> None:
    spec = ScheduleSpec.from_json({"mode": "weekly", "weekdays": ["mon", "Wednesday"],
                                   "times": ["09:00", "17:30"]})
    assert spec.next_fire(MONDAY_9 - dt.timedelta(seconds=1)) == MONDAY_9
    assert spec.next_fire(MONDAY_9) == dt.datetime(2030, 1, 7, 17, 30)
    assert spec.next_fire(dt.datetime(2030, 1, 9, 17, 30)) == dt.datetime(2030, 1, 14, 9, 0)
    assert spec.next_fire(dt.datetime(2030, 1, 12, 23, 59)) == dt.datetime(2030, 1, 14, 9, 0)


def test_monthly_skips_months_without_the_day() -> None:
    spec = ScheduleSpec.from_json({"mode": "monthly", "days": [31], "times": ["08:00"]})
    assert spec.next_fire(dt.datetime(2030, 1, 31, 8, 0)) == dt.datetime(2030, 3, 31, 8, 0)
    assert spec.next_fire(dt.datetime(2030, 3, 31, 9, 0)) == dt.datetime(2030, 5, 31, 8, 0)
    feb = ScheduleSpec.from_json({"mode": "monthly", "days": [29, 30], "times": ["08:00"]})
    assert feb.next_fire(dt.datetime(2030, 1, 30, 9, 0)) == dt.datetime(2030, 3, 29, 8, 0)
    assert feb.next_fire(dt.datetime(2032, 2, 1)) == dt.datetime(2032, 2, 29, 8, 0)  # leap
    assert spec.next_fire(dt.datetime(2030, 12, 31, 9, 0)) == dt.datetime(2031, 1, 31, 8, 0)


def test_once_fires_once_and_in_the_past_is_refused() -> None:
    spec = ScheduleSpec.from_json({"mode": "once", "at": "2030-01-07T09:00"})
    assert (spec.mode, spec.loop) == (ScheduleMode.ONCE, 1)
    assert check_not_past(spec, MONDAY_9 - dt.timedelta(minutes=1)) == MONDAY_9
    assert spec.next_fire(MONDAY_9) is None
    with pytest.raises(InvalidRequest, match="in the past"):
        check_not_past(spec, MONDAY_9)


@pytest.mark.parametrize(("data", "field", "words"), [
    ({"mode": "once", "at": "2030-02-30T09:00"}, "at", "day is out of range"),
    ({"mode": "once", "at": "2030-02-31T09:00"}, "at", "exists"),
    ({"mode": "once", "at": "2030-01-07T09:00+01:00"}, "at", "time zone"),
    ({"mode": "monthly", "days": [32], "times": ["09:00"]}, "days", "no month has day 32"),
    ({"mode": "monthly", "days": [0], "times": ["09:00"]}, "days", "1 to 31"),
    ({"mode": "weekly", "weekdays": ["funday"], "times": ["09:00"]}, "weekdays", "unknown"),
    ({"mode": "weekly", "weekdays": ["mon"], "times": ["24:00"]}, "times", "out of range"),
    ({"mode": "weekly", "weekdays": ["mon"], "times": ["09:60"]}, "times", "out of range"),
    ({"mode": "weekly", "weekdays": ["mon"], "times": ["9am"]}, "times", "HH:MM"),
    ({"mode": "weekly", "weekdays": ["mon"]}, "times", "needs times"),
    ({"mode": "weekly", "weekdays": ["mon"], "times": ["09:00"], "days": [1]}, "days", "not"),
    ({"mode": "daily"}, "mode", "once, weekly, monthly"),
    ({"mode": "weekly", "weekdays": ["mon"], "times": ["09:00"], "loop": -1}, "loop", ">= 0"),
    ({"mode": "once", "at": "2030-01-07T09:00", "loop": 3}, "loop", "once"),
])
def test_bad_schedules_are_refused_naming_the_field(
        data: dict[str, object], field: str, words: str) -> None:
    with pytest.raises(InvalidRequest, match=words) as refused:
        ScheduleSpec.from_json(data)
    assert refused.value.field == field


def test_json_round_trip_and_puwei_weekdays() -> None:
    data = {"mode": "weekly", "weekdays": ["sunday", "monday"], "times": ["16:35:00"],
            "loop": 10}
    spec = ScheduleSpec.from_json(data)
    assert spec.to_json() == {"mode": "weekly", "loop": 10, "times": ["16:35:00"],
                              "weekdays": ["monday", "sunday"]}
    assert ScheduleSpec.from_json(spec.to_json()) == spec
    assert [puwei_weekday(n) for n in (0, 1, 6)] == [6, 0, 5]
