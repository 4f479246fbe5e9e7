"""``polynav bench fleet --transport mqtt`` runs end to end on a real Mosquitto, in a tiny
configuration, and prints its figures (timings are not asserted beyond the wall budget).

The benchmark forks its worker processes, so it runs in a process of its own here (not forked
from pytest's, which has threads).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pytest

from polynav.cli import main
from tests.helpers.mosquitto import mosquitto_binary

ROOT = Path(__file__).resolve().parents[2]


def _bench(*args: str, timeout: float) -> tuple[list[str], dict[str, Any], float]:
    mosquitto_binary()  # fails the test with how to install it, when absent
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    started = time.monotonic()
    done = subprocess.run(
        [sys.executable, "-m", "polynav", "bench", "fleet", "--transport", "mqtt", *args,
         "--json"], cwd=ROOT, env=env, capture_output=True, text=True, timeout=timeout,
        check=False)
    wall = time.monotonic() - started
    assert done.returncode == 0, done.stderr[-3000:]
    lines = done.stdout.strip().splitlines()
    return lines, json.loads(lines[-1]), wall


def test_two_full_robots_in_two_processes_run_end_to_end() -> None:
    lines, figures, wall = _bench("--robots", "2", "--processes", "2", "--sim-seconds", "30",
                                  "--speed", "3", timeout=120.0)
    assert wall < 60.0
    assert figures["agents"] == "full" and figures["processes"] == 2
    assert figures["sim_seconds"] >= 29.0
    assert figures["orders_acknowledged"] >= 2  # each robot's first order, at least
    assert figures["order_latency_p50_ms"] > 0.0
    assert figures["states_read"] > 0 and figures["lost_state_messages"] == 0
    assert figures["broker_messages_per_s"]["received"] > 0.0
    # each worker drew the other's robot from its visualization messages
    assert figures["remote_pose_samples"] > 0
    assert figures["remote_pose_staleness_max_s"] >= figures["visualization_period_s"]
    assert figures["real_time_factor"] > 0.0 and figures["cpu_per_robot"] > 0.0
    assert figures["collisions"] == 0
    assert any(line.startswith("remote robots: poses every 0.25 s") for line in lines)
    assert any(line.startswith("order latency (publish -> first state") for line in lines)


def test_the_light_mode_says_so_and_loses_no_state() -> None:
    lines, figures, _ = _bench("--robots", "20", "--processes", "2", "--agents", "kinematic",
                               "--sim-seconds", "40", "--speed", "4", "--kinematic-speed", "2",
                               "--lift-wait", "5", "--cross-floor", timeout=120.0)
    assert figures["agents"] == "kinematic (light mode)" and figures["shared_connection"]
    assert any(line.startswith("light mode: kinematic vehicles") for line in lines)
    assert figures["missions"] > 0 and figures["succeeded"] == figures["missions"]
    assert figures["orders_acknowledged"] >= 20
    assert figures["lost_state_messages"] == 0


@pytest.mark.parametrize("args", [
    ["--transport", "mqtt", "--robots", "2", "--processes", "3"],
    ["--transport", "mqtt", "--robots", "2", "--speed", "0"],
    ["--agents", "kinematic"],
])
def test_bad_options_are_refused(args: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_info:
        main(["bench", "fleet", *args])
    assert exit_info.value.code == 2
    assert "polynav bench fleet: error:" in capsys.readouterr().err
