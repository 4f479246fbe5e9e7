"""Voice over real HTTP: speech, voice packages and records, aliases, greeting, volume
(galileo-http-a E-31–E-43, E-55, E-56)."""

from __future__ import annotations

import io
import wave
import zipfile
from pathlib import Path

from polynav.geometry import Pose2D
from polynav.robot.sim.devices.speaker import speech_duration, synthesize
from polynav.runtime.robot_runtime import RobotRuntime, RuntimeConfig
from polynav.store.site_store import SiteStore
from polynav.worlds.world import PersonRoute
from tests.protocols.galileo.conftest import Harness, serving
from tests.unit.robot.sim.ascii_world import ascii_world

COVERED = {
    "GET /api/v1/system/tts": "test_speech_plays_for_as_long_as_the_sentence_takes",
    "GET /api/v1/system/tts/playing": "test_speech_plays_for_as_long_as_the_sentence_takes",
    "GET /api/v1/system/tts/stop": "test_speech_plays_for_as_long_as_the_sentence_takes",
    "GET /api/v1/system/tts/records": "test_records_count_plays_and_packages_download",
    "POST /api/v1/system/tts/records": "test_a_package_of_audio_files_uploads_and_becomes_current",
    "PUT /api/v1/system/tts/records @1447-1465": "test_an_exported_package_imports_again",
    "PUT /api/v1/system/tts/records @1467-1488": "test_one_texts_audio_is_replaced_and_reset",
    "DELETE /api/v1/system/tts/records @1490-1504": "test_deleting_a_package_falls_back",
    "DELETE /api/v1/system/tts/records @1506-1522": "test_one_texts_audio_is_replaced_and_reset",
    "GET /api/v1/system/tts/alias": "test_aliases_replace_all_or_update_some",
    "POST /api/v1/system/tts/alias": "test_aliases_replace_all_or_update_some",
    "PUT /api/v1/system/tts/alias": "test_aliases_replace_all_or_update_some",
    "PUT /api/v1/system/greeting": "test_greeting_mode_welcomes_a_person_walking_past",
    "GET /api/v1/system/volume": "test_volume_is_kept_and_checked",
    "PUT /api/v1/system/volume": "test_volume_is_kept_and_checked",
}


