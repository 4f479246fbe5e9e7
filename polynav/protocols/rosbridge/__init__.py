"""rosbridge v2: polynav as ROS clients reach a robot through rosbridge_server (JSON over a
WebSocket, port 9090). The server (:mod:`.server`) serves a ROS graph; the androidmsg
interface (:mod:`.androidmsg`) and the robot's sensor streams (:mod:`.robot_topics`) fill it
from the runtime."""

from polynav.protocols.rosbridge.config import DEFAULT_PORT, RosbridgeConfig
from polynav.protocols.rosbridge.server import RosbridgeServer, RosbridgeThread, serve_rosbridge

__all__ = ["DEFAULT_PORT", "RosbridgeConfig", "RosbridgeServer", "RosbridgeThread",
           "serve_rosbridge"]
