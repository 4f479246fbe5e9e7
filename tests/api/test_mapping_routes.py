"""/api/mapping over HTTP: start, the live map as grid JSON and PNG, save and stop as jobs (202
at once; 409 at once on a taken name unless overwrite), the job and the session in the status,
cancel; 409 in the wrong mode."""

from __future__ import annotations

import httpx

from tests.api.fakes import FakeRuntime


def test_mapping_start_watch_save_stop(client: httpx.Client, fake_runtime: FakeRuntime) -> None:
    assert client.get("/api/mapping/map").status_code == 409
    assert client.post("/api/mapping/explore").status_code == 409  # not mapping
    assert client.post("/api/mapping/start").status_code == 200
    assert client.post("/api/mapping/start").status_code == 409  # already mapping
    assert client.post("/api/mapping/explore").status_code == 200
    assert client.get("/api/status").json()["mode"] == "mapping"
    grid = client.get("/api/mapping/map").json()
    assert (grid["width"], grid["height"], grid["resolution"]) == (6, 4, 0.05)
    assert len(grid["data"]) == 24 and grid["data"][:6] == [100] * 6  # bottom row first
    png = client.get("/api/mapping/map.png")
    assert png.status_code == 200 and png.headers["content-type"] == "image/png"
    assert png.content.startswith(b"\x89PNG")
    mapping = client.get("/api/status").json()["mapping"]
    assert mapping["kind"] == "new" and mapping["map"] is None and mapping["job"] is None
    assert mapping["mapped_area_m2"] == 8 * 0.05 ** 2 + 6 * 0.05 ** 2  # the fake's known cells
    saved = client.post("/api/mapping/save", json={"name": "draft"})
    assert saved.status_code == 202, saved.text
    job = saved.json()
    assert (job["name"], job["kind"], job["state"], job["finished_at"]) == (
        "draft", "save", "saving", None)
    assert client.get("/api/status").json()["mapping"]["job"] == job
    # One save at a time; the map appears when the job has written it.
    assert client.post("/api/mapping/save", json={"name": "other"}).status_code == 409
    assert "draft" not in [m["name"] for m in client.get("/api/maps").json()]
    fake_runtime.advance(0.1)
    done = client.get(f"/api/mapping/jobs/{job['id']}").json()
    assert (done["state"], done["error"], done["finished_at"]) == ("saved", None, 0.1)
    assert client.get("/api/status").json()["mapping"]["job"] == done
    assert client.get("/api/status").json()["mode"] == "mapping"  # a save: mapping goes on
    assert "draft" in [m["name"] for m in client.get("/api/maps").json()]
    taken = client.post("/api/mapping/save", json={"name": "draft"})
    assert taken.status_code == 409 and "exists" in taken.json()["error"]["message"]
    again = client.post("/api/mapping/save", json={"name": "draft", "overwrite": True})
    assert again.status_code == 202 and again.json()["id"] != job["id"]
    fake_runtime.advance(0.1)
    assert client.post("/api/mapping/stop", json={"name": "floor1"}).status_code == 409
    stopped = client.post("/api/mapping/stop", json={"name": "hall"})
    assert stopped.status_code == 202 and stopped.json()["state"] == "saving"
    status = client.get("/api/status").json()
    assert status["mode"] == "busy" and status["mapping"]["job"]["kind"] == "stop"
    assert client.post("/api/mapping/stop", json={"name": "hall2"}).status_code == 409
    fake_runtime.advance(0.1)
    assert client.get(f"/api/mapping/jobs/{stopped.json()['id']}").json()["state"] == "saved"
    status = client.get("/api/status").json()
    assert status["mode"] == "free" and status["mapping"] is None
    assert "hall" in [m["name"] for m in client.get("/api/maps").json()]
    assert client.get("/api/mapping/jobs/99").status_code == 404


def test_mapping_cancel_and_bad_bodies(client: httpx.Client) -> None:
    assert client.post("/api/mapping/cancel").status_code == 409
    client.post("/api/mapping/start")
    assert client.post("/api/mapping/stop", json={}).status_code == 422
    assert client.post("/api/mapping/stop", json={"name": "a/b"}).status_code == 422
    bad = client.post("/api/mapping/save", json={"name": "x", "overwrite": "yes"})
    assert bad.status_code == 422
    assert client.post("/api/mapping/cancel").status_code == 200
    assert client.get("/api/status").json()["mode"] == "free"


def test_mapping_start_on_an_existing_map_updates_it(
    client: httpx.Client, fake_runtime: FakeRuntime
) -> None:
    assert client.post("/api/mapping/start", json={"point": "lobby"}).status_code == 422
    assert client.post("/api/mapping/start",
                       json={"map": "floor1", "point": "lobby", "x": 1.0, "y": 2.0}
                       ).status_code == 422
    assert client.post("/api/mapping/start", json={"map": "nowhere"}).status_code == 404
    assert fake_runtime.mapping_started is None
    assert client.post("/api/mapping/start",
                       json={"map": "floor1", "x": 1.0, "y": 2.0, "theta": 0.5}).status_code == 200
    started = fake_runtime.mapping_started
    assert started is not None and started[0] == "floor1" and started[1] is None
    assert started[2] is not None and (started[2].x, started[2].y, started[2].theta) == (
        1.0, 2.0, 0.5)
    assert client.get("/api/status").json()["mode"] == "mapping"
    assert client.post("/api/mapping/cancel").status_code == 200
    assert client.post("/api/mapping/start", json={}).status_code == 200  # a new map
    assert fake_runtime.mapping_started == (None, None, None)
