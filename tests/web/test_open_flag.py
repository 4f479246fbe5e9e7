"""``polynav run --open`` opens the console in the user's browser: the browser is stood in for
(never opened by a test), and what it is given must be the console, served."""

from __future__ import annotations

import os
import signal
import threading
import time
import urllib.error
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import pytest

from polynav import cli
from tests.helpers.polynav_run import run_args


@pytest.fixture
def signal_handlers() -> Iterator[None]:
    """``polynav run`` installs its own SIGINT/SIGTERM handlers: put pytest's back after."""
    saved = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    yield
    for sig, handler in saved.items():
        signal.signal(sig, handler)


def _fetch_then_interrupt(url: str, pages: list[str]) -> None:
    deadline = time.monotonic() + 30.0
    try:
        while True:
            try:
                with urllib.request.urlopen(url, timeout=10.0) as answer:
                    pages.append(answer.read().decode())
                return
            except (urllib.error.URLError, ConnectionError):
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.05)
    finally:
        os.kill(os.getpid(), signal.SIGINT)  # as Ctrl-C: polynav run stops cleanly


def test_run_open_gives_the_browser_the_consoles_address(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str],
    signal_handlers: None,
) -> None:
    opened: list[str] = []
    pages: list[str] = []

    def browser(url: str) -> bool:
        opened.append(url)
        threading.Thread(target=_fetch_then_interrupt, args=(url, pages), daemon=True).start()
        return True

    monkeypatch.setattr("webbrowser.open", browser)
    argv = run_args(tmp_path, None, "--open")[3:]  # after "python -m polynav"
    assert cli.main(argv) == 0
    assert len(opened) == 1 and opened[0].startswith("http://127.0.0.1:")
    assert opened[0].endswith("/")
    assert pages and "<title>polynav console</title>" in pages[0]
    out = capsys.readouterr().out
    assert f"console opened in the browser: {opened[0]}" in out


def test_the_open_flag_is_off_unless_given() -> None:
    assert cli.build_parser().parse_args(["run"]).open is False
    assert cli.build_parser().parse_args(["run", "--open"]).open is True
