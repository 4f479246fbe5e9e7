"""Fixtures of the web console's browser tests: Debian's Chromium driven by Playwright, and a
real native API around a simulated robot looping at a speed, on an ephemeral loopback port.

The browser is required: without chromium these tests fail, saying what to install; only
``POLYNAV_SKIP_BROWSER=1`` skips them (tools/system_deps.sh installs chromium for ``make test``).
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from polynav.api import ApiConfig, create_app
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from tests.api.server import ServerThread

CHROMIUM = "/usr/bin/chromium"
ARTIFACTS = Path(__file__).parent / "artifacts"
SPEED = 8.0  # simulated seconds per wall second: goals of a few metres end in about a second


def _browser_missing() -> str | None:
    if not (os.path.exists(CHROMIUM) or shutil.which("chromium")):
        return (f"the browser tests need Debian's chromium at {CHROMIUM}: run tools/system_deps.sh "
                "(or apt-get install chromium), or set POLYNAV_SKIP_BROWSER=1 to skip them")
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return "the browser tests need the playwright package: pip install -e '.[test]'"
    return None


# Per module, not per session: Playwright's sync API keeps an event loop running on the main
# thread while it is open, and a later test in the same process (xdist worker) that runs its own
# loop (asyncio.run) would fail.
@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    if os.environ.get("POLYNAV_SKIP_BROWSER") == "1":
        pytest.skip("POLYNAV_SKIP_BROWSER=1: the web console's browser tests are skipped")
    missing = _browser_missing()
    if missing is not None:
        pytest.fail(missing, pytrace=False)
    from playwright.sync_api import sync_playwright

    with sync_playwright() as play:
        chromium = play.chromium.launch(
            executable_path=CHROMIUM if os.path.exists(CHROMIUM) else shutil.which("chromium"),
            headless=True, args=["--no-sandbox", "--disable-gpu"])
        yield chromium
        chromium.close()


class Console:
    """A running robot, its API on a port, and where to point the browser."""

    def __init__(self, runtime: RobotRuntime, server: ServerThread) -> None:
        self.runtime = runtime
        self.server = server
        self.url = server.url + "/"


@pytest.fixture
def console(tmp_path: Path) -> Iterator[Console]:
    world = load_world("demo")
    store = SiteStore.open(tmp_path / "data", seed_world=world)
    runtime = RobotRuntime.simulated(store, world,
                                     config=RuntimeConfig(speed=SPEED, people=False))
    server = ServerThread(create_app(runtime, ApiConfig(port=0))).start()
    runtime.start()
    try:
        yield Console(runtime, server)
    finally:
        server.stop()
        runtime.stop()
        store.close()


@pytest.fixture
def page(browser: Any, console: Console) -> Iterator[Any]:
    """A 1280x800 page of the console, loaded; JavaScript errors fail the test."""
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    page = context.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.goto(console.url)
    page.wait_for_function("window.polynav && window.polynav.status !== null", timeout=15000)
    yield page
    context.close()
    assert not errors, errors


def screenshot(page: Any, name: str) -> None:
    """Save what the page shows, for a person to look at (tests/web/artifacts/, not in git)."""
    ARTIFACTS.mkdir(exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / f"{name}.png"))
