"""The Galileo serial protocol over a real pseudo-terminal (galileo-wire-protocols §1): a host
program opens the pty with pyserial at 115200 8N1, writes command frames (with garbage between
them and frames split across writes) and reads the 30 Hz status frames, whose every field is
the runtime's state. Each command of §1.4 is sent as bytes and its effect, or its being ignored
in the wrong state, is checked on the robot.

Simulated time is advanced by the test (the runtime's loop thread is not started); the link
writes a status frame per 1/30 s of it.
"""

from __future__ import annotations

import math
import struct
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import pytest
import serial

from polynav.protocols.galileo import session as sessions
from polynav.protocols.galileo.native import commands as c
from polynav.protocols.galileo.native.serial_link import SerialLink
from polynav.protocols.galileo.native.status_frame import STATUS_FRAME_SIZE, unpack_status
from polynav.protocols.galileo.status import galileo_status
from polynav.runtime.robot_runtime import RobotRuntime
from tests.protocols.galileo.conftest import Harness, serving

COVERED = {
    "galileo-serial topic status": "test_status_frames_at_30_hz_carry_the_runtime_state",
    "galileo-serial cmd m 0": "test_garbage_and_split_frames_start_navigation_and_reach_a_goal",
    "galileo-serial cmd g <n>": "test_garbage_and_split_frames_start_navigation_and_reach_a_goal",
    "galileo-serial cmd m 4": "test_stop_and_reload_navigation",
    "galileo-serial cmd m 9": "test_stop_and_reload_navigation",
    "galileo-serial cmd i 0": "test_pause_resume_cancel_follow_the_goal_state_machine",
    "galileo-serial cmd i 1": "test_pause_resume_cancel_follow_the_goal_state_machine",
    "galileo-serial cmd i 2": "test_pause_resume_cancel_follow_the_goal_state_machine",
    "galileo-serial cmd g i <x> <y>": "test_inserted_goals_are_numbered_after_the_path_and_reset",
    "galileo-serial cmd g r 0": "test_inserted_goals_are_numbered_after_the_path_and_reset",
    "galileo-serial cmd f <v>": "test_teleop_letters_drive_and_stop",
    "galileo-serial cmd b <v>": "test_teleop_letters_drive_and_stop",
    "galileo-serial cmd c <v>": "test_teleop_letters_drive_and_stop",
    "galileo-serial cmd d <v>": "test_teleop_letters_drive_and_stop",
    "galileo-serial cmd s <v>": "test_teleop_letters_drive_and_stop",
    "galileo-serial cmd 0xaa 0x44": "test_shutdown_powers_the_robot_off",
    "galileo-serial cmd a <sign> <angle>": "test_angle_command_turns_to_a_heading",
    "galileo-serial cmd m 5": "test_loop_with_its_dwell_time",
    "galileo-serial cmd m 6": "test_loop_with_its_dwell_time",
    "galileo-serial cmd m 5 <t>": "test_loop_with_its_dwell_time",
    "galileo-serial cmd m 7": "test_dispatch_mode_on_reload_and_off",
    "galileo-serial cmd m 8": "test_dispatch_mode_on_reload_and_off",
    "galileo-serial cmd m 10": "test_dispatch_mode_on_reload_and_off",
    "galileo-serial cmd V 0": "test_mapping_start_save_stop_and_update",
    "galileo-serial cmd V 1": "test_mapping_start_save_stop_and_update",
    "galileo-serial cmd V 2": "test_mapping_start_save_stop_and_update",
    "galileo-serial cmd V 3": "test_mapping_start_save_stop_and_update",
    "galileo-serial cmd j 0": "test_charge_start_stop_and_dock_position",
    "galileo-serial cmd j 1": "test_charge_start_stop_and_dock_position",
    "galileo-serial cmd j 2": "test_charge_start_stop_and_dock_position",
    "galileo-serial cmd H 0": "test_greeting_mode_on_and_off",
    "galileo-serial cmd H 1": "test_greeting_mode_on_and_off",
}


