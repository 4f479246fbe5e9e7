"""Traffic zones found in a map: doorways are zones, wide corridors and rooms are not."""

from __future__ import annotations

import numpy as np
import pytest

from polynav.errors import ConfigError
from polynav.fleet.zones import ZoneConfig, find_zones
from polynav.maps.map import Map
from polynav.planning.path import Path

RES = 0.05


def _two_rooms(door: float) -> Map:
    """Two 4 m x 4 m rooms side by side (x 0..4 and 4.1..8.1), a ``door`` [m] wide gap in the
    wall between them at y 1.5..1.5+door; walls 0.1 m."""
    w, h = int(8.2 / RES), int(4.2 / RES)
    occ = np.zeros((h, w), dtype=bool)
    occ[:2, :] = occ[-2:, :] = True
    occ[:, :2] = occ[:, -2:] = True
    wall = int(4.05 / RES)
    occ[:, wall:wall + 2] = True
    lo, hi = int(1.5 / RES), int((1.5 + door) / RES)
    occ[lo:hi, wall:wall + 2] = False
    return Map.from_occupied(occ, resolution=RES)


def test_a_doorway_one_robot_wide_is_one_zone() -> None:
    zones = find_zones("m", _two_rooms(1.0))
    assert zones.count == 1
    assert zones.zone_at(4.1, 2.0) == 1
    assert zones.zone_at(4.1 - 0.5, 2.0) == 1  # the approach on either side
    assert zones.zone_at(2.0, 3.5) == 0 and zones.zone_at(6.0, 0.5) == 0
    assert zones.zone_id(1) == "zone:m/1"


def test_a_doorway_two_robots_wide_is_no_zone() -> None:
    assert find_zones("m", _two_rooms(2.5)).count == 0


def test_a_two_metre_corridor_is_a_zone_but_a_wider_one_is_not() -> None:
    # Two robots of 0.5 m cannot pass each other in 2 m with room to spare.
    assert find_zones("m", _two_rooms(2.0)).count == 1
    assert find_zones("m", _two_rooms(2.0), ZoneConfig(narrow_width=1.3)).count == 0


def test_zone_ahead_on_a_path_through_the_door_and_its_distance() -> None:
    zones = find_zones("m", _two_rooms(1.0))
    path = Path(np.array([[1.0, 2.0], [7.0, 2.0]]))
    found = zones.zone_ahead(path, 1.0, 2.0, lookahead=5.0)
    assert found is not None
    zone, distance = found
    assert zone == 1 and 2.2 < distance < 3.1
    assert zones.zone_ahead(path, 1.0, 2.0, lookahead=2.0) is None
    assert zones.zone_ahead(path, 4.1, 2.0, lookahead=5.0, skip=1) is None


def test_bad_zone_config_names_the_key() -> None:
    with pytest.raises(ConfigError) as err:
        ZoneConfig(narrow_width=0.4, robot_radius=0.25)
    assert err.value.key == "fleet.zones.narrow_width"


def test_a_path_leaves_the_zone_within_a_distance() -> None:
    zones = find_zones("m", _two_rooms(1.0))
    east = Path(np.array([[4.6, 2.0], [7.0, 2.0]]))
    west = Path(np.array([[4.6, 2.0], [1.0, 2.0]]))
    assert zones.zone_at(4.6, 2.0) == 1
    assert zones.leaves(east, 4.6, 2.0, 1, within=1.5)
    assert not zones.leaves(west, 4.6, 2.0, 1, within=1.5)  # it goes through the door
    ends_inside = Path(np.array([[4.6, 2.0], [4.2, 2.0]]))
    assert not zones.leaves(ends_inside, 4.6, 2.0, 1, within=1.5)


