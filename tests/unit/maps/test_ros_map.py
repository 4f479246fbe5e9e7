from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest
import yaml
from PIL import Image

from polynav.errors import InvalidRequest, PolynavError, StorageError
from polynav.geometry import Pose2D
from polynav.maps.ascii import map_from_ascii
from polynav.maps.errors import MapFormatError
from polynav.maps.map import Map, MapInfo
from polynav.maps.ros_map import load_map, save_map

# Grey levels of a 4x2 test picture, top row first as stored in the file.
PIXELS = [[0, 100, 128, 205], [230, 254, 255, 50]]

SHARED_MAPS = [
    "nav2/maps/depot.yaml",
    "nav2/maps/depot_keepout.yaml",
    "nav2/maps/depot_speed.yaml",
    "nav2/maps/empty_room.yaml",
    "nav2/maps/keepout_mask.yaml",
    "nav2/maps/map.yaml",
    "nav2/maps/map_circular.yaml",
    "nav2/maps/speed_mask.yaml",
    "nav2/maps/tb3_sandbox.yaml",
    "nav2/maps/warehouse.yaml",
    "nav2/maps/warehouse_keepout.yaml",
    "nav2/maps/warehouse_speed.yaml",
    "nav2/planner_benchmark/100by100_10.yaml",
    "nav2/planner_benchmark/100by100_15.yaml",
    "nav2/planner_benchmark/100by100_20.yaml",
]


def _write_yaml(folder: Path, image_name: str, **fields: object) -> Path:
    meta: dict[str, object] = {
        "image": image_name,
        "resolution": 0.1,
        "origin": [0.0, 0.0, 0.0],
        "negate": 0,
        "occupied_thresh": 0.65,
        "free_thresh": 0.196,
    }
    meta.update(fields)
    meta = {k: v for k, v in meta.items() if v is not None}
    path = folder / "map.yaml"
    path.write_text(yaml.safe_dump(meta))
    return path


def _write_p5(path: Path, rows: list[list[int]]) -> None:
    header = f"P5\n# CREATOR: test\n{len(rows[0])} {len(rows)}\n255\n".encode()
    path.write_bytes(header + bytes(v for row in rows for v in row))


def _assert_same_map(a: Map, b: Map) -> None:
    assert a.info == b.info
    assert a.data.dtype == b.data.dtype == np.int8
    np.testing.assert_array_equal(a.data, b.data)


# --- round trips on the shared ROS maps ------------------------------------------------------


def test_every_shared_map_is_listed(data_dir: Path) -> None:
    found = sorted(
        str(p.relative_to(data_dir))
        for folder in ("nav2/maps", "nav2/planner_benchmark")
        for p in (data_dir / folder).glob("*.yaml")
    )
    assert found == sorted(SHARED_MAPS)


@pytest.mark.parametrize("name", SHARED_MAPS)
def test_shared_map_round_trips_through_save_and_load(
    data_dir: Path, tmp_path: Path, name: str
) -> None:
    source = data_dir / name
    original = load_map(source)
    mode = yaml.safe_load(source.read_text()).get("mode", "trinary")
    variants = sorted({("png", mode), ("pgm", mode), ("png", "scale"), ("pgm", "raw")})
    for image_format, save_mode in variants:
        target = tmp_path / f"{image_format}_{save_mode}" / "copy.yaml"
        target.parent.mkdir()
        save_map(original, target, image_format=image_format, mode=save_mode)
        _assert_same_map(load_map(target), original)


def test_shared_trinary_map_loads_its_known_size_and_values(data_dir: Path) -> None:
    grid = load_map(data_dir / "nav2/maps/warehouse.yaml")
    assert grid.info == MapInfo(
        resolution=0.03, width=1006, height=1674, origin=Pose2D(-15.1, -25.0, 0.0)
    )
    assert set(np.unique(grid.data).tolist()) == {-1, 0, 100}


def test_negated_benchmark_map_reads_white_as_occupied(data_dir: Path) -> None:
    source = data_dir / "nav2/planner_benchmark/100by100_10.yaml"
    grid = load_map(source)
    with Image.open(source.with_suffix(".png")) as img:
        pixels = np.asarray(img)
    np.testing.assert_array_equal(grid.data[::-1] == 100, pixels == 255)
    np.testing.assert_array_equal(grid.data[::-1] == 0, pixels == 0)


# --- exact cell values on hand-made pictures -------------------------------------------------


