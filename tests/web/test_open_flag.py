"""``polynav run --open`` opens the console in the user's browser. No browser is opened: the
``webbrowser`` module's own ``BROWSER`` variable names a stand-in that fetches the page it is
given, so what the "browser" receives must be the console, served."""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

from polynav import cli
from tests.helpers.polynav_run import running, stop_run

STAND_IN = """\
import sys, time, urllib.request
url, out = sys.argv[1], sys.argv[2]
for _ in range(600):
    try:
        with urllib.request.urlopen(url, timeout=10) as answer:
            page = answer.read().decode()
        break
    except OSError:
        time.sleep(0.05)
else:
    page = "unreachable"
with open(out + ".tmp", "w") as f:
    f.write(url + "\\n" + page)
import os; os.replace(out + ".tmp", out)
"""


def test_run_open_gives_the_browser_the_consoles_address(tmp_path: Path) -> None:
    browser = tmp_path / "browser.py"
    browser.write_text(STAND_IN)
    seen = tmp_path / "seen.txt"
    os.environ["BROWSER"] = f"{sys.executable} {browser} %s {seen}"
    try:
        with running(tmp_path, None, "--open") as (proc, lines):
            deadline = time.monotonic() + 30.0
            while not seen.exists():
                assert time.monotonic() < deadline, "the browser was not opened"
                time.sleep(0.05)
            url, page = seen.read_text().split("\n", 1)
            assert url.startswith("http://127.0.0.1:") and url.endswith("/")
            assert f"native API {url}api " in "\n".join(lines)
            assert "<title>polynav console</title>" in page
            # The stand-in writes what it saw before it exits, and ``webbrowser.open`` returns
            # (and polynav says so) only after the exit: wait for the line, then stop.
            said = f"polynav: console opened in the browser: {url}"
            assert proc.stdout is not None
            while said not in lines[-1]:
                line = proc.stdout.readline()
                assert line, f"polynav ended without saying: {said}"
                lines.append(line.rstrip("\n"))
            stop_run(proc, lines)
    finally:
        del os.environ["BROWSER"]


def test_the_open_flag_is_off_unless_given() -> None:
    assert cli.build_parser().parse_args(["run"]).open is False
    assert cli.build_parser().parse_args(["run", "--open"]).open is True
