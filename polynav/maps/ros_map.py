"""ROS ``map_server`` map files: a YAML of metadata beside a PGM or PNG picture of the grid.

A map made by any ROS tool loads here unchanged, and a saved polynav map opens in any ROS tool.
Semantics follow ``nav2_map_server`` ``map_io.cpp`` (the project's notes on it: "ROS
map_server yaml fields" in the workspace's ``shared/data/README.md``):

* the grey value ``v`` (0..255; colour is reduced by Pillow's ITU-R 601-2 luma) becomes an
  occupancy probability ``p = (255 - v) / 255``, or ``p = v / 255`` with ``negate``;
* **trinary** (the default): ``p >= occupied_thresh`` -> 100, ``p <= free_thresh`` -> 0, else -1;
* **scale**: the same two ends, and ``round(100 (p - free) / (occ - free))`` in between;
* **raw**: ``v`` itself (``negate`` is ignored, as in Nav2); values above 100 become -1;
* in trinary and scale a pixel with alpha < 255 is unknown;
* the picture's bottom row is grid row ``iy = 0``.

Saving writes the picture first and the YAML last, each through a temporary file in the target
folder that is flushed, fsynced and renamed over the old one (DESIGN §6), so a crash leaves the
old map or the new one, and a reader that finds the YAML finds its picture.
"""

from __future__ import annotations

import io
import logging
import math
import os
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import yaml
from PIL import Image, UnidentifiedImageError

from polynav import safe_yaml
from polynav.errors import InvalidRequest, StorageError
from polynav.geometry import Pose2D
from polynav.maps.errors import MapFormatError
from polynav.maps.map import FREE, OCCUPIED, UNKNOWN, Map, MapInfo

log = logging.getLogger(__name__)

MODES = ("trinary", "scale", "raw")
IMAGE_FORMATS = ("png", "pgm")

# Pixels map_saver writes in trinary mode, and the thresholds written beside them. The free
# threshold is ROS 1 map_saver's 0.196, not Nav2's 0.25: the unknown pixel 205 has
# p = 50 / 255 = 0.19608, which 0.25 would read back as free, losing every unknown cell.
TRINARY_OCCUPIED_PIXEL = 0
TRINARY_FREE_PIXEL = 254
TRINARY_UNKNOWN_PIXEL = 205
SAVE_OCCUPIED_THRESH = 0.65
SAVE_FREE_THRESH = 0.196

# Scale maps are saved with thresholds 1.0 / 0.0, so occupancy k is pixel round(2.55 (100 - k)).
# Reading it back gives round(100 (255 - v) / 255); the pixel rounding moves p by at most
# 0.5 / 255, i.e. 0.196 occupancy points, so every k in 0..100 comes back exactly.
_SCALE_PIXELS = np.floor(255.0 * (100.0 - np.arange(101)) / 100.0 + 0.5).astype(np.uint8)


def load_map(yaml_path: str | Path) -> Map:
    """Read a ROS ``map_server`` map: the YAML and the picture it names.

    Args:
        yaml_path: the YAML file; a relative ``image`` is resolved against its folder.

    Returns:
        The occupancy map: ``data[iy, ix]`` in 0..100 or -1, ``iy = 0`` at the bottom.

    Raises:
        MapFormatError: the YAML or the picture is missing or unreadable, or a field is missing
            or invalid (the error's ``field`` names it).
    """
    path = Path(yaml_path)
    meta = _read_yaml(path)
    image_name = meta.get("image")
    if not isinstance(image_name, str) or not image_name:
        raise MapFormatError("image", f"{path}: missing or not a file name")
    resolution = _positive_float(meta, "resolution")
    origin = _origin(meta)
    negate = _negate(meta)
    occupied_thresh = _unit_float(meta, "occupied_thresh")
    free_thresh = _unit_float(meta, "free_thresh")
    if not free_thresh < occupied_thresh:
        raise MapFormatError(
            "free_thresh",
            f"must be below occupied_thresh ({free_thresh} >= {occupied_thresh})",
        )
    mode = meta.get("mode", "trinary")
    if mode not in MODES:
        raise MapFormatError("mode", f"{mode!r} is not one of {', '.join(MODES)}")

    image_path = path.parent / image_name
    grey, alpha = _read_image(image_path)
    table = _value_table(mode, negate=negate, occupied=occupied_thresh, free=free_thresh)
    values = table[grey]
    if alpha is not None and mode != "raw":
        values[alpha < 255] = UNKNOWN
    height, width = values.shape
    info = MapInfo(resolution=resolution, width=width, height=height, origin=origin)
    log.info("loaded map %s: %dx%d cells at %g m, mode %s", path, width, height, resolution, mode)
    return Map(info, np.ascontiguousarray(values[::-1]))


