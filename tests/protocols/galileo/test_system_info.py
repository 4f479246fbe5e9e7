"""System information, remote control, power, self-test, topics and parameters over real HTTP
(galileo-http-a E-03, E-05–E-08, E-22, E-23, E-44, E-49, E-72, E-73, E-75, E-76)."""

from __future__ import annotations

from tests.protocols.galileo.conftest import Harness

COVERED = {
    "GET /api/v1/system/info": "test_info_reports_battery_rates_estop_and_identity",
    "GET /api/v1/system/log": "test_the_log_lists_runtime_events",
    "GET /api/v1/system/speed": "test_remote_control_moves_the_robot_and_speed_reads_it",
    "PUT /api/v1/system/speed": "test_remote_control_moves_the_robot_and_speed_reads_it",
    "GET /api/v1/system/shutdown": "test_shutdown_powers_the_robot_off_after_its_notice",
    "GET /api/v1/system/restart_robot": "test_restart_robot_powers_off_and_on_again",
    "GET /api/v1/system/restart_novnc": "test_restart_novnc_answers_true",
    "GET /api/v1/system/schedule_manager": "test_schedule_manager_is_an_empty_list",
    "GET /api/v1/system/self_test": "test_self_test_reports_every_module_ok_after_the_checks",
    "GET /api/v1/system/check_cert": "test_check_cert_is_ok",
    "GET /api/v1/system/topic": "test_topics_serve_status_and_sensor_data",
    "GET /api/v1/system/ros_params": "test_ros_params_store_any_json_value",
    "PUT /api/v1/system/ros_params": "test_ros_params_store_any_json_value",
}


def test_info_reports_battery_rates_estop_and_identity(galileo: Harness) -> None:
    body = galileo.ok("GET", "/system/info")
    types = {"battery": int, "camera_rgb": int, "camera_depth": int, "odom": int, "imu": int,
             "camera_processed": int, "driver_port": bool, "info": dict, "charge": bool,
             "loop": bool, "slam_type": str}
    assert set(body) == set(types)
    for name, kind in types.items():
        assert isinstance(body[name], kind), name
    assert body["battery"] == round(galileo.runtime.status().battery_percent)
    assert body["odom"] == 50 and body["imu"] == 50 and body["slam_type"] == "lidar"
    info = body["info"]
    assert set(info) == {"version", "code_name", "id", "mac", "port"}
    assert len(info["id"]) == 76 and info["port"] == galileo.server.config.port
    assert body["driver_port"] is False
    galileo.runtime.simulation.press_estop()
    galileo.runtime.advance(0.2)
    assert galileo.ok("GET", "/system/info")["driver_port"] is True


def test_the_log_lists_runtime_events(galileo: Harness) -> None:
    first = galileo.ok("GET", "/system/log")["log"]
    assert isinstance(first, str)
    galileo.runtime.start_navigation("floor1")
    galileo.runtime.advance(0.2)
    text = galileo.ok("GET", "/system/log")["log"]
    assert "mode_changed" in text and "navigating" in text


def test_remote_control_moves_the_robot_and_speed_reads_it(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/speed") == {"speed_x": 0.0, "speed_y": 0.0,
                                                  "speed_angle": 0.0}
    start = galileo.runtime.simulation.true_pose
    for _ in range(10):  # a client sends at 5 Hz
        assert galileo.ok("PUT", "/system/speed",
                          json={"speed_x": 0.3, "speed_y": 0, "speed_angle": 0.0}) == {
            "result": True}
        galileo.runtime.advance(0.2)
    speed = galileo.ok("GET", "/system/speed")
    assert abs(speed["speed_x"] - 0.3) < 0.02 and speed["speed_y"] == 0.0
    moved = galileo.runtime.simulation.true_pose.distance_to(start)
    assert 0.4 < moved < 0.7
    galileo.runtime.advance(1.0)  # no more commands: the dead-man stops it
    assert galileo.ok("GET", "/system/speed")["speed_x"] == 0.0
    # Bad input: refused with result false, nothing moves.
    for body in ({"speed_x": "fast", "speed_angle": 0}, {"speed_angle": 0.1},
                 {"speed_x": 0.1, "speed_y": 0.2, "speed_angle": 0}):
        reply = galileo.ok("PUT", "/system/speed", json=body)
        assert reply["result"] is False and reply["description"]
    galileo.runtime.advance(0.5)
    assert galileo.ok("GET", "/system/speed")["speed_x"] == 0.0