@dataclass
class Line:
    """The host's end: the pty opened with pyserial, the link, the Galileo servers."""

    port: serial.Serial
    link: SerialLink
    g: Harness

    @property
    def runtime(self) -> RobotRuntime:
        return self.g.runtime

    def send(self, payload: bytes, *, split: bool = False, garbage: bytes = b"") -> None:
        """One command frame, after ``garbage``; ``split``: in two writes."""
        data = garbage + c.frame(payload)
        before = self.link.commands  # read first: the link may run the frame before we look
        if split:
            self.port.write(data[:5])
            self.port.flush()
            time.sleep(0.02)
            data = data[5:]
        self.port.write(data)
        self.port.flush()
        self._settle(before)

    def _settle(self, before: int) -> None:
        """Wait (wall time) until the link has run a command since it had run ``before``."""
        deadline = time.monotonic() + 5.0
        while self.link.commands == before and time.monotonic() < deadline:
            time.sleep(0.005)

    def frames(self) -> list[dict[str, float]]:
        """The status frames the host has received since the last call (waits a moment of
        wall time for the writer)."""
        time.sleep(0.05)
        data = b""
        while self.port.in_waiting:
            data += self.port.read(self.port.in_waiting)
            time.sleep(0.02)
        out = []
        start = data.find(c.HEADER)
        while start >= 0 and start + STATUS_FRAME_SIZE <= len(data):
            out.append(unpack_status(data[start:start + STATUS_FRAME_SIZE]))
            start = data.find(c.HEADER, start + STATUS_FRAME_SIZE)
        return out

    def status(self) -> dict[str, float]:
        """The newest status frame after a little more simulated time."""
        self.runtime.advance(0.1)
        frames = self.frames()
        assert frames, "no status frame came"
        return frames[-1]

    def until(self, done: Callable[[dict[str, float]], bool], timeout: float) -> bool:
        """Advance simulated time until the newest status frame satisfies ``done``."""
        deadline = self.runtime.now() + timeout
        while self.runtime.now() < deadline:
            self.runtime.advance(0.5)
            frames = self.frames()
            if frames and done(frames[-1]):
                return True
        return False


@pytest.fixture
def line(runtime: RobotRuntime) -> Iterator[Line]:
    with serving(runtime) as g:
        link = SerialLink(g.server.ctx).start()
        try:
            port = serial.Serial(link.path, 115200, bytesize=8, parity="N", stopbits=1,
                                 timeout=0.2)
            port.reset_input_buffer()
            yield Line(port, link, g)
            port.close()
        finally:
            link.stop()


def _navigate(line: Line) -> None:
    line.send(c.start_navigation())
    assert line.until(lambda s: s["navStatus"] == 1 and s["visualStatus"] == 1, 20.0)


def _target(line: Line, index: int) -> tuple[float, float]:
    ctx = line.g.server.ctx
    map_name = sessions.current_map(ctx)
    point = sessions.target_point(ctx, map_name, sessions.current_path(ctx, map_name), index)
    return point.pose.x, point.pose.y


def _at(line: Line, xy: tuple[float, float], tolerance: float = 0.15) -> bool:
    pose = line.runtime.simulation.true_pose
    return math.hypot(pose.x - xy[0], pose.y - xy[1]) < tolerance


def test_status_frames_at_30_hz_carry_the_runtime_state(line: Line) -> None:
    _navigate(line)
    line.frames()  # drop what came before
    line.runtime.advance(1.0)
    frames = line.frames()
    assert 29 <= len(frames) <= 31  # 30 Hz of simulated time
    stamps = [int(f["time_stamp"]) for f in frames]
    assert stamps == list(range(stamps[0], stamps[0] + len(stamps)))  # +1 per frame (A5)
    last = frames[-1]
    expected = galileo_status(line.g.server.ctx)
    for key in ("navStatus", "visualStatus", "mapStatus", "gcStatus", "gbaStatus",
                "chargeStatus", "loopStatus", "targetNumID", "targetStatus",
                "angleGoalStatus", "busyStatus"):
        assert last[key] == expected[key], key
    for key in ("power", "targetDistance", "currentPosX", "currentPosY", "currentAngle",
                "currentSpeedX", "controlSpeedX"):
        assert last[key] == pytest.approx(expected[key], abs=1e-3), key
    assert (last["navStatus"], last["visualStatus"], last["targetNumID"]) == (1, 1, -1)
    assert last["power"] > 10.0


