"""The out-of-the-box demo: the simulated robot tours the named points of a floor, for ever.

Simulated time is paced against the wall clock at ``speed`` times real time, so a person watching
the log sees a robot that moves like a robot. Stopping is cooperative through ``stop``.
"""

from __future__ import annotations

import itertools
import logging
import threading
import time
from collections.abc import Callable

from polynav.nav import events
from polynav.runtime.sim_driver import simulate
from polynav.worlds.world import World

log = logging.getLogger(__name__)


def run_demo_tour(
    world: World,
    *,
    speed: float = 1.0,
    seed: int = 0,
    people: bool = True,
    stop: threading.Event | None = None,
    report: Callable[[str], None] = log.info,
) -> int:
    """Tour the start floor's points until ``stop`` is set; returns the number of goals reached."""
    stop = stop or threading.Event()
    floor = world.floor(world.start_floor)

    def on_event(event: events.NavigationEvent) -> None:
        a = event.attempt
        if isinstance(event, events.NavigationSucceeded):
            report(f"t={event.stamp:7.1f}s reached goal {a.attempt_id} after "
                   f"{a.distance_travelled:.1f} m")
        elif isinstance(event, events.NavigationFailed):
            report(f"t={event.stamp:7.1f}s goal {a.attempt_id} failed: "
                   f"{a.reason.value if a.reason else ''} {a.message}")
        elif isinstance(event, (events.NavigationRetry, events.NavigationHeld)):
            report(f"t={event.stamp:7.1f}s {type(event).__name__}: {event}")

    driver = simulate(world, seed=seed, people=people, on_event=on_event)
    reached = 0
    wall_start, sim_start = time.monotonic(), driver.now
    for point in itertools.cycle(floor.points):
        if stop.is_set():
            break
        report(f"t={driver.now:7.1f}s heading to {point.name} "
               f"({point.pose.x:.2f}, {point.pose.y:.2f})")
        driver.stack.go_to(point.pose, driver.now)
        while not driver.stack.navigator.state.finished and not stop.is_set():
            driver.step()
            ahead = (driver.now - sim_start) / speed - (time.monotonic() - wall_start)
            if ahead > 0.0:
                stop.wait(ahead)
        reached += driver.stack.navigator.state.value == "succeeded"
    return reached
