"""Robot configuration (galileo-http-a §1.7, §3.7: E-28–E-30), the "after 5.0" key set plus
``navigation_speed`` (A-10) and the 6.6.8 keys.

The keys that mean a polynav setting are the runtime's settings, validated and persisted by the
runtime (:mod:`polynav.runtime.settings`): ``lf_linear_v`` and ``navigation_speed`` (the same
maximum speed), ``lf_theta_max``, ``robot_radius``, ``lf_xy_goal_tolerance``,
``lf_yaw_goal_tolerance``, ``lf_bar_distance_min`` (the stop distance), ``lf_forward_max_dist``
(the slow-down distance) and ``go_charge_percentage`` (the low-battery threshold). The others
belong to the vendor's own controller and services and are kept by the adapter in
``<data>/galileo/system_config.json`` as given; polynav's navigation does not read them.
``slam_type`` is ``lidar``: polynav localizes by lidar, and ``camera`` is refused. Setting
``wifi_ssid`` with ``wifi_password`` joins that network. A POST checks every key's type first
and changes nothing when one is wrong; unknown keys are ignored (A-10, A-11). ``maps`` is a
list of ``{"map": name, "path": name}`` objects.
"""

from __future__ import annotations

import json
import os
import tempfile
import threading
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from polynav.errors import InvalidRequest, StorageError
from polynav.protocols.galileo.context import Context
from polynav.protocols.galileo.endpoint import Reply, RouteList
from polynav.protocols.galileo.params import Params
from polynav.protocols.galileo.system_replies import OK
from polynav.runtime.settings import RobotSettings

ROUTES = RouteList()

#: Galileo key -> polynav setting.
SETTINGS = {
    "navigation_speed": "max_linear_velocity",
    "lf_linear_v": "max_linear_velocity",
    "lf_theta_max": "max_angular_velocity",
    "robot_radius": "robot_radius",
    "lf_xy_goal_tolerance": "xy_goal_tolerance",
    "lf_yaw_goal_tolerance": "yaw_goal_tolerance",
    "lf_bar_distance_min": "obstacle_stop_distance",
    "lf_forward_max_dist": "obstacle_slowdown_distance",
    "go_charge_percentage": "low_battery_percent",
}


@dataclass(frozen=True, slots=True)
class Key:
    """A key the adapter keeps: its type and default."""

    kind: type
    default: Any


#: The keys kept by the adapter, in the document's order.
KEPT: dict[str, Key] = {
    "default_map": Key(str, ""),
    "maps": Key(list, []),
    "auto_charge": Key(bool, False),
    "slam_type": Key(str, "lidar"),
    "lf_k2": Key(float, 1.0),
    "lf_kp": Key(float, 1.0),
    "lf_ki": Key(float, 0.0),
    "lf_kd": Key(float, 0.0),
    "lf_look_ahead_dist": Key(float, 0.5),
    "astar_path_changeability": Key(bool, True),
    "lf_move_direction": Key(int, 0),
    "use_smooth_switch_map": Key(float, 0.0),
    "lagrange_id": Key(str, ""),
    "weixin_id": Key(str, ""),
    "wifi_ssid": Key(str, ""),
    "wifi_password": Key(str, ""),
}

ORDER = ("default_map", "maps", "navigation_speed", "auto_charge", "slam_type", "lf_linear_v",
         "lf_theta_max", "lf_k2", "lf_kp", "lf_ki", "lf_kd", "lf_look_ahead_dist",
         "robot_radius", "lf_xy_goal_tolerance", "lf_yaw_goal_tolerance",
         "astar_path_changeability", "lf_bar_distance_min", "lf_forward_max_dist",
         "lf_move_direction", "go_charge_percentage", "use_smooth_switch_map", "lagrange_id",
         "weixin_id", "wifi_ssid", "wifi_password")


