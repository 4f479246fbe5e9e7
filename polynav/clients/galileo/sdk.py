"""``GalileoSDK``: the SDK's calls (galileo-wire-protocols §6.5), each sending what §6.6 says.

Out-parameters of the C++ SDK come back as a second value (``code, goal = MoveTo(x, y)``);
callbacks are plain callables. The preconditions of §6.6 answer ``INVALIDE_STATE`` from the
newest status; a call without a connected robot answers ``NOT_CONNECTED``. Like the SDK, the
command calls only send: the effect shows in the status (``WaitForGoal``, the callbacks).

Decisions (``docs/decisions.md``, "Galileo SDK client"): the WebSocket carries status and
commands, so there is no ROS master; ``GetGoalNum`` is the path in use's target count (HTTP
``nav_points``) plus the goals this client inserted since its last reset (the SDK's ``MoveTo``
resets before inserting, so its goal number is exact); ``MoveTo(x, y, theta)`` (v2) is the HTTP
pose goal; the cross-LAN IoT ``Connect`` answers ``NETWORK_ERROR`` (polynav has no IoT relay).
"""

from __future__ import annotations

import logging
import math
import threading
import time
import uuid
from collections.abc import Callable
from typing import Any

import httpx

from polynav.clients.galileo.codes import GALILEO_RETURN_CODE as CODE
from polynav.clients.galileo.codes import HttpBridgeResponse, ServerInfo
from polynav.clients.galileo.discovery import DISCOVERY_PORT, BroadcastReceiver
from polynav.clients.galileo.link import LinkError, RobotLink, Status, wait_until
from polynav.protocols.galileo.native import commands as cmd

log = logging.getLogger(__name__)

ConnectCallback = Callable[[CODE, str], None]
StatusCallback = Callable[[CODE, Status], None]
GoalCallback = Callable[[int, Status], None]

#: The pause the SDK leaves between the commands of one call (``MoveTo``, ``StopCharge``).
COMMAND_GAP = 0.4  # [s]
WS_PORT = 3547