def test_shutdown_powers_the_robot_off_after_its_notice(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/shutdown") == {"result": True}
    again = galileo.ok("GET", "/system/shutdown")
    assert again["result"] is False and "under way" in again["description"]
    galileo.runtime.advance(10.5)
    assert not galileo.runtime.powered


def test_restart_robot_powers_off_and_on_again(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/restart_robot") == {"result": True}
    galileo.runtime.advance(10.5)
    assert not galileo.runtime.powered
    galileo.runtime.advance(5.0)
    assert galileo.runtime.powered


def test_restart_novnc_answers_true(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/restart_novnc") == {"result": True}


def test_schedule_manager_is_an_empty_list(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/schedule_manager") == []


def test_self_test_reports_every_module_ok_after_the_checks(galileo: Harness) -> None:
    galileo.runtime.advance(3.0)  # the first self-check runs 2 s after start
    body = galileo.ok("GET", "/system/self_test")
    assert body == {"motor_driver": True, "camera": True, "charge": True, "lidar": True,
                    "bluetooth": True, "battery": True}
    galileo.runtime.simulation.inject_fault("laser_slot_object")
    galileo.runtime.advance(10.5)
    broken = galileo.ok("GET", "/system/self_test")
    assert broken["lidar"] is False and broken["camera"] is False
    assert broken["motor_driver"] is True


def test_check_cert_is_ok(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/check_cert") == {"status": "ok"}


def test_topics_serve_status_and_sensor_data(galileo: Harness) -> None:
    status = galileo.ok("GET", "/system/topic", params={"topic_name": "/galileo/status"})
    assert "navStatus" in status and "header" in status
    env = galileo.ok("GET", "/system/topic",
                     params={"topic_name": "/bw_env_sensors/EnvSensorData"})
    assert set(env) == {"temperature", "rh", "smoke", "pm1_0", "pm2_5", "pm10", "lel", "noise"}
    assert all(isinstance(v, float) for v in env.values())
    air = galileo.ok("GET", "/system/topic",
                     params={"topic_name": "/bw_env_sensors/AirSensorData"})
    assert set(air) == {"temperature", "rh", "co2", "illuminance"}
    galileo.runtime.advance(60.0)
    later = galileo.ok("GET", "/system/topic",
                       params={"topic_name": "/bw_env_sensors/EnvSensorData"})
    assert later != env  # the readings drift on the clock
    missing = galileo.get("/system/topic", topic_name="/no/such")
    assert missing.status_code == 404 and missing.json()["status"] == "error"
    assert galileo.get("/system/topic").status_code == 400


def test_ros_params_store_any_json_value(galileo: Harness) -> None:
    assert galileo.ok("GET", "/system/ros_params", params={"param": "/foo"}) == {"/foo": None}
    value = {"a": [1, 2.5, "x"], "b": True}
    assert galileo.ok("PUT", "/system/ros_params", json={"param": "/foo", "value": value}) == {
        "/foo": value}
    assert galileo.ok("GET", "/system/ros_params", params={"param": "/foo"}) == {"/foo": value}
    stored = galileo.server.ctx.data_dir / "galileo" / "ros_params.json"
    assert stored.is_file()
    assert galileo.put("/system/ros_params", {"param": "/foo"}).status_code == 400
    assert galileo.put("/system/ros_params", {"value": 1}).status_code == 400
    assert galileo.ok("GET", "/system/ros_params", params={"param": "/foo"}) == {"/foo": value}