@pytest.mark.parametrize(
    ("fields", "expected_top", "expected_bottom"),
    [
        ({}, [100, -1, -1, -1], [0, 0, 0, 100]),
        ({"mode": "trinary", "negate": 1}, [0, -1, -1, 100], [100, 100, 100, -1]),
        ({"negate": True}, [0, -1, -1, 100], [100, 100, 100, -1]),
        ({"mode": "scale"}, [100, 91, 67, 0], [0, 0, 0, 100]),
        (
            {"mode": "scale", "occupied_thresh": 1.0, "free_thresh": 0.0},
            [100, 61, 50, 20],
            [10, 0, 0, 80],
        ),
        ({"mode": "raw"}, [0, 100, -1, -1], [-1, -1, -1, 50]),
        ({"mode": "raw", "negate": 1}, [0, 100, -1, -1], [-1, -1, -1, 50]),
    ],
    ids=["trinary-default", "negate", "negate-bool", "scale", "scale-full", "raw", "raw-negate"],
)
def test_pgm_pixels_become_the_documented_occupancy_values(
    tmp_path: Path, fields: dict[str, object], expected_top: list[int], expected_bottom: list[int]
) -> None:
    _write_p5(tmp_path / "map.pgm", PIXELS)
    grid = load_map(_write_yaml(tmp_path, "map.pgm", **fields))
    assert grid.info.width == 4 and grid.info.height == 2
    # Row iy = 0 is the bottom row of the picture.
    assert grid.data.tolist() == [expected_bottom, expected_top]


def test_plain_p2_pgm_loads_like_binary_p5(tmp_path: Path) -> None:
    body = "\n".join(" ".join(str(v) for v in row) for row in PIXELS)
    (tmp_path / "map.pgm").write_text(f"P2\n4 2\n255\n{body}\n")
    grid = load_map(_write_yaml(tmp_path, "map.pgm"))
    assert grid.data.tolist() == [[0, 0, 0, 100], [100, -1, -1, -1]]


def test_png_grey_loads_like_pgm(tmp_path: Path) -> None:
    Image.fromarray(np.array(PIXELS, dtype=np.uint8)).save(tmp_path / "map.png")
    grid = load_map(_write_yaml(tmp_path, "map.png"))
    assert grid.data.tolist() == [[0, 0, 0, 100], [100, -1, -1, -1]]


def test_colour_png_is_reduced_to_grey_by_luma(tmp_path: Path) -> None:
    # Luma: red -> 76 (p = 0.70, occupied), green -> 150 (p = 0.41, unknown), white free.
    rgb = np.array([[[255, 0, 0], [0, 255, 0], [255, 255, 255]]], dtype=np.uint8)
    Image.fromarray(rgb).save(tmp_path / "map.png")
    assert load_map(_write_yaml(tmp_path, "map.png")).data.tolist() == [[100, -1, 0]]


def test_palette_png_is_reduced_to_grey(tmp_path: Path) -> None:
    img = Image.fromarray(np.array([[0, 255, 205]], dtype=np.uint8)).convert("P")
    img.save(tmp_path / "map.png")
    assert load_map(_write_yaml(tmp_path, "map.png")).data.tolist() == [[100, 0, -1]]


@pytest.mark.parametrize(
    ("mode", "expected"),
    [("trinary", [100, -1, 0, -1]), ("scale", [100, -1, 0, -1]), ("raw", [0, 0, -1, -1])],
)
def test_transparent_pixels_are_unknown_except_in_raw_mode(
    tmp_path: Path, mode: str, expected: list[int]
) -> None:
    grey = np.array([[0, 0, 255, 255]], dtype=np.uint8)
    alpha = np.array([[255, 0, 255, 254]], dtype=np.uint8)
    Image.fromarray(np.stack([grey, alpha], axis=-1)).save(tmp_path / "map.png")
    grid = load_map(_write_yaml(tmp_path, "map.png", mode=mode))
    assert grid.data.tolist() == [expected]


def test_sixteen_bit_png_is_scaled_to_eight_bits(tmp_path: Path) -> None:
    Image.fromarray(np.array([[0, 65535, 205 * 257]], dtype=np.uint16)).save(tmp_path / "map.png")
    assert load_map(_write_yaml(tmp_path, "map.png")).data.tolist() == [[100, 0, -1]]


def test_origin_resolution_and_yaw_are_read_from_the_yaml(tmp_path: Path) -> None:
    _write_p5(tmp_path / "map.pgm", PIXELS)
    grid = load_map(_write_yaml(tmp_path, "map.pgm", resolution=0.025, origin=[1.5, -2, 0.5]))
    assert grid.info == MapInfo(resolution=0.025, width=4, height=2, origin=Pose2D(1.5, -2.0, 0.5))


