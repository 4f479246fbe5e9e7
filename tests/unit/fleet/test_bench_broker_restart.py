"""``polynav bench fleet --transport mqtt --broker-restart-at S`` kills the real Mosquitto mid-run
and starts it again; the fleet manager's missions all end, none failed or requeued (the light
vehicles share one connection per process: no will to requeue them)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

from tests.helpers.mosquitto import mosquitto_binary

ROOT = Path(__file__).resolve().parents[3]


def test_a_broker_restart_mid_run_costs_no_mission() -> None:
    mosquitto_binary()  # fails the test with how to install it, when absent
    done = subprocess.run(
        [sys.executable, "-m", "polynav", "bench", "fleet", "--transport", "mqtt", "--robots",
         "12", "--processes", "2", "--agents", "kinematic", "--sim-seconds", "60", "--speed",
         "6", "--kinematic-speed", "2", "--lift-wait", "5", "--cross-floor",
         "--mission-rate", "1", "--broker-restart-at", "15", "--json"],
        cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)}, capture_output=True, text=True,
        timeout=120.0, check=False)
    assert done.returncode == 0, done.stderr[-3000:]
    lines = done.stdout.strip().splitlines()
    figures = json.loads(lines[-1])
    assert figures["broker_restarts"] == 1
    assert any("broker restarts 1" in line for line in lines)
    assert figures["missions"] >= 20
    assert figures["succeeded"] == figures["missions"] and figures["failed"] == []
    assert figures["mission_requeues"] == 0
    assert figures["missions_unfinished"] <= figures["robots"]  # only those under way
    assert figures["unsent_messages"] > 0  # the outage was real: states went nowhere