def save_map(
    grid: Map,
    yaml_path: str | Path,
    *,
    image_format: str = "png",
    mode: str = "trinary",
) -> None:
    """Write ``grid`` as a ROS map: ``<stem>.png`` (or ``.pgm``) and the YAML, both atomically.

    * ``trinary`` writes what ROS ``map_saver`` writes: occupied (>= 65) black 0, free (<= 20)
      254, anything else (unknown, and partly occupied 21..64) 205, thresholds 0.65 / 0.196
      (ROS 1's; Nav2's 0.25 would read 205 back as free). It round-trips maps of 0 / 100 / -1
      exactly.
    * ``scale`` keeps every value 0..100 (thresholds 1.0 / 0.0) and writes unknown as a
      transparent pixel, so it round-trips any map exactly, but needs PNG when the map has
      unknown cells: PGM has no alpha channel.
    * ``raw`` writes the occupancy value itself as the grey level (unknown as 255).

    Args:
        grid: the map to save.
        yaml_path: the YAML file to write; the picture goes beside it with the same stem.
        image_format: ``"png"`` or ``"pgm"`` (binary P5).
        mode: ``"trinary"``, ``"scale"`` or ``"raw"``.

    Raises:
        InvalidRequest: unknown format or mode, or scale mode to PGM with unknown cells; nothing
            is written then.
        StorageError: the files could not be written (the old files are left as they were).
    """
    if image_format not in IMAGE_FORMATS:
        raise InvalidRequest("image_format", f"{image_format!r} is not one of png, pgm")
    if mode not in MODES:
        raise InvalidRequest("mode", f"{mode!r} is not one of {', '.join(MODES)}")
    path = Path(yaml_path)
    data = grid.data
    known = (data >= FREE) & (data <= OCCUPIED)
    if mode == "scale" and image_format == "pgm" and not known.all():
        raise InvalidRequest(
            "image_format",
            "scale mode writes unknown cells as transparent pixels and PGM has no alpha; "
            "use png, or mode trinary or raw",
        )
    picture = _picture(data, known, mode)
    if mode == "scale":
        occupied_thresh, free_thresh = 1.0, 0.0
    else:
        occupied_thresh, free_thresh = SAVE_OCCUPIED_THRESH, SAVE_FREE_THRESH
    image_path = path.with_name(f"{path.stem}.{image_format}")
    buf = io.BytesIO()
    picture.save(buf, format="PNG" if image_format == "png" else "PPM")
    origin = grid.info.origin
    meta: dict[str, Any] = {
        "image": image_path.name,
        "mode": mode,
        "resolution": float(grid.info.resolution),
        "origin": [float(origin.x), float(origin.y), float(origin.theta)],
        "negate": 0,
        "occupied_thresh": occupied_thresh,
        "free_thresh": free_thresh,
    }
    text = yaml.safe_dump(meta, sort_keys=False, default_flow_style=None)
    # The picture first: a YAML on disk must never name a picture that is not there yet.
    _write_atomic(image_path, buf.getvalue())
    _write_atomic(path, text.encode("utf-8"))
    log.info("saved map %s (%s, %s)", path, image_format, mode)


