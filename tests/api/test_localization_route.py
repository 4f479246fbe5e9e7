"""POST /api/localization/relocalize over HTTP: the pose and score, or a 409 that says why."""

from __future__ import annotations

import httpx

from tests.api.fakes import FakeRuntime


def test_relocalize_answers_pose_and_score_while_navigating(
    client: httpx.Client, fake_runtime: FakeRuntime
) -> None:
    refused = client.post("/api/localization/relocalize")
    assert refused.status_code == 409 and refused.json()["error"]["code"] == "conflict"
    assert client.post("/api/navigation/start", json={"map": "floor1", "x": 3.0, "y": 4.0,
                                                      "theta": 0.5}).status_code == 200
    answer = client.post("/api/localization/relocalize")
    assert answer.status_code == 200, answer.text
    assert answer.json() == {"x": 3.0, "y": 4.0, "theta": 0.5, "score": 0.93}


def test_a_scan_that_fits_several_places_is_409_not_localized(
    client: httpx.Client, fake_runtime: FakeRuntime
) -> None:
    client.post("/api/navigation/start", json={"map": "floor1", "x": 3.0, "y": 4.0})
    fake_runtime.lost_in_a_hall = True
    answer = client.post("/api/localization/relocalize")
    assert answer.status_code == 409
    error = answer.json()["error"]
    assert error["code"] == "not_localized" and "ambiguous" in error["message"]
