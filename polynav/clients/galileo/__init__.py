"""A Python client with the Galileo SDK's calls (galileo-wire-protocols §6).

``GalileoSDK`` finds robots by their UDP announcements, reads GalileoStatus from the Galileo
WebSocket and sends the native command bytes on ``/galileo/cmds``, speeds on ``/cmd_vel``, and
the few calls the bytes do not cover over the HTTP API, so a script written for the C++/Python
SDK ports line by line::

    sdk = GalileoSDK()
    if sdk.Connect("", True, 10000, None, None) == GALILEO_RETURN_CODE.OK:
        sdk.StartNav()
        code, goal = sdk.MoveTo(5.5, 12.5)
        sdk.WaitForGoal(goal)
    sdk.Dispose()
"""

from polynav.clients.galileo.codes import GALILEO_RETURN_CODE, HttpBridgeResponse, ServerInfo
from polynav.clients.galileo.sdk import GalileoSDK

__all__ = ["GALILEO_RETURN_CODE", "GalileoSDK", "HttpBridgeResponse", "ServerInfo"]
