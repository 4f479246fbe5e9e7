"""IO over real HTTP: the base's outputs, the expansion board, the voice module's IO, PWM and
servo (galileo-http-a E-24–E-27, E-45–E-48)."""

from __future__ import annotations

import pytest

from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/system/io": "test_base_outputs_start_unset_and_keep_their_level",
    "POST /api/v1/system/io": "test_base_outputs_start_unset_and_keep_their_level",
    "GET /api/v1/system/bw_io": "test_expansion_board_outputs_and_wired_inputs",
    "PUT /api/v1/system/bw_io": "test_expansion_board_outputs_and_wired_inputs",
    "GET /api/v1/system/asr/io": "test_voice_module_inputs_and_outputs",
    "PUT /api/v1/system/asr/io": "test_voice_module_inputs_and_outputs",
    "GET /api/v1/system/asr/pwm": "test_voice_module_pwm_and_servo",
    "GET /api/v1/system/asr/servo": "test_voice_module_pwm_and_servo",
}


def test_base_outputs_start_unset_and_keep_their_level(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/io") == {"status": "ok", "out1": "-1", "out2": "-1",
                                               "out3": "-1"}
    assert galileo.ok("POST", "/system/io", json={"level": "1", "port": "2"}) == {
        "status": "ok"}
    assert galileo.ok("POST", "/system/io", json={"level": 0, "port": 3}) == {"status": "ok"}
    assert galileo.ok("GET", "/system/io") == {"status": "ok", "out1": "-1", "out2": "1",
                                               "out3": "0"}
    for body in ({"level": "1", "port": "4"}, {"level": "2", "port": "1"}, {"port": "1"},
                 {"level": "high", "port": "1"}):
        reply = galileo.post("/system/io", body)
        assert reply.status_code == 400 and reply.json()["status"] == "error"
    assert galileo.ok("GET", "/system/io")["out1"] == "-1"


def test_expansion_board_outputs_and_wired_inputs(galileo: Harness) -> None:
    body = galileo.ok("GET", "/system/bw_io")
    assert body == {"in": {str(k): 0 for k in range(8)}, "out": {str(k): 0 for k in range(8)}}
    assert galileo.ok("PUT", "/system/bw_io", json={"level": 1, "port": 7}) == {"status": "ok"}
    galileo.runtime.peripherals.devices.expansion_io.set_input(2, 1)  # type: ignore[attr-defined]
    body = galileo.ok("GET", "/system/bw_io")
    assert body["out"]["7"] == 1 and body["in"]["2"] == 1
    assert all(isinstance(v, int) for v in body["out"].values())
    assert galileo.put("/system/bw_io", {"level": 1, "port": 8}).status_code == 400
    assert galileo.put("/system/bw_io", {"level": 1}).status_code == 400


def test_voice_module_inputs_and_outputs(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/asr/io") == {"4": False, "5": False, "6": False,
                                                   "7": False}
    galileo.runtime.peripherals.devices.voice_io.set_input(6, 1)  # type: ignore[attr-defined]
    assert galileo.ok("GET", "/system/asr/io")["6"] is True
    assert galileo.ok("PUT", "/system/asr/io", json={"0": True, "3": True}) == {
        "status": "ok"}
    outputs, _ = galileo.runtime.peripherals.io_state("voice_io")
    assert outputs == [1, None, None, 1]
    for body in ({"1": True, "4": True}, {"x": True}, {}, {"1": "perhaps"}):
        reply = galileo.request("PUT", "/system/asr/io", json=body)
        assert reply.status_code == 400, body
    assert galileo.runtime.peripherals.io_state("voice_io")[0] == [1, None, None, 1]


@pytest.mark.parametrize(("path", "params", "field"), [
    ("/system/asr/pwm", {"port": 9, "freq": 100, "percent": 50}, "port"),
    ("/system/asr/pwm", {"port": 1, "freq": 100, "percent": 150}, "percent"),
    ("/system/asr/servo", {"port": 1, "angle": 270}, "angle"),
    ("/system/asr/servo", {"port": 1}, "angle"),
])
def test_bad_pwm_and_servo_requests_are_refused(galileo: Harness, path: str,
                                                params: dict[str, int], field: str) -> None:
    reply = galileo.get(path, **params)
    assert reply.status_code == 400 and field in reply.json()["description"]
    assert galileo.runtime.peripherals.devices.voice_io.pwm == {}  # type: ignore[attr-defined]


def test_voice_module_pwm_and_servo(galileo: Harness) -> None:
    voice_io = galileo.runtime.peripherals.devices.voice_io
    assert galileo.ok("GET", "/system/asr/pwm", params={"port": 1, "freq": 1000,
                                                         "percent": 25}) == {"status": "ok"}
    assert voice_io.pwm == {1: (1000, 25)}  # type: ignore[attr-defined]
    assert galileo.ok("GET", "/system/asr/servo", params={"port": 2, "angle": 90}) == {
        "status": "ok"}
    assert voice_io.servo == {2: 90}  # type: ignore[attr-defined]