def test_speech_plays_for_as_long_as_the_sentence_takes(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/tts/playing") == {"status": False}
    assert galileo.ok("GET", "/system/tts", params={"text": "欢迎光临"}) == {"status": "ok"}
    assert galileo.ok("GET", "/system/tts/playing") == {"status": True}
    galileo.runtime.advance(speech_duration("欢迎光临") + 0.1)
    assert galileo.ok("GET", "/system/tts/playing") == {"status": False}
    galileo.ok("GET", "/system/tts", params={"text": "Start charging"})
    assert galileo.ok("GET", "/system/tts/stop") == {"status": "ok"}
    assert galileo.ok("GET", "/system/tts/playing") == {"status": False}
    assert galileo.ok("GET", "/system/tts/stop") == {"status": "ok"}
    for params in ({}, {"text": "   "}):
        assert galileo.get("/system/tts", **params).status_code == 400
    assert galileo.ok("GET", "/system/tts/playing") == {"status": False}


def test_records_count_plays_and_packages_download(galileo: Harness) -> None:
    empty = galileo.ok("GET", "/system/tts/records")
    assert empty == {"packages": ["default"], "records": [], "current_package": "default"}
    for _ in range(2):
        galileo.ok("GET", "/system/tts", params={"text": "你好"})
        galileo.runtime.advance(1.5)
    body = galileo.ok("GET", "/system/tts/records")
    (record,) = body["records"]
    assert set(record) == {"text", "md5sum", "tags", "codenames", "i18n", "mode",
                           "last_active", "active_count"}
    assert record["text"] == "你好" and record["active_count"] == 2
    assert isinstance(record["last_active"], int) and len(record["md5sum"]) == 32
    audio = galileo.get("/system/tts/records", package_name="default", text="你好")
    assert audio.status_code == 200 and audio.headers["content-type"] == "audio/wav"
    with wave.open(io.BytesIO(audio.content)) as w:
        assert abs(w.getnframes() / w.getframerate() - speech_duration("你好")) < 1e-3
    archive = galileo.get("/system/tts/records", package_name="default")
    assert archive.headers["content-type"] == "application/zip"
    assert "records.json" in zipfile.ZipFile(io.BytesIO(archive.content)).namelist()
    assert galileo.get("/system/tts/records", package_name="nope").status_code == 404
    assert galileo.get("/system/tts/records", package_name="default",
                       text="never said").status_code == 404
    assert galileo.get("/system/tts/records", package_name="../x").status_code == 400


def test_a_package_of_audio_files_uploads_and_becomes_current(galileo: Harness) -> None:
    files = {"a": ("欢迎光临.wav", synthesize("x"), "audio/wav"),
             "b": ("再见.wav", synthesize("y"), "audio/wav")}
    reply = galileo.request("POST", "/system/tts/records", data={"package_name": "Jenny"},
                            files=files)
    assert reply.status_code == 200 and reply.json() == {"status": "ok"}
    body = galileo.ok("GET", "/system/tts/records")
    assert body["current_package"] == "Jenny" and "Jenny" in body["packages"]
    assert {r["text"] for r in body["records"]} == {"欢迎光临", "再见"}
    got = galileo.get("/system/tts/records", package_name="Jenny", text="再见")
    assert got.content == synthesize("y")
    bad = galileo.request("POST", "/system/tts/records", data={"package_name": "x"},
                          files={"a": ("notes.txt", b"text", "text/plain")})
    assert bad.status_code == 400
    none = galileo.request("POST", "/system/tts/records", data={"package_name": "x"})
    assert none.status_code == 400
    assert "x" not in galileo.ok("GET", "/system/tts/records")["packages"]


def test_an_exported_package_imports_again(galileo: Harness) -> None:
    galileo.ok("GET", "/system/tts", params={"text": "hello"})
    archive = galileo.get("/system/tts/records", package_name="default").content
    reply = galileo.request("PUT", "/system/tts/records", data={"package_name": "copy"},
                            files={"package_file": ("copy.zip", archive, "application/zip")})
    assert reply.status_code == 200, reply.text
    assert galileo.ok("GET", "/system/tts/records")["current_package"] == "copy"
    assert galileo.get("/system/tts/records", package_name="copy",
                       text="hello").content == synthesize("hello")
    broken = galileo.request("PUT", "/system/tts/records", data={"package_name": "b"},
                             files={"package_file": ("b.zip", b"not a zip", "application/zip")})
    assert broken.status_code == 400
    assert "b" not in galileo.ok("GET", "/system/tts/records")["packages"]


def test_one_texts_audio_is_replaced_and_reset(galileo: Harness) -> None:
    galileo.ok("GET", "/system/tts", params={"text": "hello"})
    reply = galileo.request("PUT", "/system/tts/records",
                            data={"package_name": "default", "text": "hello"},
                            files={"audio_file": ("mine.ogg", b"OggS-data", "audio/ogg")})
    assert reply.status_code == 200, reply.text
    got = galileo.get("/system/tts/records", package_name="default", text="hello")
    assert got.content == b"OggS-data" and got.headers["content-type"] == "audio/ogg"
    assert galileo.ok("DELETE", "/system/tts/records", params={"text": "hello"}) == {
        "status": "ok"}
    got = galileo.get("/system/tts/records", package_name="default", text="hello")
    assert got.content == synthesize("hello")
    assert galileo.delete("/system/tts/records", text="never said").status_code == 404
    missing = galileo.request("PUT", "/system/tts/records",
                              data={"package_name": "default", "text": "hello"})
    assert missing.status_code == 400


def test_deleting_a_package_falls_back(galileo: Harness) -> None:
    galileo.request("POST", "/system/tts/records", data={"package_name": "p"},
                    files={"a": ("hi.wav", synthesize("hi"), "audio/wav")})
    assert galileo.ok("DELETE", "/system/tts/records", params={"package_name": "p"}) == {
        "status": "ok"}
    body = galileo.ok("GET", "/system/tts/records")
    assert body["packages"] == ["default"] and body["current_package"] == "default"
    assert galileo.delete("/system/tts/records", package_name="p").status_code == 404
    assert galileo.delete("/system/tts/records", package_name="default").status_code == 409
    assert galileo.delete("/system/tts/records").status_code == 400


def test_aliases_replace_all_or_update_some(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/tts/alias") == {}
    assert galileo.ok("POST", "/system/tts/alias", json={"你好": "你好啊"}) == {"status": "ok"}
    assert galileo.ok("GET", "/system/tts/alias") == {"你好": "你好啊"}
    assert galileo.ok("PUT", "/system/tts/alias", json={"再见": "拜拜"}) == {
        "你好": "你好啊", "再见": "拜拜"}
    said = galileo.get("/system/tts/records", package_name="default", text="再见")
    assert said.content == synthesize("拜拜")  # the original sounds as its replacement
    assert galileo.post("/system/tts/alias", ["a", "b"]).status_code == 400
    assert galileo.post("/system/tts/alias", {"a": 1}).status_code == 400
    assert galileo.ok("GET", "/system/tts/alias") == {"你好": "你好啊", "再见": "拜拜"}


def test_greeting_mode_welcomes_a_person_walking_past(tmp_path: Path) -> None:
    room = "\n".join(["#" * 100] + ["#" + "." * 98 + "#"] * 38 + ["#" * 100])
    walker = PersonRoute(((9.0, 1.2), (1.0, 1.2)), speed=0.8, loop=False)
    world = ascii_world(room, start=Pose2D(5.0, 2.5, -1.5707963), people=(walker,))
    with SiteStore.open(tmp_path / "data", seed_world=world) as store:
        runtime = RobotRuntime.simulated(store, world, config=RuntimeConfig(people=True))
        with serving(runtime) as g:
            assert g.ok("PUT", "/system/greeting", json={"greeting": True}) == {
                "greeting": True}
            assert g.advance_until(lambda: runtime.peripherals.speaking(), timeout=15.0)
            assert runtime.peripherals.devices.speaker.text == "欢迎光临"  # type: ignore[attr-defined]
            records = g.ok("GET", "/system/tts/records")["records"]
            assert [r["text"] for r in records] == ["欢迎光临"]
            assert g.ok("PUT", "/system/greeting", json={"greeting": False}) == {
                "greeting": False}
            runtime.advance(30.0)  # walks past again: no greeting
            assert g.ok("GET", "/system/tts/records")["records"][0]["active_count"] == 1
            assert g.put("/system/greeting", {"greeting": "loud"}).status_code == 400


def test_volume_is_kept_and_checked(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/volume") == {"value": 60}
    assert galileo.ok("PUT", "/system/volume", json={"value": 35}) == {"status": "ok"}
    assert galileo.ok("GET", "/system/volume") == {"value": 35}
    for value in (101, -5, "loud", 12.5):
        assert galileo.put("/system/volume", {"value": value}).status_code == 400
    assert galileo.ok("GET", "/system/volume") == {"value": 35}