def test_garbage_and_split_frames_start_navigation_and_reach_a_goal(line: Line) -> None:
    line.send(c.go_to_goal(1))  # before navigation: ignored (the visual system is off)
    assert line.status()["targetStatus"] == -1
    line.send(c.start_navigation(), split=True, garbage=b"\x00\xffnoise\xcd\xeb")
    assert line.until(lambda s: s["navStatus"] == 1 and s["visualStatus"] == 1, 20.0)
    line.send(c.go_to_goal(1), garbage=b"\xcd\xeb\xd7\x30")  # a bad length byte first
    status = line.status()
    assert (status["targetNumID"], status["targetStatus"]) == (1, 1)
    assert status["targetDistance"] > 0.0
    assert line.until(lambda s: s["targetStatus"] == 0, 120.0)
    assert _at(line, _target(line, 1))
    final = line.status()
    assert final["targetNumID"] == 1 and final["targetDistance"] == pytest.approx(0.0)


def test_pause_resume_cancel_follow_the_goal_state_machine(line: Line) -> None:
    _navigate(line)
    line.send(c.pause())  # no goal: ignored
    assert line.status()["targetStatus"] == -1
    line.send(c.go_to_goal(99))  # no such goal: error, the robot stays
    status = line.status()
    assert (status["targetNumID"], status["targetStatus"]) == (99, 3)
    line.send(c.cancel())  # error -> free
    assert line.status()["targetStatus"] in (-1, 0)
    line.send(c.go_to_goal(2))
    assert line.status()["targetStatus"] == 1
    line.runtime.advance(1.0)
    line.send(c.resume())  # working: resume is ignored
    assert line.status()["targetStatus"] == 1
    line.send(c.pause())
    assert line.until(lambda s: s["targetStatus"] == 2, 2.0)
    still = line.runtime.simulation.true_pose
    line.runtime.advance(2.0)
    moved = line.runtime.simulation.true_pose
    assert math.hypot(moved.x - still.x, moved.y - still.y) < 0.05
    line.send(c.resume())
    assert line.until(lambda s: s["targetStatus"] == 1, 2.0)
    line.send(c.go_to_goal(1))  # working: the goal is replaced
    status = line.status()
    assert (status["targetNumID"], status["targetStatus"]) == (1, 1)
    line.send(c.cancel())
    assert line.until(lambda s: s["targetStatus"] == 0, 2.0)


def test_inserted_goals_are_numbered_after_the_path_and_reset(line: Line) -> None:
    _navigate(line)
    ctx = line.g.server.ctx
    from polynav.protocols.galileo.native.control import native_control

    control = native_control(ctx)
    count = control.goal_count()
    here = line.runtime.simulation.true_pose
    goal = (here.x + 1.5, here.y)
    line.send(c.insert_goal(*goal))
    assert control.goal_count() == count + 1
    line.send(c.go_to_goal(count))
    assert line.status()["targetNumID"] == count
    assert line.until(lambda s: s["targetStatus"] == 0, 60.0)
    assert _at(line, goal)
    line.send(c.reset_goals())
    assert control.goal_count() == count
    line.send(c.go_to_goal(count))  # gone: error
    assert line.status()["targetStatus"] == 3


