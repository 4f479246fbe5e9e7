"""HTTP callbacks a task asks the robot to make (``callback_action``), off the control loop.

A request waits on the network, so it never runs on the loop: :meth:`HttpCallbacks.start`
checks the address and hands the request to a worker thread, and the task polls
:meth:`HttpCallbacks.result` each tick. The network's time is wall time; the request's
``timeout`` is the socket's, so the worker needs no clock.

Where a callback may go is the runtime's to say (``RuntimeConfig.task_callback_hosts``): by
default only the loopback host (``localhost``, 127.0.0.0/8, ::1), because a task comes from
any client of any dialect and must not make the robot a proxy into the site's network. The
host is checked as written, never resolved, redirects are not followed (a redirect is an
answer, not a 2xx) and no proxy from the environment is used, so the check cannot be walked
round.
"""

from __future__ import annotations

import ipaddress
import itertools
import json
import logging
import socket
import threading
import urllib.error
import urllib.parse
import urllib.request
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from polynav.errors import Conflict, InvalidRequest

log = logging.getLogger(__name__)

MAX_BODY = 4096
"""Characters of the answer's body kept [chars]."""
MAX_READ = 64 * 1024
"""Bytes of the answer read at most [B]; the rest is left unread."""
MAX_RUNNING = 8
"""Callbacks in flight at once; more are refused (each holds a thread)."""
METHODS = ("GET", "POST", "PUT", "PATCH", "DELETE")
_LOOPBACK = ("localhost", "localhost.")


@dataclass(frozen=True, slots=True)
class CallbackResult:
    """How a callback ended: the HTTP ``status`` (0: no answer) and the answer's ``body``
    (text, at most :data:`MAX_BODY` characters), or ``error`` (network error, timeout)."""

    status: int
    body: str = ""
    error: str = ""

    @property
    def ok(self) -> bool:
        return 200 <= self.status < 300 and not self.error


class _NoRedirect(urllib.request.HTTPRedirectHandler):
    """Redirects are answers: following one would reach a host that was never checked."""

    def redirect_request(self, *args: Any, **kwargs: Any) -> None:
        return None


def _opener() -> urllib.request.OpenerDirector:
    return urllib.request.build_opener(urllib.request.ProxyHandler({}), _NoRedirect())


class HttpCallbacks:
    """The robot's HTTP callbacks; ``allowed`` are the hosts beyond loopback
    (``RuntimeConfig.task_callback_hosts``)."""

    def __init__(self, allowed: tuple[str, ...] = ()) -> None:
        self._names = {a.lower().rstrip(".") for a in allowed if not _network(a)}
        self._networks = [n for n in (_network(a) for a in allowed) if n is not None]
        self._results: dict[int, CallbackResult | None] = {}
        self._ids = itertools.count(1)
        self._lock = threading.Lock()

    def check(self, url: str) -> str:
        """The host of ``url`` if a callback may go there.

        Raises:
            InvalidRequest: not an http(s) URL, or a host the configuration does not allow.
        """
        try:
            parts = urllib.parse.urlsplit(url)
            host = parts.hostname or ""
            parts.port  # noqa: B018 - raises ValueError on a bad port
        except ValueError as exc:
            raise InvalidRequest("url", f"not a URL: {exc}") from None
        if parts.scheme not in ("http", "https") or not host:
            raise InvalidRequest("url", f"must be an http:// or https:// URL, got {url!r}")
        if not self.allows(host):
            raise InvalidRequest("url", f"callbacks may go to the loopback host only (and to "
                                        f"runtime.task_callback_hosts), not {host!r}")
        return host

    def allows(self, host: str) -> bool:
        """Whether a callback may go to ``host`` (as written in the URL; never resolved)."""
        name = host.lower().rstrip(".")
        if name in _LOOPBACK or name in self._names:
            return True
        try:
            address = ipaddress.ip_address(name)
        except ValueError:
            return False
        return address.is_loopback or any(address in n for n in self._networks)

    def start(self, url: str, method: str, data: Mapping[str, Any] | None,
              timeout: float) -> int:
        """Send the request from a worker thread; its id for :meth:`result`.

        ``data`` goes as a JSON body, or for ``GET`` and ``DELETE`` as the query string
        (strings as they are, other values as JSON).

        Raises:
            InvalidRequest: a bad URL, host or method (see :meth:`check`).
            Conflict: :data:`MAX_RUNNING` callbacks are in flight.
        """
        self.check(url)
        method = method.upper()
        if method not in METHODS:
            raise InvalidRequest("method", f"must be one of {', '.join(METHODS)}, got {method!r}")
        request = _request(url, method, data or {})
        with self._lock:
            if sum(1 for r in self._results.values() if r is None) >= MAX_RUNNING:
                raise Conflict(f"{MAX_RUNNING} callbacks are in flight already")
            call_id = next(self._ids)
            self._results[call_id] = None
        worker = threading.Thread(target=self._send, args=(call_id, request, timeout),
                                  name=f"callback-{call_id}", daemon=True)
        worker.start()
        log.info("callback %d: %s %s", call_id, method, url)
        return call_id

    def result(self, call_id: int) -> CallbackResult | None:
        """How callback ``call_id`` ended; ``None`` while it waits."""
        with self._lock:
            return self._results.get(call_id)

    def forget(self, call_id: int) -> None:
        """Drop a callback's result (read, or no longer wanted: the worker's answer is lost).
        """
        with self._lock:
            if self._results.get(call_id) is not None:
                del self._results[call_id]
            elif call_id in self._results:
                self._results[call_id] = CallbackResult(0, error="abandoned")

    def _send(self, call_id: int, request: urllib.request.Request, timeout: float) -> None:
        try:
            with _opener().open(request, timeout=timeout) as answer:
                result = CallbackResult(answer.status, _text(answer.read(MAX_READ)))
        except urllib.error.HTTPError as exc:  # a non-2xx answer (redirects included)
            result = CallbackResult(exc.code, _text(exc.read(MAX_READ)))
        except TimeoutError:
            result = CallbackResult(0, error=f"timeout after {timeout:g} s")
        except (urllib.error.URLError, OSError, ValueError) as exc:
            reason = getattr(exc, "reason", exc)
            if isinstance(reason, TimeoutError | socket.timeout):
                result = CallbackResult(0, error=f"timeout after {timeout:g} s")
            else:
                result = CallbackResult(0, error=f"network error: {reason}")
        log.info("callback %d: %s", call_id, result.status or result.error)
        with self._lock:
            if call_id in self._results and self._results[call_id] is None:
                self._results[call_id] = result
            else:  # forgotten while it ran
                self._results.pop(call_id, None)


def _network(text: str) -> ipaddress.IPv4Network | ipaddress.IPv6Network | None:
    try:
        return ipaddress.ip_network(text, strict=False)
    except ValueError:
        return None


def _request(url: str, method: str, data: Mapping[str, Any]) -> urllib.request.Request:
    if method in ("GET", "DELETE"):
        if data:
            query = urllib.parse.urlencode(
                {k: v if isinstance(v, str) else json.dumps(v) for k, v in data.items()})
            url = f"{url}{'&' if urllib.parse.urlsplit(url).query else '?'}{query}"
        return urllib.request.Request(url, method=method)
    return urllib.request.Request(url, data=json.dumps(data).encode(), method=method,
                                  headers={"Content-Type": "application/json"})


def _text(data: bytes) -> str:
    return data.decode("utf-8", errors="replace")[:MAX_BODY]
