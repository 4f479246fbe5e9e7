"""The SDK's return codes and the records its calls hand back (galileo-wire-protocols §6.4-6.5)."""

from __future__ import annotations

import enum
from dataclasses import dataclass


class GALILEO_RETURN_CODE(enum.IntEnum):
    """What every call answers; the spellings (``INVALIDE_...``) are the SDK's."""

    OK = 0
    NOT_CONNECTED = 1
    INVALIDE_STATE = 2
    NO_SERVER_FOUND = 3
    MULTI_SERVER_FOUND = 4
    NETWORK_ERROR = 5
    ALREADY_CONNECTED = 6
    TIMEOUT = 7
    SERVER_ERROR = 8
    GOAL_CANCELLED = 9
    INVALIDE_GOAL = 10
    INVALIDE_PARAMS = 11


@dataclass(frozen=True, slots=True)
class ServerInfo:
    """A robot heard on the LAN: its announcement and the address it came from.

    Attributes:
        ID: the robot's id (76 hex digits on a Galileo robot).
        mac: its MAC address.
        port: its HTTP port.
        ip: the announcement's sender.
        version: its HTTP API version.
        timestamp: when it was last heard [s, monotonic clock].
    """

    ID: str
    mac: str
    port: int
    ip: str
    version: str
    timestamp: float

    def getID(self) -> str:
        return self.ID


@dataclass(frozen=True, slots=True)
class HttpBridgeResponse:
    """``SendGalileoBridgeRequest``'s answer: the request's id, the HTTP status, the body."""

    uuid: str
    status_code: int
    body: str