def test_the_flow_of_a_path_through_a_zone_is_the_way_it_goes() -> None:
    zones = find_zones("m", _two_rooms(1.0))
    east = Path(np.array([[1.0, 2.0], [7.0, 2.0]]))
    assert zones.flow(east, 1.0, 2.0, 1) == "EE"
    assert zones.flow(Path(east.points[::-1].copy()), 7.0, 2.0, 1) == "WW"
    # From inside the zone: from the robot to where the path leaves it.
    assert zones.flow(east, 4.0, 2.0, 1) == "EE"

    # A path that turns back at the door has no clear way through it.
    turn = Path(np.array([[1.0, 2.0], [3.6, 2.0], [1.0, 2.1]]))
    assert zones.flow(turn, 1.0, 2.0, 1) is None
    # A path that never reaches the zone has none either.
    assert zones.flow(Path(np.array([[1.0, 3.5], [2.0, 3.5]])), 1.0, 3.5, 1) is None


def _corridor_with_a_door() -> Map:
    """A corridor 1 m wide (y 4..5) along x 0..10 above a room (y 0..3.9), joined by a door
    at x 4.5..5.5 in the wall between them (y 3.9..4.0)."""
    w, h = int(10.0 / RES), int(5.2 / RES)
    occ = np.ones((h, w), dtype=bool)
    occ[int(4.0 / RES):int(5.0 / RES), :] = False
    occ[int(0.1 / RES):int(3.9 / RES), int(0.1 / RES):int(9.9 / RES)] = False
    occ[int(3.9 / RES):int(4.0 / RES), int(4.5 / RES):int(5.5 / RES)] = False
    return Map.from_occupied(occ, resolution=RES)


def test_ways_east_into_a_door_and_out_of_it_are_two_flows() -> None:
    # Both head east overall, but one comes out of the door and the other turns into it:
    # they would meet in the door.
    zones = find_zones("m", _corridor_with_a_door())
    zone = zones.zone_at(5.0, 4.5)
    assert zone != 0
    out_of = Path(np.array([[5.0, 2.0], [5.0, 4.5], [9.5, 4.5]]))
    into = Path(np.array([[0.5, 4.5], [5.0, 4.5], [5.0, 2.0]]))
    along = Path(np.array([[0.5, 4.5], [9.5, 4.5]]))
    assert zones.flow(out_of, 5.0, 2.0, zone) == "NE"
    assert zones.flow(into, 0.5, 4.5, zone) == "ES"
    assert zones.flow(along, 0.5, 4.5, zone) == "EE"


def _corridor_with_two_doors() -> Map:
    """The corridor 1 m wide (y 4..5) of :func:`_corridor_with_a_door`, with two doors into the
    room below: at x 1.5..2.5 and at x 7.5..8.5."""
    grid = _corridor_with_a_door()
    occ = grid.occupied().copy()
    occ[int(3.9 / RES):int(4.0 / RES), int(4.5 / RES):int(5.5 / RES)] = True
    for x in (2.0, 8.0):
        occ[int(3.9 / RES):int(4.0 / RES), int((x - 0.5) / RES):int((x + 0.5) / RES)] = False
    return Map.from_occupied(occ, resolution=RES)


def test_the_flow_names_every_turn_of_the_way_through() -> None:
    # Up the west door and east along the corridor to its end, against up the east door and
    # west to the corridor's end: equal ends (north in, ...), yet opposite along the corridor.
    zones = find_zones("m", _corridor_with_two_doors(), ZoneConfig(segment_length=20.0))
    zone = zones.zone_at(5.0, 4.5)
    assert zone != 0 and zones.zone_at(2.0, 3.95) == zone == zones.zone_at(8.0, 3.95)
    east = Path(np.array([[2.0, 2.0], [2.0, 4.5], [9.9, 4.5]]))
    west = Path(np.array([[8.0, 2.0], [8.0, 4.5], [0.1, 4.5]]))
    assert zones.flow(east, 2.0, 2.0, zone) == "NE"
    assert zones.flow(west, 8.0, 2.0, zone) == "NW"
    # Up one door, along and down the other: the middle leg is named.
    across = Path(np.array([[2.0, 2.0], [2.0, 4.5], [8.0, 4.5], [8.0, 2.0]]))
    assert zones.flow(across, 2.0, 2.0, zone) == "NES"