def _read_yaml(path: Path) -> dict[str, Any]:
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise MapFormatError("yaml", f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise MapFormatError("yaml", f"{path}: cannot read: {exc}") from exc
    try:
        meta = safe_yaml.load(text)
    except yaml.YAMLError as exc:
        raise MapFormatError("yaml", f"{path}: not valid YAML: {exc}") from exc
    if not isinstance(meta, dict):
        raise MapFormatError("yaml", f"{path}: expected a mapping of map fields")
    return meta


def _number(meta: dict[str, Any], key: str) -> float:
    if key not in meta:
        raise MapFormatError(key, "missing")
    return _as_number(key, meta[key])


def _as_number(key: str, value: object) -> float:
    # bool is an int subclass, and "resolution: yes" is surely a mistake.
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise MapFormatError(key, f"expected a number, got {value!r}")
    if not math.isfinite(value):
        raise MapFormatError(key, f"must be finite, got {value!r}")
    return float(value)


def _positive_float(meta: dict[str, Any], key: str) -> float:
    value = _number(meta, key)
    if value <= 0.0:
        raise MapFormatError(key, f"must be > 0, got {value}")
    return value


def _unit_float(meta: dict[str, Any], key: str) -> float:
    value = _number(meta, key)
    if not 0.0 <= value <= 1.0:
        raise MapFormatError(key, f"must be within [0, 1], got {value}")
    return value


def _origin(meta: dict[str, Any]) -> Pose2D:
    value = meta.get("origin")
    if not isinstance(value, list) or len(value) != 3:
        raise MapFormatError("origin", f"expected [x, y, yaw], got {value!r}")
    x, y, yaw = (_as_number("origin", v) for v in value)
    return Pose2D(x, y, yaw)


def _negate(meta: dict[str, Any]) -> bool:
    if "negate" not in meta:
        raise MapFormatError("negate", "missing")
    value = meta["negate"]
    if value in (0, 1) and isinstance(value, int):  # includes False / True
        return bool(value)
    raise MapFormatError("negate", f"expected 0 or 1, got {value!r}")


def _read_image(path: Path) -> tuple[npt.NDArray[np.uint8], npt.NDArray[np.uint8] | None]:
    """Grey levels and alpha (``None`` if opaque by format), rows top first as in the file."""
    try:
        with Image.open(path) as img:
            img.load()
            return _grey_alpha(img)
    except FileNotFoundError:
        raise MapFormatError("image", f"{path}: no such file") from None
    except (UnidentifiedImageError, OSError, SyntaxError, ValueError) as exc:
        # Pillow reports truncated or malformed files as OSError / SyntaxError / ValueError.
        raise MapFormatError("image", f"{path}: cannot read picture: {exc}") from exc


def _grey_alpha(img: Image.Image) -> tuple[npt.NDArray[np.uint8], npt.NDArray[np.uint8] | None]:
    mode = img.mode
    if mode in ("I", "I;16", "I;16B", "I;16L", "I;16N"):
        # 16-bit grey (PNG or PGM with maxval > 255): scale to 8 bits like an image library does.
        wide = np.asarray(img).astype(np.int64)
        return ((wide * 255 + 32767) // 65535).clip(0, 255).astype(np.uint8), None
    if "transparency" in img.info or mode in ("P", "PA", "LA", "La", "RGBa"):
        img = img.convert("RGBA")
        mode = "RGBA"
    if mode == "RGBA":
        alpha = np.asarray(img.getchannel("A"), dtype=np.uint8)
        return np.asarray(img.convert("L"), dtype=np.uint8), alpha
    if mode != "L":
        img = img.convert("L")
    return np.asarray(img, dtype=np.uint8), None


def _value_table(mode: str, *, negate: bool, occupied: float, free: float) -> npt.NDArray[np.int8]:
    """Occupancy value for each grey level 0..255."""
    v = np.arange(256, dtype=np.float64)
    if mode == "raw":
        return np.where(v <= OCCUPIED, v, UNKNOWN).astype(np.int8)
    p = v / 255.0 if negate else (255.0 - v) / 255.0
    table = np.full(256, UNKNOWN, dtype=np.int8)
    if mode == "scale":
        middle = np.rint(100.0 * (p - free) / (occupied - free))
        table[:] = middle.clip(FREE, OCCUPIED).astype(np.int8)
    table[p <= free] = FREE
    table[p >= occupied] = OCCUPIED
    return table


def png_bytes(grid: Map) -> bytes:
    """``grid`` as the PNG ``map_saver`` would write (trinary, top row first), in memory: for a
    live map served while it is being built."""
    data = grid.data
    buf = io.BytesIO()
    _picture(data, (data >= FREE) & (data <= OCCUPIED), "trinary").save(buf, format="PNG")
    return buf.getvalue()


def _picture(data: npt.NDArray[np.int8], known: npt.NDArray[np.bool_], mode: str) -> Image.Image:
    """The image to save, top row first (the grid is flipped: row iy = 0 is the bottom)."""
    values = data.astype(np.int64)
    if mode == "trinary":
        grey = np.full(data.shape, TRINARY_UNKNOWN_PIXEL, dtype=np.uint8)
        grey[known & (values <= round(SAVE_FREE_THRESH * 100))] = TRINARY_FREE_PIXEL
        grey[known & (values >= round(SAVE_OCCUPIED_THRESH * 100))] = TRINARY_OCCUPIED_PIXEL
        return Image.fromarray(np.ascontiguousarray(grey[::-1]))
    if mode == "raw":
        grey = np.where(known, values, 255).astype(np.uint8)
        return Image.fromarray(np.ascontiguousarray(grey[::-1]))
    grey = _SCALE_PIXELS[np.where(known, values, 0)]
    if known.all():
        return Image.fromarray(np.ascontiguousarray(grey[::-1]))
    # Unknown: transparent mid-grey, as map_saver writes it.
    grey[~known] = 128
    alpha = np.where(known, 255, 0).astype(np.uint8)
    la = np.stack([grey[::-1], alpha[::-1]], axis=-1)
    return Image.fromarray(np.ascontiguousarray(la))


def _write_atomic(path: Path, payload: bytes) -> None:
    """Replace ``path`` with ``payload``: readers see the old bytes or the new, never half."""
    folder = path.parent
    try:
        fd, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    except OSError as exc:
        raise StorageError(f"cannot write {path}: {exc}") from exc
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(payload)
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp_name, path)
    except OSError as exc:
        Path(tmp_name).unlink(missing_ok=True)
        raise StorageError(f"cannot write {path}: {exc}") from exc
    _fsync_folder(folder)


def _fsync_folder(folder: Path) -> None:
    """Make the rename itself durable (POSIX); a no-op where folders cannot be opened."""
    if not hasattr(os, "O_DIRECTORY"):
        return
    fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)
