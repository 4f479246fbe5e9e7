"""Galileo automation (Blockly) tasks over real HTTP (galileo-tasks-bt-ws §6): kept in the site
store, run in their own limited process when polynav runs with automations on, triggered by a
task's ``blockly_action`` through the API block's key."""

from __future__ import annotations

import time
from typing import Any

from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import World
from tests.protocols.galileo.conftest import Harness, serving

COVERED = {
    "GET /api/v1/blockly_task": "test_blockly_tasks_are_kept_changed_and_deleted",
    "POST /api/v1/blockly_task": "test_blockly_tasks_are_kept_changed_and_deleted",
    "PUT /api/v1/blockly_task": "test_blockly_tasks_are_kept_changed_and_deleted",
    "DELETE /api/v1/blockly_task": "test_blockly_tasks_are_kept_changed_and_deleted",
}

XML = ('<xml><block type="api_trigger"><field name="api_key">{key}</field>'
       '<statement name="DO"></statement></block></xml>')


def _blockly(title: str, py: str, key: str | None = None, enabled: bool = True
             ) -> dict[str, Any]:
    return {"title": title, "description": f"{title} for the test", "py": py,
            "blocklyxml": XML.format(key=key) if key else "<xml></xml>", "is_enabled": enabled}


def test_blockly_tasks_are_kept_changed_and_deleted(galileo: Harness) -> None:
    made = galileo.ok("POST", "/blockly_task", json=_blockly("greet", "robot.say('hi')\n",
                                                              key="greet_key"))
    assert made["title"] == "greet" and made["is_enabled"] is True
    assert made["api_key"] == "greet_key"  # read from the API block
    assert made["state"] == "WAITTING"  # automations are off here: kept, not run
    listed = galileo.ok("GET", "/blockly_task")
    assert [a["id"] for a in listed] == [made["id"]]
    changed = galileo.ok("PUT", "/blockly_task", json={"id": made["id"], "title": "hello",
                                                       "is_enabled": False})
    assert changed["title"] == "hello" and changed["is_enabled"] is False
    assert changed["py"] == "robot.say('hi')\n"  # kept as it was
    assert galileo.ok("DELETE", "/blockly_task", params={"id": made["id"]}) == {"status": "ok"}
    assert galileo.ok("GET", "/blockly_task") == []


def test_bad_blockly_requests_change_nothing(galileo: Harness) -> None:
    missing = galileo.post("/blockly_task", {"title": "x", "description": "", "py": "pass"})
    assert missing.status_code == 400 and missing.json()["status"] == "error"
    wrong = galileo.post("/blockly_task", {**_blockly("x", "pass"), "is_enabled": "maybe"})
    assert wrong.status_code == 400
    assert galileo.put("/blockly_task", {"id": "nope", "title": "y"}).status_code == 404
    assert galileo.delete("/blockly_task", id="nope").status_code == 404
    galileo.ok("POST", "/blockly_task", json=_blockly("a", "pass\n", key="k1"))
    taken = galileo.post("/blockly_task", _blockly("b", "pass\n", key="k1"))
    assert taken.status_code == 400 and "already triggers" in taken.json()["description"]
    assert len(galileo.ok("GET", "/blockly_task")) == 1


def test_a_blockly_action_triggers_the_automation_which_drives_the_robot(
        world: World, store: SiteStore) -> None:
    runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False,
                                                                         automations=True))
    with serving(runtime) as g:
        g.ok("GET", "/navigation/start", params={"map": "floor1", "start_index": 2})
        assert g.advance_until(lambda: g.runtime.status().mode == "navigating", 10.0)
        program = "r = robot.say('hello from blockly')\nprint('said', r['state'])\n"
        automation = g.ok("POST", "/blockly_task", json=_blockly("hello", program,
                                                                 key="hello_key"))
        task = g.ok("POST", "/task", json={"name": "trigger", "sub_tasks": [
            {"type": "blockly_action", "api_key": "hello_key"}]})
        g.ok("GET", "/task/start", params={"id": task["id"]})

        def ran() -> bool:
            time.sleep(0.01)  # the program's process answers in wall time
            return g.ok("GET", "/blockly_task")[0]["state"] not in ("WAITTING", "WORKING")

        assert g.advance_until(ran, 120.0, step=0.2)
        assert g.ok("GET", "/task", params={"id": task["id"]})["state"] == "COMPLETE"
        assert g.ok("GET", "/blockly_task")[0]["state"] == "COMPLETE"
        run = runtime.automations.runner.runs(automation["id"])[-1]
        assert "said COMPLETE" in run["log"]
        assert runtime.peripherals.devices.speaker.text == "hello from blockly"
        # A key no automation has: the action FAILs in a tree, ERROR shown in a plain task.
        other = g.ok("POST", "/task", json={"name": "nobody", "control_type": "sequence",
                                            "sub_tasks": [{"type": "blockly_action",
                                                           "api_key": "nobody"}]})
        g.ok("GET", "/task/start", params={"id": other["id"]})
        assert g.advance_until(lambda: g.ok("GET", "/task", params={"id": other["id"]})[
            "state"] == "FAIL", 10.0)
