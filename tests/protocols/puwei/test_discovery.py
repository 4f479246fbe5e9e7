"""UDP discovery (puwei-api §3.1): ``discovery`` to the group or the port gets ``puwei ...``
back, to the sender only; ephemeral ports, nothing leaves 127.0.0.0/8."""

from __future__ import annotations

import socket
from collections.abc import Iterator

import pytest

from polynav.protocols.puwei.config import MULTICAST_GROUP
from polynav.runtime.robot_runtime import RobotRuntime
from tests.protocols.puwei.conftest import Harness, puwei_config, serving

COVERED = {
    'udp 224.0.0.1:9999 "discovery"': "test_discovery_to_the_group_on_loopback_is_answered",
}


@pytest.fixture
def announced(runtime: RobotRuntime) -> Iterator[Harness]:
    with serving(runtime, puwei_config(discovery_port=0)) as h:
        yield h


def client() -> socket.socket:
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_IF, socket.inet_aton("127.0.0.1"))
    sock.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 1)
    sock.bind(("127.0.0.1", 0))
    sock.settimeout(5.0)
    return sock


def test_discovery_to_the_group_on_loopback_is_answered(announced: Harness) -> None:
    port = announced.server.discovery_port
    assert port is not None
    with client() as sock:
        sock.sendto(b"discovery", (MULTICAST_GROUP, port))
        data, sender = sock.recvfrom(1024)
    assert data.startswith(b"puwei")
    assert data == f"puwei {announced.server.port}".encode()
    assert sender == ("127.0.0.1", port)


def test_discovery_by_unicast_is_answered_and_other_words_are_not(announced: Harness) -> None:
    port = announced.server.discovery_port
    assert port is not None
    with client() as sock, client() as other:
        other.settimeout(0.3)
        sock.sendto(b"hello", ("127.0.0.1", port))
        sock.sendto(b"discovery", ("127.0.0.1", port))
        data, _ = sock.recvfrom(1024)
        assert data.startswith(b"puwei")
        # Only the sender is answered: another socket hears nothing.
        with pytest.raises(TimeoutError):
            other.recvfrom(1024)
        # The word that came first got no answer either.
        sock.settimeout(0.3)
        with pytest.raises(TimeoutError):
            sock.recvfrom(1024)
