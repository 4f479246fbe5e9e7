"""The host's entries of the androidmsg interface (ros1-nav-iface §3.5-3.7): ``/set_wifi``,
``/navi_info`` and ``/robot_ssh``.

``/robot_ssh`` runs shell commands on the vendor's host (A21); polynav runs none. It takes a
fixed allow-list that maps onto the runtime's own services (``reboot``: the power cycle's
reboot) and refuses everything else, so the entry can never become a remote shell.
"""

from __future__ import annotations

import json

from polynav import __version__
from polynav.errors import PolynavError
from polynav.protocols.ros_graph import Graph, Message, RosError, Service
from polynav.protocols.rosbridge.androidmsg import ids
from polynav.runtime.robot_runtime import RobotRuntime

#: ``/robot_ssh`` instructions polynav carries out, and what each answers.
ALLOWED = ("reboot",)


class System:
    """The host entries over one runtime."""

    def __init__(self, runtime: RobotRuntime, robot_id: str) -> None:
        self._runtime = runtime
        self._robot_id = robot_id

    def declare(self, graph: Graph) -> None:
        graph.add_service(Service("/set_wifi", "map_msgs/SetWifi", self.set_wifi))
        graph.add_service(Service("/navi_info", "map_msgs/AboutRobot", self.navi_info))
        graph.add_service(Service("/robot_ssh", "map_msgs/RobotSsh", self.robot_ssh))

    def set_wifi(self, args: Message) -> Message:
        ssid = ids.text(args, "wifi_name")
        password = args.get("wifi_pass", "")
        if not isinstance(password, str):
            raise RosError("'wifi_pass' must be a string")
        try:
            self._runtime.device.join_network(ssid, password or None)
        except PolynavError as exc:
            raise RosError(f"/set_wifi: {exc}") from None
        return {}

    def navi_info(self, args: Message) -> Message:
        info = {"coco_num": "", "navi_channel": "polynav", "numero": self._robot_id,
                "version_code": __version__, "version_name": f"polynav {__version__}"}
        return {"status": 0, "nav_info": json.dumps(info)}

    def robot_ssh(self, args: Message) -> Message:
        instruction = ids.text(args, "instruction")
        if instruction not in ALLOWED:
            raise RosError(f"/robot_ssh: {instruction!r} is not allowed (polynav runs no shell; "
                           f"allowed: {', '.join(ALLOWED)})")
        try:
            self._runtime.device.power.shutdown(reboot=True)
        except PolynavError as exc:
            raise RosError(f"/robot_ssh: {exc}") from None
        return {"status": 0, "data": "rebooting"}
