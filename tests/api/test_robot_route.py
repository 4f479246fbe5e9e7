"""GET /api/robot shows the profile; POST /api/robot/check refuses bad profiles naming the field;
PUT /api/settings is held to the profile (409 `beyond_profile` with the reason)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest

from polynav.robot.profile import load_profile
from polynav.runtime.config import RuntimeConfig
from polynav.runtime.robot_runtime import RobotRuntime
from polynav.store.site_store import SiteStore
from polynav.worlds import load_world
from tests.api.server import native_client


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> Iterator[httpx.Client]:
    """The API around a real runtime of the rectangular research base (its loop not running:
    commands run at once)."""
    world = load_world("demo")
    store = SiteStore.open(tmp_path_factory.mktemp("robot") / "site", seed_world=world)
    runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=False),
                                     profile=load_profile("research-base"))
    with native_client(runtime) as http:
        yield http
    store.close()


def test_get_robot_shows_the_profile(client: httpx.Client) -> None:
    body = client.get("/api/robot").json()
    assert body["name"] == "research-base"
    assert len(body["footprint"]["polygon"]) == 4
    assert body["limits"]["max_linear_velocity"] == 2.0
    assert body["inscribed_radius"] == pytest.approx(0.215)
    assert body["lidar"]["pose"]["x"] == pytest.approx(0.12)


def test_settings_above_the_profile_or_below_the_body_are_409(client: httpx.Client) -> None:
    r = client.put("/api/settings", json={"max_linear_velocity": 2.5})  # schema-valid
    assert r.status_code == 409
    assert r.json()["error"]["code"] == "beyond_profile"
    assert "limits.max_linear_velocity" in r.json()["error"]["message"]
    r = client.put("/api/settings", json={"robot_radius": 0.1})
    assert r.status_code == 409
    assert "below the body" in r.json()["error"]["message"]
    # Within the profile it applies, and 2 m/s is allowed for this robot.
    r = client.put("/api/settings", json={"max_linear_velocity": 1.8, "robot_radius": 0.3})
    assert r.status_code == 200 and r.json()["max_linear_velocity"] == 1.8


def _profile(**changes: Any) -> dict[str, Any]:
    doc: dict[str, Any] = {"name": "t", "footprint": {"radius": 0.2}}
    doc.update(changes)
    return doc


def test_check_accepts_a_good_profile_with_defaults_filled_in(client: httpx.Client) -> None:
    r = client.post("/api/robot/check", json=_profile(limits={"max_linear_velocity": 1.5}))
    assert r.status_code == 200
    assert r.json()["limits"]["max_linear_velocity"] == 1.5
    assert r.json()["lidar"]["beams"] == 360
    # 108.0 is an integer in JSON Schema's sense (what Schemathesis found refused)
    r = client.post("/api/robot/check", json=_profile(lidar={"beams": 108.0}))
    assert r.status_code == 200 and r.json()["lidar"]["beams"] == 108
    r = client.post("/api/robot/check", json=_profile(lidar={"beams": 108.5}))
    assert r.status_code in (409, 422) and "beams" in r.json()["error"]["message"]


@pytest.mark.parametrize(
    ("doc", "status", "field"),
    [
        (_profile(limits={"max_linear_velocity": -1.0}), 409, "robot.limits.max_linear_velocity"),
        (_profile(footprint={"polygon": [[0.3, 0.2], [-0.2, -0.2], [-0.2, 0.2], [0.3, -0.2]]}),
         409, "robot.footprint.polygon"),
        (_profile(lidar={"pose": {"x": 0.5}}), 409, "robot.lidar.pose"),
        (_profile(wheels=4), 422, "wheels"),
        (_profile(limits={"max_linear_velocity": "fast"}), 422, "max_linear_velocity"),
    ],
)
def test_check_refuses_bad_profiles_naming_the_field(
    client: httpx.Client, doc: dict[str, Any], status: int, field: str
) -> None:
    r = client.post("/api/robot/check", json=doc)
    assert r.status_code == status
    assert field in r.json()["error"]["message"]


def test_cli_style_file_round_trip(tmp_path: Path, client: httpx.Client) -> None:
    shown = client.get("/api/robot").json()
    doc = {k: v for k, v in shown.items() if k not in ("inscribed_radius", "circumscribed_radius")}
    doc["footprint"] = {k: v for k, v in doc["footprint"].items() if v is not None}
    r = client.post("/api/robot/check", json=doc)
    assert r.status_code == 200 and r.json() == shown


def test_mapless_navigation_over_the_api_takes_odometry_frame_goals(client: httpx.Client) -> None:
    assert client.post("/api/navigation/mapless").status_code == 200
    status = client.get("/api/status").json()
    assert status["mode"] == "navigating" and status["map"] == "odom"
    r = client.post("/api/navigation/goal", json={"x": 5.0, "y": 4.5, "theta": 0.0})
    assert r.status_code == 202
    # Points belong to maps: none while mapless.
    assert client.post("/api/navigation/goal", json={"point": "lobby"}).status_code == 404
    assert client.post("/api/navigation/stop").status_code == 200
    assert client.get("/api/status").json()["mode"] == "free"