def test_teleop_letters_drive_and_stop(line: Line) -> None:
    runtime = line.runtime
    for letter, check in (("f", lambda a, b: b.x - a.x > 0.05),
                          ("b", lambda a, b: b.x - a.x < -0.05),
                          ("c", lambda a, b: math.remainder(b.theta - a.theta, math.tau) > 0.1),
                          ("d", lambda a, b: math.remainder(b.theta - a.theta, math.tau) < -0.1)):
        start = runtime.simulation.true_pose
        for _ in range(5):  # at a 5 Hz control rate, as a host drives
            line.send(c.teleop(letter, 50))
            runtime.advance(0.2)
        assert check(start, runtime.simulation.true_pose), letter
        line.send(c.teleop("s", 100))
        runtime.advance(1.0)
    assert line.status()["currentSpeedX"] == pytest.approx(0.0, abs=0.02)
    assert line.status()["targetStatus"] == -1  # teleop leaves the goal state alone


def test_angle_command_turns_to_a_heading(line: Line) -> None:
    _navigate(line)
    line.send(c.set_angle(1, 90))  # -90 degrees in the map frame
    assert line.status()["angleGoalStatus"] == 0
    assert line.until(lambda s: s["angleGoalStatus"] == 1, 30.0)
    heading = line.runtime.simulation.true_pose.theta
    assert abs(math.remainder(heading + math.pi / 2, math.tau)) < 0.1
    # the angle's mark fades once a newer goal starts: that goal's own state shows
    line.send(c.go_to_goal(0))
    assert line.until(lambda s: s["targetStatus"] == 1 and s["angleGoalStatus"] == 0, 10.0)


def test_loop_with_its_dwell_time(line: Line) -> None:
    line.send(c.start_loop())  # not navigating: ignored
    assert line.status()["loopStatus"] == 0
    _navigate(line)
    line.send(c.set_loop_wait(1))
    line.send(c.start_loop())
    assert line.status()["loopStatus"] == 1
    assert line.until(lambda s: s["targetStatus"] == 1, 5.0)
    first = line.status()["targetNumID"]
    assert line.until(lambda s: s["targetNumID"] != first and s["targetStatus"] == 1, 200.0)
    line.send(c.stop_loop())
    assert line.until(lambda s: s["loopStatus"] == 0, 2.0)


def test_stop_and_reload_navigation(line: Line) -> None:
    line.send(c.reload_navigation())  # not navigating: ignored
    assert line.status()["navStatus"] == 0
    _navigate(line)
    line.send(c.reload_navigation())
    assert line.until(lambda s: s["navStatus"] == 1 and s["visualStatus"] == 1, 20.0)
    line.send(c.stop_navigation())
    assert line.until(lambda s: s["navStatus"] == 0 and s["visualStatus"] == -1, 5.0)


def test_dispatch_mode_on_reload_and_off(line: Line) -> None:
    ctx = line.g.server.ctx
    line.send(c.reload_dispatch())  # not in dispatch mode: ignored
    assert not sessions.session(ctx).dispatch
    line.send(c.enable_dispatch())
    assert sessions.session(ctx).dispatch
    assert line.until(lambda s: s["navStatus"] == 1, 20.0)
    line.send(c.go_to_goal(1))  # dispatch mode: Galileo goals are refused
    assert line.status()["targetStatus"] == -1
    line.send(c.reload_dispatch())
    assert line.until(lambda s: s["navStatus"] == 1 and s["visualStatus"] == 1, 20.0)
    line.send(c.disable_dispatch())
    assert not sessions.session(ctx).dispatch
    assert line.until(lambda s: s["navStatus"] == 0, 5.0)