def test_image_path_is_relative_to_the_yaml_folder(tmp_path: Path) -> None:
    (tmp_path / "pics").mkdir()
    _write_p5(tmp_path / "pics" / "floor.pgm", PIXELS)
    yaml_path = _write_yaml(tmp_path, "pics/floor.pgm")
    other = tmp_path / "elsewhere"
    other.mkdir()
    cwd = os.getcwd()
    os.chdir(other)
    try:
        assert load_map(yaml_path).info.width == 4
    finally:
        os.chdir(cwd)


def test_absolute_image_path_is_used_as_is(tmp_path: Path) -> None:
    _write_p5(tmp_path / "map.pgm", PIXELS)
    folder = tmp_path / "yamls"
    folder.mkdir()
    assert load_map(_write_yaml(folder, str(tmp_path / "map.pgm"))).info.height == 2


def test_extra_yaml_keys_are_ignored(tmp_path: Path) -> None:
    _write_p5(tmp_path / "map.pgm", PIXELS)
    assert load_map(_write_yaml(tmp_path, "map.pgm", map_type="occupancy")).info.width == 4


# --- bad input -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("fields", "field"),
    [
        ({"image": None}, "image"),
        ({"image": 3}, "image"),
        ({"resolution": None}, "resolution"),
        ({"resolution": 0}, "resolution"),
        ({"resolution": "fine"}, "resolution"),
        ({"resolution": True}, "resolution"),
        ({"resolution": float("nan")}, "resolution"),
        ({"origin": None}, "origin"),
        ({"origin": [0.0, 0.0]}, "origin"),
        ({"origin": [0.0, "a", 0.0]}, "origin"),
        ({"negate": None}, "negate"),
        ({"negate": 2}, "negate"),
        ({"occupied_thresh": None}, "occupied_thresh"),
        ({"occupied_thresh": 1.5}, "occupied_thresh"),
        ({"free_thresh": -0.1}, "free_thresh"),
        ({"free_thresh": 0.7}, "free_thresh"),
        ({"mode": "ternary"}, "mode"),
    ],
)
def test_missing_or_invalid_field_is_named_in_the_error(
    tmp_path: Path, fields: dict[str, object], field: str
) -> None:
    _write_p5(tmp_path / "map.pgm", PIXELS)
    with pytest.raises(MapFormatError) as caught:
        load_map(_write_yaml(tmp_path, "map.pgm", **fields))
    assert caught.value.field == field
    assert isinstance(caught.value, InvalidRequest)
    assert isinstance(caught.value, PolynavError)


def test_missing_image_file_is_a_map_format_error(tmp_path: Path) -> None:
    with pytest.raises(MapFormatError, match="no such file") as caught:
        load_map(_write_yaml(tmp_path, "gone.png"))
    assert caught.value.field == "image"


def test_image_that_is_not_a_picture_is_a_map_format_error(tmp_path: Path) -> None:
    (tmp_path / "map.png").write_bytes(b"this is not a png")
    with pytest.raises(MapFormatError) as caught:
        load_map(_write_yaml(tmp_path, "map.png"))
    assert caught.value.field == "image"


def test_missing_yaml_file_is_a_map_format_error(tmp_path: Path) -> None:
    with pytest.raises(MapFormatError) as caught:
        load_map(tmp_path / "nothing.yaml")
    assert caught.value.field == "yaml"


@pytest.mark.parametrize("text", ["image: [unclosed\n", "- a list\n- not a map\n", ""])
def test_yaml_that_is_not_a_mapping_is_a_map_format_error(tmp_path: Path, text: str) -> None:
    path = tmp_path / "map.yaml"
    path.write_text(text)
    with pytest.raises(MapFormatError) as caught:
        load_map(path)
    assert caught.value.field == "yaml"


# --- saving ----------------------------------------------------------------------------------


def test_trinary_save_writes_map_saver_pixels_and_yaml(tmp_path: Path) -> None:
    data = np.array([[0, 100, -1, 20], [21, 64, 65, 99]], dtype=np.int8)
    grid = Map(MapInfo(resolution=0.05, width=4, height=2, origin=Pose2D(-1.0, 2.5, 0.0)), data)
    save_map(grid, tmp_path / "floor.yaml", image_format="pgm")
    with Image.open(tmp_path / "floor.pgm") as img:
        assert img.format == "PPM" and img.mode == "L"
        pixels = np.asarray(img).tolist()
    assert pixels == [[205, 205, 0, 0], [254, 0, 205, 254]]  # top row = data row 1
    assert (tmp_path / "floor.pgm").read_bytes().startswith(b"P5")
    assert (tmp_path / "floor.yaml").read_text() == (
        "image: floor.pgm\n"
        "mode: trinary\n"
        "resolution: 0.05\n"
        "origin: [-1.0, 2.5, 0.0]\n"
        "negate: 0\n"
        "occupied_thresh: 0.65\n"
        "free_thresh: 0.196\n"
    )


