"""Looking at the server's end of a loopback connection, for servers running in this process."""

from __future__ import annotations

import contextlib
import os
import socket


def server_end_nodelay(client: socket.socket) -> int:
    """``TCP_NODELAY`` of the socket in this process whose peer is ``client``.

    Scans this process's file descriptors for the accepted socket (its peer address is the
    client's own address), whatever server accepted it (asyncio, uvicorn).

    Raises:
        LookupError: no such socket in this process.
    """
    wanted = client.getsockname()
    for name in os.listdir("/proc/self/fd"):
        fd = int(name)
        with contextlib.suppress(OSError):
            candidate = socket.socket(fileno=os.dup(fd))
            with candidate:
                if candidate.type != socket.SOCK_STREAM:
                    continue
                with contextlib.suppress(OSError):
                    if candidate.getpeername() == wanted:
                        return candidate.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY)
    raise LookupError(f"no socket in this process is connected to {wanted}")
