"""A robot standing still costs little: its costmap takes a few scans a second, not every one."""

from __future__ import annotations

from polynav.runtime.sim_driver import simulate
from polynav.worlds.world import World


def _count_scans(driver) -> list[float]:  # type: ignore[no-untyped-def]
    stamps: list[float] = []
    update = driver.stack.costmap.update_scan

    def counting(pose, scan):  # type: ignore[no-untyped-def]
        stamps.append(scan.stamp)
        return update(pose, scan)

    driver.stack.costmap.update_scan = counting
    return stamps


def test_a_standing_robot_maps_a_few_scans_a_second_and_a_moving_one_every_scan(
    world: World,
) -> None:
    driver = simulate(world, seed=3, people=True)
    driver.run(1.0)
    stamps = _count_scans(driver)
    driver.run(4.0)  # standing: the lidar scans 15 times a second
    assert 12 <= len(stamps) <= 21  # one every 0.2 s or more: 4 or 5 a second
    floor = world.floor(world.start_floor)
    goal = max(floor.points, key=lambda p: p.pose.distance_to(world.start_pose)).pose
    stamps.clear()
    driver.stack.go_to(goal, driver.now)
    driver.run(4.0)
    assert len(stamps) >= 55  # driving: every scan