class KeptConfig:
    """The adapter's keys in a JSON file, written atomically."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self.lock = threading.Lock()

    def load(self) -> dict[str, Any]:
        values = {key: spec.default for key, spec in KEPT.items()}
        if self.path.exists():
            try:
                stored = json.loads(self.path.read_text("utf-8"))
            except ValueError as exc:
                raise StorageError(f"{self.path}: {exc}") from exc
            values.update({k: v for k, v in stored.items() if k in KEPT})
        return values

    def save(self, values: Mapping[str, Any]) -> None:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=".system_config.", dir=self.path.parent)
        try:
            with os.fdopen(fd, "w", encoding="utf-8") as f:
                json.dump(dict(values), f, ensure_ascii=False)
                f.flush()
                os.fsync(f.fileno())
            os.replace(tmp, self.path)
        except OSError as exc:
            Path(tmp).unlink(missing_ok=True)
            raise StorageError(f"{self.path}: {exc}") from exc


def _kept(ctx: Context) -> KeptConfig:
    return ctx.state("galileo.system_config",
                     lambda: KeptConfig(ctx.data_dir / "galileo" / "system_config.json"))


def _check(params: Params, key: str) -> Any:
    """``key``'s value in its type (a JSON value, or its text in the query string).

    Raises:
        InvalidRequest: the wrong type or value.
    """
    kind = KEPT[key].kind if key in KEPT else float
    if kind is bool:
        return params.boolean(key)
    if kind is int:
        return params.integer(key)
    if kind is float:
        return params.number(key)
    if kind is str:
        value = params.text(key)
        if key == "slam_type" and value != "lidar":
            raise InvalidRequest(key, "polynav navigates by lidar: only \"lidar\"")
        return value
    value = params.structure(key)
    if not isinstance(value, list) or not all(
        isinstance(m, dict) and isinstance(m.get("map"), str) and isinstance(m.get("path"), str)
        for m in value
    ):
        raise InvalidRequest(key, 'must be a list of {"map": name, "path": name}')
    return value


def config_body(ctx: Context) -> dict[str, Any]:
    settings = ctx.runtime.settings().to_dict()
    values = _kept(ctx).load()
    values.update({key: float(settings[name]) for key, name in SETTINGS.items()})
    return {key: values[key] for key in ORDER}


@ROUTES.get("/system/config")
def get_config(ctx: Context, params: Params) -> Reply:
    """E-28."""
    return config_body(ctx)


@ROUTES.post("/system/config")
def post_config(ctx: Context, params: Params) -> Reply:
    """E-29: change any of the keys; the whole config after."""
    checked = {k: _check(params, k) for k in params.values if k in SETTINGS or k in KEPT}
    changes: dict[str, object] = {}
    for key, value in checked.items():
        if key in SETTINGS:
            name = SETTINGS[key]
            if name in changes and changes[name] != value:
                raise InvalidRequest(key, f"contradicts another key for {name}")
            changes[name] = value
    # Validate the settings as a whole before anything is written.
    ctx.runtime.settings().apply(changes, ctx.runtime.profile)
    kept = {k: v for k, v in checked.items() if k in KEPT}
    if "wifi_ssid" in kept and kept["wifi_ssid"]:
        ctx.runtime.device.join_network(kept["wifi_ssid"],
                                        kept.get("wifi_password") or None)
    if changes:
        ctx.runtime.update_settings(changes)
    if kept:
        store = _kept(ctx)
        with store.lock:
            store.save({**store.load(), **kept})
    return config_body(ctx)


@ROUTES.delete("/system/config")
def delete_config(ctx: Context, params: Params) -> Reply:
    """E-30: put ``key`` back to its default."""
    key = params.text("key")
    if key in SETTINGS:
        name = SETTINGS[key]
        default = RobotSettings.defaults_for(ctx.runtime.profile).to_dict()[name]
        ctx.runtime.update_settings({name: default})
    elif key in KEPT:
        store = _kept(ctx)
        with store.lock:
            values = store.load()
            values[key] = KEPT[key].default
            store.save(values)
    else:
        raise InvalidRequest("key", f"no config key {key!r}")
    return {"status": OK}
