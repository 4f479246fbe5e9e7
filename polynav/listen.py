"""Listening TCP sockets for every server polynav runs (native API, each dialect).

Small request/response exchanges on kept-alive connections stall on Nagle's algorithm: a server
that writes a response's head and body separately (uvicorn does) holds the body back until the
client's delayed ACK, about 40 ms later. asyncio turns Nagle off on accepted connections only
when the listening socket says it is TCP (``proto == IPPROTO_TCP``), and
``socket.create_server`` leaves ``proto`` at 0. So every listener is made here: TCP by protocol
number, with ``TCP_NODELAY`` set on the listener too (Linux hands it on to accepted sockets,
whatever serves them).
"""

from __future__ import annotations

import socket


def tcp_listener(host: str, port: int, *, backlog: int = 128) -> socket.socket:
    """A bound, listening, non-blocking TCP socket whose connections never wait on Nagle.

    Args:
        host: interface to bind (``127.0.0.1`` by default everywhere in polynav).
        port: port to bind; 0 lets the OS choose.
        backlog: pending connections the kernel queues.

    Raises:
        OSError: the address cannot be resolved or bound.
    """
    family, kind, proto, _, address = socket.getaddrinfo(
        host, port, type=socket.SOCK_STREAM, proto=socket.IPPROTO_TCP, flags=socket.AI_PASSIVE
    )[0]
    sock = socket.socket(family, kind, proto)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        sock.bind(address)
        sock.listen(backlog)
        sock.setblocking(False)
    except BaseException:
        sock.close()
        raise
    return sock
