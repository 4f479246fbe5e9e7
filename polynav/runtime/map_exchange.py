"""Maps exchanged with a dispatch server (Galileo's ``upload_map_action`` and
``download_map_action``), off the control loop.

Galileo robots send their maps to, and fetch maps from, a dispatch server named by
``server_id``; the document gives no wire format. polynav's (docs/decisions.md): each server is
configured by id and base URL (``RuntimeConfig.dispatch_servers``, ``polynav run
--dispatch-server ID=URL``); a map travels as a zip holding ``map.yaml`` and ``map.png`` (ROS
map_server files, as Galileo's own map archive): upload is ``PUT {url}/maps/{name}`` with the
zip as the body, download is ``GET {url}/maps/{map_id}`` answering one, saved in the site store
as map ``map_id``. Only hosts a task's callback may reach are allowed (loopback unless
configured), redirects are answers and no proxy is used, as for callbacks. Transfers run on a
worker thread each; the task polls :meth:`MapExchange.result` every tick.
"""

from __future__ import annotations

import io
import itertools
import logging
import tempfile
import threading
import urllib.error
import urllib.parse
import urllib.request
import zipfile
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path

from polynav.errors import Conflict, InvalidRequest, NotFound, PolynavError
from polynav.maps import ros_map
from polynav.maps.map import Map
from polynav.runtime.http_callbacks import HttpCallbacks

log = logging.getLogger(__name__)

TIMEOUT = 30.0  # [s] of one transfer's socket
MAX_ARCHIVE = 64 * 1024 * 1024  # [B] of a map fetched
MAX_MEMBER = 64 * 1024 * 1024  # [B] of one file in it


@dataclass(frozen=True, slots=True)
class TransferResult:
    """How a transfer ended: ``ok``, or why not (``error``); the HTTP ``status`` if any."""

    ok: bool
    status: int = 0
    error: str = ""


def map_archive(grid: Map, extra: Mapping[str, str] | None = None) -> bytes:
    """``grid`` as a zip of ROS map files, ``map.yaml`` and ``map.png`` (the exchange's, and
    the core of Galileo's map archive), with ``extra`` text members beside them."""
    buffer = io.BytesIO()
    with tempfile.TemporaryDirectory() as folder:
        yaml_path = Path(folder) / "map.yaml"
        ros_map.save_map(grid, yaml_path, image_format="png")
        with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as zf:
            zf.write(yaml_path, "map.yaml")
            zf.write(Path(folder) / "map.png", "map.png")
            for name, text in (extra or {}).items():
                zf.writestr(name, text)
    return buffer.getvalue()


def read_archive(data: bytes) -> Map:
    """The map in an exchange zip.

    Raises:
        InvalidRequest: not a zip, no ``map.yaml`` and the picture it names, a file too large,
            or a map that does not load.
    """
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as zf, tempfile.TemporaryDirectory() as folder:
            names = set(zf.namelist())
            if "map.yaml" not in names:
                raise InvalidRequest("map", "the archive holds no map.yaml")
            for info in zf.infolist():
                if info.filename not in ("map.yaml", "map.png", "map.pgm"):
                    continue
                if info.file_size > MAX_MEMBER:
                    raise InvalidRequest("map", f"{info.filename} is too large")
                (Path(folder) / info.filename).write_bytes(zf.read(info))
            return ros_map.load_map(Path(folder) / "map.yaml")
    except zipfile.BadZipFile as exc:
        raise InvalidRequest("map", f"not a zip archive: {exc}") from None


class MapExchange:
    """The robot's map transfers; ``servers`` maps a dispatch server id to its base URL."""

    def __init__(self, servers: Mapping[str, str], callbacks: HttpCallbacks) -> None:
        self._servers = dict(servers)
        self._callbacks = callbacks
        for url in self._servers.values():
            callbacks.check(url)
        self._results: dict[int, TransferResult | None] = {}
        self._ids = itertools.count(1)
        self._lock = threading.Lock()

    def url(self, server_id: str) -> str:
        """The base URL of ``server_id``.

        Raises:
            NotFound: no such dispatch server is configured.
        """
        url = self._servers.get(server_id)
        if url is None:
            known = ", ".join(sorted(self._servers)) or "none configured"
            raise NotFound("dispatch server", f"{server_id} (known: {known})")
        return url.rstrip("/")

    def upload(self, server_id: str, name: str, grid: Map) -> int:
        """Send map ``name`` to ``server_id``; the transfer's id."""
        url = f"{self.url(server_id)}/maps/{urllib.parse.quote(name, safe='')}"
        request = urllib.request.Request(url, data=map_archive(grid), method="PUT",
                                         headers={"Content-Type": "application/zip"})
        return self._start(request, lambda data: None)

    def download(self, server_id: str, map_id: str, save: Callable[[Map], object]) -> int:
        """Fetch map ``map_id`` from ``server_id`` and ``save`` it; the transfer's id."""
        url = f"{self.url(server_id)}/maps/{urllib.parse.quote(map_id, safe='')}"
        request = urllib.request.Request(url, method="GET")
        return self._start(request, lambda data: save(read_archive(data)))

    def result(self, transfer_id: int) -> TransferResult | None:
        """How a transfer ended; ``None`` while it runs."""
        with self._lock:
            return self._results.get(transfer_id)

    def forget(self, transfer_id: int) -> None:
        with self._lock:
            self._results.pop(transfer_id, None)

    def _start(self, request: urllib.request.Request, then: Callable[[bytes], object]) -> int:
        self._callbacks.check(request.full_url)
        with self._lock:
            if sum(1 for r in self._results.values() if r is None) >= 4:
                raise Conflict("4 map transfers are under way already")
            transfer_id = next(self._ids)
            self._results[transfer_id] = None
        threading.Thread(target=self._run, args=(transfer_id, request, then), daemon=True,
                         name=f"map-transfer-{transfer_id}").start()
        log.info("map transfer %d: %s %s", transfer_id, request.get_method(), request.full_url)
        return transfer_id

    def _run(self, transfer_id: int, request: urllib.request.Request,
             then: Callable[[bytes], object]) -> None:
        opener = urllib.request.build_opener(urllib.request.ProxyHandler({}), _NoRedirect())
        try:
            with opener.open(request, timeout=TIMEOUT) as answer:
                data = answer.read(MAX_ARCHIVE + 1)
                if len(data) > MAX_ARCHIVE:
                    raise InvalidRequest("map", f"larger than {MAX_ARCHIVE} bytes")
                then(data)
                result = TransferResult(True, answer.status)
        except urllib.error.HTTPError as exc:
            result = TransferResult(False, exc.code, f"the server answered {exc.code}")
        except PolynavError as exc:
            result = TransferResult(False, 200, str(exc))
        except (urllib.error.URLError, OSError, ValueError) as exc:
            result = TransferResult(False, 0, f"network error: {getattr(exc, 'reason', exc)}")
        log.info("map transfer %d: %s", transfer_id, "done" if result.ok else result.error)
        with self._lock:
            if transfer_id in self._results:
                self._results[transfer_id] = result


class _NoRedirect(urllib.request.HTTPRedirectHandler):
    """A redirect is an answer: following it would reach a host never checked."""

    def redirect_request(self, *args: object, **kwargs: object) -> None:
        return None