def _long_corridor() -> Map:
    """A corridor 1 m wide (y 4..5) along x 0..24 above one long room (y 0.1..3.9), joined by
    1 m doors centred on x 2, 6, 18 and 22."""
    w, h = int(24.0 / RES), int(5.2 / RES)
    occ = np.ones((h, w), dtype=bool)
    occ[int(4.0 / RES):int(5.0 / RES), :] = False
    occ[int(0.1 / RES):int(3.9 / RES), int(0.1 / RES):int(23.9 / RES)] = False
    for x in (2.0, 6.0, 18.0, 22.0):
        occ[int(3.9 / RES):int(4.0 / RES), int((x - 0.5) / RES):int((x + 0.5) / RES)] = False
    return Map.from_occupied(occ, resolution=RES)


def test_a_long_passage_is_cut_into_segments_of_one_group() -> None:
    zones = find_zones("m", _long_corridor())
    along = [zones.zone_at(x, 4.5) for x in np.arange(0.3, 23.8, 0.1)]
    segments = sorted(set(along))
    assert 0 not in segments and len(segments) >= 3
    assert len({zones.group(n) for n in segments}) == 1  # one passage
    for n in segments:  # each at most segment_length long, in one piece along the corridor
        xs = [x for x, z in zip(np.arange(0.3, 23.8, 0.1), along, strict=True) if z == n]
        assert max(xs) - min(xs) <= 8.0
        assert len(xs) == round((max(xs) - min(xs)) / 0.1) + 1
    # Cut at the narrowest cross-sections: no door is split between two segments.
    for x in (2.0, 6.0, 18.0, 22.0):
        assert len({zones.zone_at(x + dx, y) for dx in (-0.3, 0.0, 0.3)
                    for y in (3.6, 3.95, 4.5)}) == 1
    # The whole corridor is one zone when segments may be as long as it.
    assert find_zones("m", _long_corridor(), ZoneConfig(segment_length=30.0)).count == 1


def test_a_run_lists_the_segments_of_a_passage_in_path_order() -> None:
    zones = find_zones("m", _long_corridor())
    east = Path(np.array([[2.0, 2.0], [2.0, 4.5], [22.0, 4.5], [22.0, 2.0]]))
    runs = zones.runs(east, 2.0, 2.0, reach=5.0)
    assert len(runs) == 1
    run = runs[0]
    assert run.segments[0] == zones.zone_at(2.0, 3.5)
    assert run.segments[-1] == zones.zone_at(22.0, 3.5)
    assert set(run.segments) == {zones.zone_at(x, 4.5) for x in np.arange(2.0, 22.0, 0.1)}
    assert run.entries == tuple(sorted(run.entries)) and run.entries[0] == run.entry
    assert 0.5 < run.entry < 1.5  # the door's zone reaches 0.7 m into the room
    assert zones.runs(east, 2.0, 2.0, reach=0.4) == []
    # From inside: the run starts where the robot stands.
    inside = zones.runs(east, 10.0, 4.5, reach=5.0)[0]
    assert inside.entry == 0.0 and inside.segments[0] == zones.zone_at(10.0, 4.5)
    # Out into the room and back in through the next door 4 m on: two runs.
    dip = Path(np.array([[2.0, 2.0], [2.0, 4.5], [2.0, 2.0], [6.0, 2.0], [6.0, 4.5]]))
    assert len(zones.runs(dip, 2.0, 2.0, reach=30.0)) == 2
    assert len(zones.runs(dip, 2.0, 2.0, reach=0.5)) == 0


def test_bad_segment_length_names_the_key() -> None:
    with pytest.raises(ConfigError) as err:
        ZoneConfig(segment_length=2.0)
    assert err.value.key == "fleet.zones.segment_length"


def test_the_zones_near_a_point_are_those_a_body_there_is_in() -> None:
    zones = find_zones("m", _long_corridor())
    left, right = zones.zone_at(11.5, 4.5), zones.zone_at(12.5, 4.5)
    boundary = min(x for x in np.arange(11.5, 12.5, 0.05) if zones.zone_at(x, 4.5) == right)
    assert zones.zones_near(boundary + 0.2, 4.5, 0.4) == {left, right}
    assert zones.zones_near(boundary + 0.6, 4.5, 0.4) == {right}
    assert zones.zones_near(12.0, 2.0, 0.3) == set()  # in the room, far from every door
    assert zones.zones_near(-5.0, -5.0, 0.5) == set()  # off the map
