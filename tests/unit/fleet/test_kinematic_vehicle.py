"""Light VDA 5050 vehicles follow their orders over a real Mosquitto, on a hand-driven site clock.

Several vehicles share one MQTT connection (the benchmark's light mode); polynav's master
control sends the orders from its own connection. Each wait for the broker has a bound.
"""

from __future__ import annotations

import datetime as dt
import math
import time
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from polynav.fleet import messages as m
from polynav.fleet.kinematic_vehicle import KinematicConfig, KinematicVehicle
from polynav.fleet.master_control import MasterControl, Stop
from polynav.fleet.mqtt_transport import MqttTransport
from polynav.fleet.shared_client import SharedClient
from polynav.geometry import Pose2D
from tests.helpers.mosquitto import Mosquitto

WAIT = 10.0
MAPS = frozenset({"floor1", "floor2"})


class Site:
    """A broker, a master control and two light vehicles on one shared connection."""

    def __init__(self, broker: Mosquitto) -> None:
        self.now = 0.0
        self.master_client = MqttTransport(broker.url, "test/master")
        self.master = MasterControl(self.master_client)
        self.vehicle_client = MqttTransport(broker.url, "test/vehicles")
        self.shared = SharedClient(self.vehicle_client)
        headers = m.Headers(m.DEFAULT_VERSION, m.DEFAULT_MANUFACTURER, lambda: self.now)
        config = KinematicConfig(speed=1.0, lift_wait=10.0, visualization_period=0.5,
                                 lifts={"floor1": ((5.0, 1.0),), "floor2": ((5.0, 1.0),)})
        self.vehicles = {
            serial: KinematicVehicle(serial, self.shared, config,
                                     start=m.AgvPosition(1.0, y, 0.0, "floor1", True, 1.0),
                                     maps=MAPS, headers=headers)
            for serial, y in (("k1", 1.0), ("k2", 3.0))}
        for serial in self.vehicles:
            self.master.add_robot(serial)
        self.visualizations = self.master_client.subscribe_raw(
            m.topic("+", m.Visualization), version=m.DEFAULT_VERSION)
        assert self.master_client.wait_subscribed(WAIT)
        assert self.vehicle_client.wait_subscribed(WAIT)

    def close(self) -> None:
        self.vehicle_client.close()
        self.master_client.close()

    def tick(self) -> None:
        for vehicle in self.vehicles.values():
            vehicle.tick(self.now)
        self.master.tick(self.now)

    def until(self, done: Callable[[], bool]) -> None:
        """Tick (the clock standing still) until ``done()``, waiting for the broker between."""
        deadline = time.monotonic() + WAIT
        while not done():
            assert time.monotonic() < deadline, "the broker did not deliver in time"
            time.sleep(0.01)
            self.tick()

    def run(self, seconds: float, step: float = 0.1) -> None:
        """Advance the site clock ``seconds``, ticking every ``step``."""
        for _ in range(round(seconds / step)):
            self.now = round(self.now + step, 6)
            self.tick()

    def state(self, serial: str) -> m.State:
        state = self.master.state(serial)
        assert state is not None
        return state


@pytest.fixture
def site(tmp_path: Path) -> Iterator[Site]:
    with Mosquitto(tmp_path) as broker:
        running = Site(broker)
        try:
            yield running
        finally:
            running.close()


def test_a_light_vehicle_drives_its_order_through_a_lift(site: Site) -> None:
    site.until(lambda: all(site.master.state(s) is not None for s in site.vehicles))
    order_id = site.master.send_order("k1", [Stop("a", "floor1", Pose2D(4.0, 1.0, 0.0)),
                                             Stop("b", "floor2", Pose2D(5.0, 4.0, 0.0))])
    site.until(lambda: site.state("k1").order_id == order_id)
    taken = site.state("k1")
    assert [n.node_id for n in taken.node_states] == ["a", "b"]
    assert not taken.errors

    site.run(2.0)  # 2 m of 3 to node a
    site.until(lambda: site.state("k1").driving)  # a state on starting to drive
    assert site.vehicles["k1"].position.x == pytest.approx(3.0)
    site.run(2.0)  # a passed, on to the lift at (5, 1): 4 s for 4 m, then in the lift
    site.until(lambda: site.state("k1").last_node_id == "a")
    site.run(6.0)  # in the lift: still on floor 1, standing
    in_lift = site.vehicles["k1"].position
    assert (in_lift.map_id, in_lift.x, in_lift.y) == ("floor1", pytest.approx(5.0),
                                                       pytest.approx(1.0))
    site.run(8.0)  # out on floor 2 after the 10 s wait, then 3 m to b
    site.until(lambda: site.state("k1").last_node_id == "b")
    done = site.state("k1")
    assert done.order_id == order_id and not done.node_states and not done.errors
    assert done.agv_position is not None and done.agv_position.map_id == "floor2"
    assert math.hypot(done.agv_position.x - 5.0, done.agv_position.y - 4.0) < 1e-6
    assert not done.driving
    # k2, on the same connection, never moved; both sent schema-valid visualizations
    k2 = site.state("k2").agv_position
    assert k2 is not None and (k2.x, k2.y) == (1.0, 3.0)
    seen = {message.topic.split("/")[3] for message in site.visualizations.drain()}
    assert seen == {"k1", "k2"}


def test_a_light_vehicle_answers_bad_orders_and_instant_actions(site: Site) -> None:
    site.until(lambda: all(site.master.state(s) is not None for s in site.vehicles))
    # An order that does not start where the vehicle stands: noRouteError, nothing moves.
    far = m.Order(m.Header(1, m.iso_timestamp(dt.datetime.now(dt.UTC)), "2.0.0",
                           "polynav", "k2"), "far-1", 0,
                  (m.Node("x", 0, m.NodePosition(20.0, 20.0, 0.0, "floor1")),
                   m.Node("y", 2, m.NodePosition(21.0, 20.0, 0.0, "floor1"))),
                  (m.Edge("x->y", 1, "x", "y"),))
    site.master_client.publish(m.topic("k2", m.Order), far)
    site.until(lambda: any(e.error_type == "noRouteError" for e in site.state("k2").errors))
    assert site.state("k2").order_id == ""
    # Malformed JSON on the order topic: a validationError in the state, never a crash.
    site.master_client.publish_raw(m.topic("k2", m.Order), b"{not json")
    site.until(lambda: any(e.error_type == "validationError" for e in site.state("k2").errors))

    order_id = site.master.send_order("k1", [Stop("a", "floor1", Pose2D(4.0, 1.0, 0.0))])
    site.until(lambda: site.state("k1").order_id == order_id)
    pause = m.InstantActions(m.Header(7, m.iso_timestamp(dt.datetime.now(dt.UTC)),
                                      "2.0.0", "polynav", "k1"),
                             (m.Action("p1", m.ActionType.START_PAUSE.value),
                              m.Action("c1", m.ActionType.START_CHARGING.value)))
    site.master_client.publish(m.topic("k1", m.InstantActions), pause)
    site.until(lambda: len(site.state("k1").action_states) == 2)
    statuses = {a.action_id: a.action_status for a in site.state("k1").action_states}
    assert statuses == {"p1": m.ActionStatus.FINISHED, "c1": m.ActionStatus.FAILED}
    site.run(2.0)
    assert site.vehicles["k1"].position.x == pytest.approx(1.0)  # paused: no move
    site.master.cancel_order("k1")
    site.until(lambda: any(e.error_type == "orderFailed" for e in site.state("k1").errors))
    assert not site.state("k1").node_states