def test_mapping_start_save_stop_and_update(line: Line) -> None:
    store = line.g.server.ctx.store
    line.send(c.stop_mapping())  # not mapping: ignored
    line.send(c.start_mapping())
    assert line.until(lambda s: s["mapStatus"] == 1, 5.0)
    line.send(c.start_navigation())  # mapping: ignored
    assert line.status()["navStatus"] == 0
    for _ in range(10):
        line.send(c.teleop("c", 40))
        line.runtime.advance(0.3)
    line.send(c.save_map())
    assert "slamdb" in [record.name for record in store.maps()]
    assert line.status()["mapStatus"] == 1  # saving goes on mapping
    line.send(c.stop_mapping())
    assert line.until(lambda s: s["mapStatus"] == 0, 10.0)
    line.send(c.update_map())
    assert line.until(lambda s: s["mapStatus"] == 1, 20.0)
    line.send(c.stop_mapping())
    assert line.until(lambda s: s["mapStatus"] == 0, 10.0)


def test_charge_start_stop_and_dock_position(line: Line) -> None:
    _navigate(line)
    ctx = line.g.server.ctx
    line.send(c.start_charge())
    assert line.until(lambda s: s["chargeStatus"] in (3, 4), 5.0)  # finding / docking
    line.send(c.stop_charge())
    assert line.until(lambda s: s["chargeStatus"] == 0 and s["targetStatus"] != 1, 5.0)
    line.send(c.start_charge())
    assert line.until(lambda s: s["chargeStatus"] in (1, 2), 180.0)
    line.send(c.start_charge())  # charging already: ignored
    here = line.runtime.status().pose
    line.send(c.save_charge_dock())  # on the dock: its pose is stored
    pile = sessions.charge_pile(ctx, sessions.current_map(ctx)).pose
    assert math.hypot(pile.x - here.x, pile.y - here.y) < 0.01
    line.send(c.stop_charge())
    assert line.status()["chargeStatus"] in (1, 2)  # no charge task runs: stays on the dock


def test_greeting_mode_on_and_off(line: Line) -> None:
    peripherals = line.runtime.peripherals
    line.send(c.enable_greeting())
    assert peripherals.greeting
    line.send(c.disable_greeting())
    assert not peripherals.greeting


def test_shutdown_powers_the_robot_off(line: Line) -> None:
    line.send(c.shutdown())
    assert line.runtime.device.power.shutting_down
    line.runtime.advance(11.0)  # the notice's lead, then the cut
    assert not line.runtime.powered


def test_a_status_frame_decodes_by_offset_as_the_spec_tables_say(line: Line) -> None:
    _navigate(line)
    line.runtime.advance(0.2)
    time.sleep(0.05)
    raw = line.port.read(line.port.in_waiting)
    start = raw.find(c.HEADER)
    frame = raw[start:start + STATUS_FRAME_SIZE]
    assert frame[3] == 0x55 and frame[-1] == 0
    assert struct.unpack_from("<i", frame, 4)[0] == 1  # nav_status at frame offset 4
    assert struct.unpack_from("<f", frame, 72)[0] == pytest.approx(
        line.runtime.status().pose.x, abs=0.05)  # current_pose_x at 72


def test_malformed_input_is_ignored_and_counted(line: Line) -> None:
    from polynav.protocols.galileo.diagnostics import diagnostics

    counters = diagnostics(line.g.server.ctx)
    line.port.write(b"\x01\x02\x03garbage")  # no header at all
    line.port.write(b"\xcd\xeb\xd7\x40" + bytes(10))  # LEN 64 > 20: dropped
    # a short frame takes the next byte as its rest ('m' + 0xCD: no command), and the frame it
    # cut lost its header: garbage, as on the reference receiver
    line.send(c.pause(), garbage=b"\xcd\xeb\xd7\x02m")
    line.send(c.pause())  # no goal: ignored
    line.send(b"\x6d\x01")  # m 1: no such command
    line.send(b"\xff" * 20)  # 20 unknown bytes
    counts = counters.snapshot()
    assert counts["serial.garbage_bytes"] >= 10
    assert counts["serial.bad_length"] >= 1
    assert counts["native.unknown"] >= 2
    assert counts["native.ignored"] >= 1
    _navigate(line)  # the line still works
    assert counts.get("native.run", 0) < counters.snapshot()["native.run"]