def test_scale_save_round_trips_every_value_and_unknown(tmp_path: Path) -> None:
    values = np.arange(-1, 101, dtype=np.int8).reshape(2, 51)
    grid = Map(MapInfo(resolution=0.1, width=51, height=2), values)
    save_map(grid, tmp_path / "m.yaml", mode="scale")
    _assert_same_map(load_map(tmp_path / "m.yaml"), grid)
    meta = yaml.safe_load((tmp_path / "m.yaml").read_text())
    assert (meta["mode"], meta["occupied_thresh"], meta["free_thresh"]) == ("scale", 1.0, 0.0)


def test_scale_save_to_pgm_with_unknown_cells_is_refused_before_writing(tmp_path: Path) -> None:
    grid = map_from_ascii("#.?")
    with pytest.raises(InvalidRequest, match="alpha"):
        save_map(grid, tmp_path / "m.yaml", image_format="pgm", mode="scale")
    assert list(tmp_path.iterdir()) == []


def test_raw_save_round_trips_to_pgm(tmp_path: Path) -> None:
    values = np.arange(-1, 101, dtype=np.int8).reshape(6, 17)
    grid = Map(MapInfo(resolution=0.1, width=17, height=6), values)
    save_map(grid, tmp_path / "m.yaml", image_format="pgm", mode="raw")
    _assert_same_map(load_map(tmp_path / "m.yaml"), grid)


def test_rotated_origin_and_tiny_resolution_round_trip_exactly(tmp_path: Path) -> None:
    grid = map_from_ascii("#.\n.?", resolution=1e-5, origin=Pose2D(-0.1, 1e-7, 3.0))
    save_map(grid, tmp_path / "m.yaml")
    loaded = load_map(tmp_path / "m.yaml")
    _assert_same_map(loaded, grid)
    assert loaded.info.origin.theta == 3.0
    assert math.isclose(loaded.info.resolution, 1e-5, rel_tol=0.0)


@pytest.mark.parametrize(
    ("kwargs", "field"), [({"image_format": "jpg"}, "image_format"), ({"mode": "x"}, "mode")]
)
def test_save_rejects_unknown_format_or_mode(
    tmp_path: Path, kwargs: dict[str, str], field: str
) -> None:
    with pytest.raises(InvalidRequest) as caught:
        save_map(map_from_ascii(".."), tmp_path / "m.yaml", **kwargs)
    assert caught.value.field == field
    assert list(tmp_path.iterdir()) == []


def test_save_replaces_old_files_and_leaves_no_temporary_files(tmp_path: Path) -> None:
    save_map(map_from_ascii("##"), tmp_path / "m.yaml")
    save_map(map_from_ascii("..."), tmp_path / "m.yaml")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.png", "m.yaml"]
    assert load_map(tmp_path / "m.yaml").data.tolist() == [[0, 0, 0]]


def test_save_writes_the_picture_before_the_yaml(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    replaced: list[str] = []
    real_replace = os.replace

    def spy(src: str, dst: str | Path) -> None:
        replaced.append(Path(dst).name)
        real_replace(src, dst)

    monkeypatch.setattr(os, "replace", spy)
    save_map(map_from_ascii("#."), tmp_path / "m.yaml")
    assert replaced == ["m.png", "m.yaml"]


def test_failed_yaml_write_keeps_the_old_yaml_and_cleans_up(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    save_map(map_from_ascii("##"), tmp_path / "m.yaml", mode="raw")
    old_yaml = (tmp_path / "m.yaml").read_text()
    real_replace = os.replace

    def fail_on_yaml(src: str, dst: str | Path) -> None:
        if str(dst).endswith(".yaml"):
            raise OSError("disk full")
        real_replace(src, dst)

    monkeypatch.setattr(os, "replace", fail_on_yaml)
    with pytest.raises(StorageError, match="disk full"):
        save_map(map_from_ascii("..."), tmp_path / "m.yaml")
    assert (tmp_path / "m.yaml").read_text() == old_yaml
    assert sorted(p.name for p in tmp_path.iterdir()) == ["m.png", "m.yaml"]


def test_save_into_missing_folder_is_a_storage_error(tmp_path: Path) -> None:
    with pytest.raises(StorageError):
        save_map(map_from_ascii(".."), tmp_path / "missing" / "m.yaml")
