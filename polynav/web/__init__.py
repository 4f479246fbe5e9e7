"""The web console: a single-page app served by the native API at ``/`` (docs/console.md).

Static files only (``index.html``, ES modules, a style sheet), no build step: the browser loads
them as they are in this package and talks to the same server's REST API and WebSocket, so the
console can do nothing a program could not.
"""

from __future__ import annotations

import logging
import threading
import time
import webbrowser
from collections.abc import Callable
from pathlib import Path

from fastapi import FastAPI
from fastapi.responses import FileResponse
from fastapi.staticfiles import StaticFiles

log = logging.getLogger(__name__)

#: Where the console's files are.
STATIC_DIR = Path(__file__).parent / "static"
#: The URL prefix of its scripts and style sheet.
ASSETS_PREFIX = "/web"


def install_console(app: FastAPI) -> None:
    """Serve the console: ``/`` is its page, ``/web/...`` its scripts and styles (both left
    out of the OpenAPI document: they are not part of the API)."""

    @app.get("/", include_in_schema=False)
    def console_page() -> FileResponse:
        return FileResponse(STATIC_DIR / "index.html", media_type="text/html",
                            headers={"Cache-Control": "no-cache"})

    app.mount(ASSETS_PREFIX, StaticFiles(directory=STATIC_DIR), name="console")


#: How long ``--open`` waits for the server to serve before opening the browser anyway [s].
SERVE_WAIT = 30.0


def open_console_when_serving(serving: Callable[[], bool], url: str) -> threading.Thread:
    """Open the console in the browser once ``serving()`` is true, from a daemon thread: a
    browser's first request must find the server answering, and a browser that holds the call
    until it is closed (a text-mode one) must not hold up the server's start."""

    def run() -> None:
        deadline = time.monotonic() + SERVE_WAIT
        while not serving() and time.monotonic() < deadline:
            time.sleep(0.05)
        open_console(url)

    thread = threading.Thread(target=run, name="open-console", daemon=True)
    thread.start()
    return thread


def open_console(url: str) -> bool:
    """Open the console at ``url`` in the user's browser (``polynav run --open``); says so on
    standard output, or that no browser could be found (the URL is printed anyway)."""
    opened = webbrowser.open(url)
    if opened:
        print(f"polynav: console opened in the browser: {url}", flush=True)
    else:
        print(f"polynav: no browser to open; the console is at {url}", flush=True)
    return opened
