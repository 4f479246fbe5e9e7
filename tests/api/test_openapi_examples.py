"""The OpenAPI document's examples work: each, sent as Schemathesis's examples phase sends it,
answers 2xx on the demo site, and the links lead where they say.

The examples phase of tests/api/test_openapi_fuzz.py sends the same requests with every check,
but there a 404 or a 409 is a declared answer and passes; here an example that names a car, a
map or a point the demo site lacks fails. Each operation's examples run on a fresh demo site,
after the examples of the operation that puts the robot in the mode they need (a goal needs
navigation started), as a person trying the document in order would.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any, cast

import httpx
import pytest
import schemathesis
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from schemathesis import Case
from schemathesis.schemas import APIOperation

from polynav.api import ApiConfig, create_app
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from tests.api.fakes import FakeRuntime


class _Unbound:
    """Stands in for the runtime and the store until each operation binds a fresh site (see
    tests/api/test_openapi_fuzz.py)."""


APP = create_app(
    cast(RobotRuntime, _Unbound()), ApiConfig(port=0), store=cast(SiteStore, _Unbound())
)
schema = schemathesis.openapi.from_asgi("/openapi.json", APP)
DEMO = load_world("demo")

# The operation whose examples put the robot in the mode another's need.
NEEDS = {
    "set_initial_pose": "start_navigation",
    "send_goal": "start_navigation",
    "save_mapping": "start_mapping",
    "stop_mapping": "start_mapping",
    "delete_path": "save_path",
    "leave_cart": "dock_cart",
}
# Operations that name a resource (a path or a body naming a car, map, point) or need a mode:
# the ones the issue asks to reach, which must have examples that answer 2xx.
MUST_REACH = {
    "request_lift", "set_lift_mode", "start_navigation", "send_goal", "set_initial_pose",
    "get_map", "get_map_image", "list_points", "create_point", "get_point", "update_point",
    "delete_point", "start_mapping", "save_mapping", "stop_mapping", "create_task",
    "dock_cart", "leave_cart",
}


def _operations() -> dict[str, APIOperation]:
    found = {}
    for result in schema.get_all_operations():
        operation = result.ok()
        found[operation.definition.raw["operationId"]] = operation
    return found


OPERATIONS = _operations()


@pytest.fixture
def sites(tmp_path: Path) -> Iterator[list[SiteStore]]:
    opened: list[SiteStore] = []
    yield opened
    for store in opened:
        store.close()


def _fresh_site(root: Path, opened: list[SiteStore]) -> None:
    store = SiteStore.open(root / f"site{len(opened)}", seed_world=DEMO)
    opened.append(store)
    APP.state.runtime, APP.state.store = FakeRuntime(store), store


def _example_cases(data: st.DataObject, operation_id: str) -> list[Case]:
    strategies = OPERATIONS[operation_id].get_strategies_from_examples()
    return [data.draw(strategy) for strategy in strategies]


def test_every_example_answers_2xx_on_the_demo_site(
    tmp_path: Path, sites: list[SiteStore]
) -> None:
    answers: dict[str, list[int]] = {}

    @settings(max_examples=1, database=None, derandomize=True, deadline=None,
              suppress_health_check=list(HealthCheck))
    @given(data=st.data())
    def try_the_examples(data: st.DataObject) -> None:
        for operation_id in OPERATIONS:
            cases = _example_cases(data, operation_id)
            if not cases:
                continue
            for case in cases:
                _fresh_site(tmp_path, sites)
                if operation_id in NEEDS:
                    before = _example_cases(data, NEEDS[operation_id])[0]
                    assert before.call().status_code // 100 == 2, before.path
                # Every check of Schemathesis, as in the fuzz test, and the answer kept.
                response = case.call_and_validate()
                answers.setdefault(operation_id, []).append(response.status_code)

    try_the_examples()
    failing = {op: codes for op, codes in answers.items() if any(c // 100 != 2 for c in codes)}
    assert failing == {}, f"examples that do not answer 2xx on the demo site: {failing}"
    missing = MUST_REACH - set(answers)
    assert missing == set(), f"operations without an example: {sorted(missing)}"


def _link_targets(operation_id: str, status: str) -> dict[str, Any]:
    response = OPERATIONS[operation_id].definition.raw["responses"][status]
    return cast(dict[str, Any], response.get("links", {}))


def test_the_links_lead_to_operations_of_the_document() -> None:
    """Each link names an operation that exists and only parameters that operation has."""
    seen = 0
    for operation_id, operation in OPERATIONS.items():
        for status in operation.definition.raw["responses"]:
            for name, link in _link_targets(operation_id, status).items():
                target = OPERATIONS.get(link["operationId"])
                assert target is not None, f"{operation_id} {status} {name}"
                declared = {p["name"] for p in target.definition.raw.get("parameters", [])}
                assert set(link.get("parameters", {})) <= declared, (operation_id, name)
                seen += 1
    assert seen >= 6


def test_a_listed_car_is_reached_through_its_link(client: httpx.Client) -> None:
    """Over HTTP: GET /api/lifts hands its first car and a floor it serves on to the car's
    request, as the link says."""
    listed = client.get("/api/lifts").json()
    link = _link_targets("list_lifts", "200")["RequestListedCar"]
    car = _pointer(listed, link["parameters"]["car"])
    floor = _pointer(listed, link["requestBody"]["floor"])
    answer = client.post(f"/api/lifts/{car}/request", json={"floor": floor})
    assert answer.status_code == 200, answer.text
    assert answer.json()["destination_floor"] == floor


def test_a_listed_point_starts_navigation_through_its_link(client: httpx.Client) -> None:
    link = _link_targets("list_points", "200")["StartNavigationAtListedPoint"]
    listed = client.get("/api/points").json()
    body = {key: _pointer(listed, expression) for key, expression in link["requestBody"].items()}
    assert client.post("/api/navigation/start", json=body).status_code == 200
    status = client.get("/api/status").json()
    assert (status["mode"], status["map"]) == ("navigating", listed[0]["map"])
    goal = _link_targets("start_navigation", "200")["GoalAtTheStart"]
    assert goal["requestBody"] == {"point": "$request.body#/point"}
    assert client.post("/api/navigation/goal", json={"point": body["point"]}).status_code == 202


def _pointer(document: Any, expression: str) -> Any:
    """The value a ``$response.body#/a/0/b`` expression names in ``document``."""
    prefix = "$response.body#/"
    assert expression.startswith(prefix)
    for part in expression[len(prefix):].split("/"):
        document = document[int(part)] if isinstance(document, list) else document[part]
    return document