class GalileoSDK:
    """One SDK object (the SDK allows one per program; nothing here needs that).

    Args:
        discovery_port: where announcements are heard (22002).
        ws_port: the robots' WebSocket port (3547).
        username, password: the HTTP API's login.
        command_gap: the pause between the commands of one call [s].
    """

    def __init__(self, *, discovery_port: int = DISCOVERY_PORT, ws_port: int = WS_PORT,
                 username: str = "admin", password: str = "admin",
                 command_gap: float = COMMAND_GAP) -> None:
        self._receiver = BroadcastReceiver(discovery_port)
        self._ws_port = ws_port
        self._login = (username, password)
        self._gap = command_gap
        self._lock = threading.Lock()
        self._link: RobotLink | None = None
        self._status: Status | None = None
        self._status_event = threading.Condition()
        self._on_disconnect: ConnectCallback | None = None
        self._status_callback: StatusCallback | None = None
        self._goal_callback: GoalCallback | None = None
        self._inserted = 0

    # -- discovery and connection ----------------------------------------------------------------

    @property
    def discovery_port(self) -> int:
        """Where announcements are heard (the port chosen when given 0)."""
        return self._receiver.port

    def GetServersOnline(self) -> list[ServerInfo]:
        return self._receiver.servers()

    def GetCurrentServer(self) -> ServerInfo | None:
        link = self._link
        return None if link is None else link.server

    def CheckServerOnline(self, targetid: str) -> bool:
        return any(s.ID == targetid for s in self._receiver.servers())

    def Connect(self, targetID: str = "", auto_connect: Any = True,
                timeout: Any = 10000, OnConnect: Any = None,
                OnDisconnect: Any = None) -> CODE:
        """Connect to ``targetID`` (or, with ``auto_connect``, the only robot in the LAN) within
        ``timeout`` ms; with ``OnConnect`` it returns at once and calls back. The SDK's other
        form, ``Connect(targetID, timeout, password, OnConnect, OnDisconnect)`` across LANs
        through the vendor's IoT relay, answers ``NETWORK_ERROR``: there is no relay here."""
        if isinstance(timeout, str):  # Connect(id, timeout_ms, password, ...): the IoT form
            log.warning("galileo sdk: cross-LAN (IoT) connection is not available")
            return CODE.NETWORK_ERROR
        if self._link is not None:
            return CODE.ALREADY_CONNECTED
        self._on_disconnect = OnDisconnect
        if OnConnect is None:
            return self._connect(targetID, bool(auto_connect), float(timeout) / 1000.0)

        def run() -> None:
            code = self._connect(targetID, bool(auto_connect), float(timeout) / 1000.0)
            link = self._link
            OnConnect(code, link.server.ID if link is not None else targetID)

        threading.Thread(target=run, name="galileo-sdk-connect", daemon=True).start()
        return CODE.OK

    def _connect(self, target: str, auto: bool, seconds: float) -> CODE:
        deadline = time.monotonic() + seconds
        server: ServerInfo | None = None
        while server is None:
            servers = self._receiver.servers()
            if target:
                server = next((s for s in servers if s.ID == target), None)
            elif auto and len(servers) > 1:
                return CODE.MULTI_SERVER_FOUND
            elif auto and len(servers) == 1:
                server = servers[0]
            elif not auto:
                return CODE.INVALIDE_PARAMS  # neither a robot named nor one to pick
            left = deadline - time.monotonic()
            if server is None:
                if left <= 0:
                    return CODE.TIMEOUT if servers or target else CODE.NO_SERVER_FOUND
                self._receiver.wait(min(left, 0.5))
        try:
            link = RobotLink(server, self._ws_port, *self._login, on_status=self._status_in,
                             on_lost=self._lost)
        except LinkError as exc:
            log.warning("galileo sdk: %s", exc)
            return CODE.NETWORK_ERROR
        with self._lock:
            self._link = link
        left = max(0.0, deadline - time.monotonic())
        with self._status_event:
            if not self._status_event.wait_for(lambda: self._status is not None, left):
                self._drop_link()
                return CODE.TIMEOUT
        return CODE.OK

    def Dispose(self) -> None:
        """Close the connection and stop listening."""
        self._drop_link()
        self._receiver.close()

    def _drop_link(self) -> None:
        with self._lock:
            link, self._link = self._link, None
        self._status = None
        if link is not None:
            link.close()

    def _lost(self) -> None:
        link = self._link
        if self._on_disconnect is not None and link is not None:
            self._on_disconnect(CODE.NOT_CONNECTED, link.server.ID)

    def _status_in(self, status: Status) -> None:
        before = self._status
        with self._status_event:
            self._status = status
            self._status_event.notify_all()
        if self._status_callback is not None:
            self._status_callback(CODE.OK, status)
        if (self._goal_callback is not None and before is not None
                and before["targetStatus"] != 0 and status["targetStatus"] == 0):
            self._goal_callback(int(status["targetNumID"]), status)

    # -- status ----------------------------------------------------------------------------------

    def GetCurrentStatus(self) -> tuple[CODE, Status | None]:
        status = self._status
        if self._link is None or status is None:
            return CODE.NOT_CONNECTED, None
        return CODE.OK, dict(status)

    def SetCurrentStatusCallback(self, callback: StatusCallback | None) -> None:
        self._status_callback = callback

    def SetGoalReachedCallback(self, callback: GoalCallback | None) -> None:
        self._goal_callback = callback

    def _check(self, **wanted: int) -> CODE:
        """``OK`` when connected and every ``field == value`` (``navStatus=1``); a name ending
        in ``_not`` asks for ``!=``."""
        status = self._status
        if self._link is None or status is None:
            return CODE.NOT_CONNECTED
        for key, value in wanted.items():
            field, negate = (key[:-4], True) if key.endswith("_not") else (key, False)
            if (status[field] == value) == negate:
                return CODE.INVALIDE_STATE
        return CODE.OK

    # -- commands --------------------------------------------------------------------------------

    def _send(self, payload: bytes) -> CODE:
        link = self._link
        if link is None:
            return CODE.NOT_CONNECTED
        try:
            link.send_command(payload)
        except LinkError as exc:
            log.warning("galileo sdk: %s", exc)
            return CODE.NETWORK_ERROR
        return CODE.OK

    def _sequence(self, *payloads: bytes) -> CODE:
        for n, payload in enumerate(payloads):
            if n:
                time.sleep(self._gap)
            code = self._send(payload)
            if code is not CODE.OK:
                return code
        return CODE.OK

    def _when(self, code: CODE, then: Callable[[], CODE]) -> CODE:
        return then() if code is CODE.OK else code

    def SendCMD(self, command: bytes | bytearray | list[int],
                length: int | None = None) -> CODE:
        """Raw command bytes (the serial payload, without the header)."""
        data = bytes(command)
        if length is not None:
            data = data[:length]
        if not 0 < len(data) <= cmd.MAX_COMMAND_LEN:
            return CODE.INVALIDE_PARAMS
        return self._send(data)

    def StartNav(self) -> CODE:
        return self._when(self._check(mapStatus_not=1, navStatus_not=1),
                          lambda: self._send(cmd.start_navigation()))

    def StopNav(self) -> CODE:
        return self._when(self._check(navStatus=1), lambda: self._send(cmd.stop_navigation()))

    def SetGoal(self, goalIndex: int) -> CODE:
        if not 0 <= goalIndex <= 255:
            return CODE.INVALIDE_PARAMS

        def run() -> CODE:
            if self._status is not None and self._status["chargeStatus"] != 0:
                self._send(cmd.stop_charge())
            return self._send(cmd.go_to_goal(goalIndex))

        return self._when(self._check(navStatus=1), run)

    def PauseGoal(self) -> CODE:
        return self._when(self._check(navStatus=1), lambda: self._send(cmd.pause()))

    def ResumeGoal(self) -> CODE:
        return self._when(self._check(navStatus=1), lambda: self._send(cmd.resume()))

    def CancelGoal(self) -> CODE:
        return self._when(self._check(navStatus=1), lambda: self._send(cmd.cancel()))

    def InsertGoal(self, x: float, y: float) -> CODE:
        if not (math.isfinite(x) and math.isfinite(y)):
            return CODE.INVALIDE_PARAMS

        def run() -> CODE:
            code = self._send(cmd.insert_goal(x, y))
            if code is CODE.OK:
                self._inserted += 1
            return code

        return self._when(self._check(navStatus=1), run)

    def ResetGoal(self) -> CODE:
        def run() -> CODE:
            code = self._send(cmd.reset_goals())
            if code is CODE.OK:
                self._inserted = 0
            return code

        return self._when(self._check(navStatus=1), run)

    def SetSpeed(self, vLinear: float, vAngle: float) -> CODE:
        link = self._link
        if link is None or self._status is None:
            return CODE.NOT_CONNECTED
        if not (math.isfinite(vLinear) and math.isfinite(vAngle)):
            return CODE.INVALIDE_PARAMS
        if self._status["chargeStatus"] != 0:
            self._send(cmd.stop_charge())
        try:
            link.send_twist(vLinear, vAngle)
        except LinkError:
            return CODE.NETWORK_ERROR
        return CODE.OK

    def Shutdown(self) -> CODE:
        return self._send(cmd.shutdown())

    def SetAngle(self, sign: int, angle: int) -> CODE:
        if sign not in (0, 1) or not 0 <= angle <= 180:
            return CODE.INVALIDE_PARAMS
        return self._send(cmd.set_angle(sign, angle))

    def StartLoop(self) -> CODE:
        def run() -> CODE:
            self._inserted = 0  # inserted goals are not part of the patrol
            return self._sequence(cmd.reset_goals(), cmd.start_loop())

        return self._when(self._check(navStatus=1), run)

    def StopLoop(self) -> CODE:
        return self._when(self._check(navStatus=1), lambda: self._send(cmd.stop_loop()))

    def SetLoopWaitTime(self, time_s: int) -> CODE:
        if not 0 <= time_s <= 255:
            return CODE.INVALIDE_PARAMS
        return self._when(self._check(navStatus=1),
                          lambda: self._send(cmd.set_loop_wait(time_s)))

    def StartMapping(self) -> CODE:
        return self._when(self._check(mapStatus=0, navStatus=0),
                          lambda: self._send(cmd.start_mapping()))

    def StopMapping(self) -> CODE:
        return self._when(self._check(mapStatus=1), lambda: self._send(cmd.stop_mapping()))

    def SaveMap(self) -> CODE:
        return self._when(self._check(mapStatus=1), lambda: self._send(cmd.save_map()))

    def UpdateMap(self) -> CODE:
        return self._when(self._check(mapStatus=0, navStatus=0),
                          lambda: self._send(cmd.update_map()))

    def StartChargeLocal(self) -> CODE:
        return self._send(cmd.start_charge())

    def StopChargeLocal(self) -> CODE:
        return self._send(cmd.stop_charge())

    def SaveChargeBasePosition(self) -> CODE:
        return self._send(cmd.save_charge_dock())

    def EnableGreeting(self, flag: bool) -> CODE:
        return self._send(cmd.enable_greeting() if flag else cmd.disable_greeting())

    # -- goals, with waiting -----------------------------------------------------------------

    def GetGoalNum(self) -> tuple[CODE, int]:
        """The goals ``g n`` can name: the path in use's target points and the goals this
        client inserted since its last reset."""
        link = self._link
        if link is None:
            return CODE.NOT_CONNECTED, 0
        try:
            points = link.call("/navigation/nav_points")
        except LinkError as exc:
            log.warning("galileo sdk: %s", exc)
            return CODE.SERVER_ERROR, 0
        targets = sum(1 for line in str(points.get("path_data", "")).splitlines() if line.strip())
        return CODE.OK, targets + self._inserted

    def MoveTo(self, x: float, y: float,
               theta: float | None = None) -> tuple[CODE, int]:
        """V1 ``MoveTo(x, y)``: reset, insert a goal at (x, y), go to it; its goal number. V2
        ``MoveTo(x, y, theta)``: a pose goal (goal number -2, no index)."""
        values = (x, y) if theta is None else (x, y, theta)
        if not all(math.isfinite(v) for v in values):
            return CODE.INVALIDE_PARAMS, -1
        code = self._check(navStatus=1)
        if code is not CODE.OK:
            return code, -1
        link = self._link
        assert link is not None
        if theta is not None:
            try:
                link.call("/navigation/start_nav_task", {"x": x, "y": y, "theta": theta})
            except LinkError as exc:
                log.warning("galileo sdk: %s", exc)
                return CODE.SERVER_ERROR, -1
            return CODE.OK, -2
        for step in (self.ResetGoal, lambda: self.InsertGoal(x, y)):
            code = step()
            if code is not CODE.OK:
                return code, -1
            time.sleep(self._gap)
        code, count = self.GetGoalNum()
        if code is not CODE.OK:
            return code, -1
        goal = count - 1
        return self.SetGoal(goal), goal

    def WaitForGoal(self, goalID: int, timeout: float | None = None) -> CODE:
        """Until goal ``goalID`` is reached (``OK``) or replaced or cancelled
        (``GOAL_CANCELLED``): §6.6's rule (the goal must show within 5 s, else
        ``INVALIDE_GOAL``). ``timeout`` [s] bounds the wait (``TIMEOUT``); the SDK has none."""
        code = self._check(navStatus=1)
        if code is not CODE.OK:
            return code
        if not wait_until(lambda: self._field("targetNumID") == goalID, 5.0):
            return CODE.INVALIDE_GOAL
        deadline = None if timeout is None else time.monotonic() + timeout
        was_working = self._field("targetStatus") != 0
        while True:
            status = self._status
            if self._link is None or status is None:
                return CODE.NOT_CONNECTED
            if status["targetNumID"] != goalID:
                return CODE.GOAL_CANCELLED
            if status["targetStatus"] == 0 and (was_working or status["targetDistance"] < 0.3):
                return CODE.OK
            if status["targetStatus"] == 3:
                return CODE.GOAL_CANCELLED
            was_working = was_working or status["targetStatus"] != 0
            if deadline is not None and time.monotonic() > deadline:
                return CODE.TIMEOUT
            with self._status_event:
                self._status_event.wait(0.5)

    def _field(self, name: str) -> Any:
        status = self._status
        return None if status is None else status.get(name)

    def StartCharge(self, x: float | None = None, y: float | None = None,
                    timeout: float | None = None) -> CODE:
        """Blocking: to the dock and onto it. V1 ``StartCharge(x, y)`` drives to the dock's
        position first; V2 ``StartCharge()`` lets the robot find its stored dock."""
        code = self._check(navStatus=1)
        if code is not CODE.OK:
            return code
        if x is not None and y is not None:
            code, goal = self.MoveTo(x, y)
            if code is CODE.OK:
                code = self.WaitForGoal(goal, timeout)
            if code is not CODE.OK:
                return code
        code = self._send(cmd.start_charge())
        if code is not CODE.OK:
            return code
        done = wait_until(lambda: self._field("chargeStatus") in (1, 2, 5),
                          math.inf if timeout is None else timeout, pause=0.1)
        if not done:
            return CODE.TIMEOUT
        return CODE.OK if self._field("chargeStatus") in (1, 2) else CODE.SERVER_ERROR

    def StopCharge(self) -> CODE:
        def run() -> CODE:
            self._inserted = 0
            return self._sequence(cmd.cancel(), cmd.reset_goals(), cmd.stop_charge())

        return self._when(self._check(navStatus=1), run)

    # -- HTTP ------------------------------------------------------------------------------------

    def SendAudio(self, audio: str) -> CODE:
        link = self._link
        if link is None:
            return CODE.NOT_CONNECTED
        try:
            link.call("/system/tts", text=audio)
        except LinkError as exc:
            log.warning("galileo sdk: %s", exc)
            return CODE.SERVER_ERROR
        return CODE.OK

    def SendGalileoBridgeRequest(self, method: str, url: str, body: str = "",
                                 timeout: int = 10000) -> tuple[CODE, HttpBridgeResponse | None]:
        """Any HTTP API call (``url`` like ``/api/v1/system/status``), the token added."""
        link = self._link
        if link is None:
            return CODE.NOT_CONNECTED, None
        if method.upper() not in ("GET", "POST", "PUT", "DELETE", "PATCH") or \
                not url.startswith("/"):
            return CODE.INVALIDE_PARAMS, None
        try:
            reply = link.request(method, url, body, timeout / 1000.0)
        except httpx.TimeoutException:
            return CODE.TIMEOUT, None
        except httpx.HTTPError as exc:
            log.warning("galileo sdk: %s", exc)
            return CODE.NETWORK_ERROR, None
        return CODE.OK, HttpBridgeResponse(str(uuid.uuid4()), reply.status_code, reply.text)

    def PublishTest(self) -> CODE:
        """A test message to the robot (the IoT example's): a ping on the status stream."""
        link = self._link
        if link is None:
            return CODE.NOT_CONNECTED
        try:
            link.ping()
        except LinkError:
            return CODE.NETWORK_ERROR
        return CODE.OK
