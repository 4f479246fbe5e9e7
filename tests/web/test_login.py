"""The console when the API asks for a login (bound off loopback): its login form, the session
cookie carrying REST and the WebSocket, and a viewer who sees everything and drives nothing."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.api.auth_site import PASSWORDS, AuthSite, auth_site
from tests.web.conftest import screenshot


@pytest.fixture
def site(tmp_path: Path) -> Iterator[AuthSite]:
    with auth_site(tmp_path) as served:
        yield served


@pytest.fixture
def context(browser: Any) -> Iterator[Any]:
    ctx = browser.new_context(viewport={"width": 1280, "height": 800})
    yield ctx
    ctx.close()


def log_in(page: Any, name: str, password: str) -> None:
    page.fill("#login-name", name)
    page.fill("#login-password", password)
    page.click("#login-form button[type=submit]")


def test_a_viewer_logs_in_sees_the_robot_and_cannot_drive(site: AuthSite, context: Any) -> None:
    page = context.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda exc: errors.append(str(exc)))
    page.goto(site.url + "/")
    page.wait_for_selector("#login:not(.hidden)")
    screenshot(page, "login")
    log_in(page, "victor", "not the password")
    page.wait_for_function("document.getElementById('login-error').textContent.length > 0")
    assert page.is_visible("#login")
    log_in(page, "victor", PASSWORDS["victor"])
    page.wait_for_selector("#login", state="hidden")
    # The stream comes through the WebSocket on the session cookie.
    page.wait_for_function("document.getElementById('st-mode').textContent === 'free'")
    assert page.text_content("#user") == "victor (viewer)"
    for control in ("#nav-start", "#estop", "#map-start", "[data-tool=wall]", "#task-create"):
        assert page.is_disabled(control), control
    page.mouse.click(400, 400)  # a click on the map sends no goal
    page.keyboard.press("ArrowUp")
    assert page.evaluate("window.polynav.status.navigation.state") == "idle"
    assert page.evaluate("window.polynav.status.mode") == "free"
    screenshot(page, "viewer")
    page.click("#logout")
    page.wait_for_selector("#login:not(.hidden)")
    assert not errors, errors


def test_an_operator_logs_in_and_drives(site: AuthSite, context: Any) -> None:
    page = context.new_page()
    page.goto(site.url + "/")
    log_in(page, "olga", PASSWORDS["olga"])
    page.wait_for_selector("#login", state="hidden")
    page.wait_for_function("document.getElementById('user').textContent === 'olga (operator)'")
    assert page.is_enabled("#nav-start")
    page.click("#nav-start")
    # The fake robot's clock stands still, so its stream sends no new status: ask the API, as
    # the page does, on the session cookie.
    page.wait_for_function("window.polynav.api.get('/api/status')"
                           ".then(s => s.mode === 'navigating')")
    cookies = {c["name"]: c for c in context.cookies()}
    session = next(c for c in cookies.values() if c["httpOnly"])
    assert session["sameSite"] == "Strict" and session["path"] == "/api"
