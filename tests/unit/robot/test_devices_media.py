from __future__ import annotations

import io
import math
import struct
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from polynav.errors import Conflict, InvalidRequest, NotFound
from polynav.robot.devices import JobState
from polynav.robot.interface import LaserScan
from polynav.robot.sim.devices import matroska
from polynav.robot.sim.devices.camera import HEIGHT, WIDTH, SimCamera
from polynav.robot.sim.devices.media import FRAME_RATE, MediaFolder, VideoRecorder


def _scan(front: float, back: float = math.inf) -> LaserScan:
    """360 beams: a wall ``front`` metres ahead across +-60 degrees, ``back`` behind."""
    angles = -math.pi + np.arange(360) * 2 * math.pi / 360
    ranges = np.full(360, np.inf, dtype=np.float32)
    ranges[np.abs(angles) <= math.radians(60)] = front
    ranges[np.abs(angles) >= math.radians(120)] = back
    return LaserScan(0.0, -math.pi, 2 * math.pi / 360, 0.1, 20.0, ranges)


def _wall_rows(png: bytes) -> int:
    """How many rows of the middle column show wall colour."""
    image = np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(int)
    column = image[:, WIDTH // 2]
    return int(np.count_nonzero(column[:, 2] < column[:, 0] - 15))  # wall is warm, not grey


def test_a_nearer_wall_looks_taller_and_the_rear_camera_looks_behind() -> None:
    near = SimCamera(lambda: _scan(1.0)).capture(0.0, view="front", fmt="png")
    far = SimCamera(lambda: _scan(4.0)).capture(0.0, view="front", fmt="png")
    assert Image.open(io.BytesIO(near)).size == (WIDTH, HEIGHT)
    assert _wall_rows(near) > 2 * _wall_rows(far) > 0
    behind = SimCamera(lambda: _scan(1.0, back=math.inf)).capture(0.0, view="back", fmt="png")
    assert _wall_rows(behind) == 0
    jpeg = SimCamera(lambda: None).capture(0.0, view="front", fmt="jpeg")
    assert jpeg[:2] == b"\xff\xd8"
    with pytest.raises(InvalidRequest):
        SimCamera(lambda: None).capture(0.0, view="top", fmt="png")
    with pytest.raises(InvalidRequest):
        SimCamera(lambda: None).capture(0.0, view="front", fmt="gif")


def _elements(data: bytes) -> list[tuple[int, bytes]]:
    """Top-level EBML elements of ``data``: (id, payload)."""
    out, i = [], 0
    while i < len(data):
        first = data[i]
        id_len = 1 + (8 - first.bit_length())  # leading zeros + 1
        eid = int.from_bytes(data[i:i + id_len], "big")
        i += id_len
        size_len = 8 - data[i].bit_length() + 1
        size = int.from_bytes(data[i:i + size_len], "big") & ((1 << (7 * size_len)) - 1)
        i += size_len
        out.append((eid, data[i:i + size]))
        i += size
    return out


def test_the_video_file_is_matroska_with_one_mjpeg_track_and_clusters_of_key_frames() -> None:
    frames = [(ms, b"\xff\xd8jpeg%d" % ms) for ms in range(0, 65_000, 5_000)]
    data = matroska.mjpeg_mkv(frames, 320, 240)
    (ebml, header), (segment, body) = _elements(data)
    assert (ebml, segment) == (matroska.EBML, matroska.SEGMENT)
    assert b"matroska" in header
    parts = _elements(body)
    ids = [eid for eid, _ in parts]
    assert ids[:3] == [matroska.SEEK_HEAD, matroska.INFO, matroska.TRACKS]
    assert b"V_MJPEG" in parts[2][1]
    # The seek head points at Info, Tracks and the first Cluster.
    offsets, position = {}, 0
    for eid, payload in parts:
        offsets.setdefault(eid, position)
        position += len(matroska.element(eid, payload))
    seeks = {}
    for _, seek in _elements(parts[0][1]):
        (_, sid), (_, spos) = _elements(seek)
        seeks[int.from_bytes(sid, "big")] = int.from_bytes(spos, "big")
    assert seeks == {k: offsets[k] for k in (matroska.INFO, matroska.TRACKS, matroska.CLUSTER)}
    clusters = [payload for eid, payload in parts if eid == matroska.CLUSTER]
    assert len(clusters) == 3  # a new cluster every 30 s
    blocks = []
    for cluster in clusters:
        inner = _elements(cluster)
        assert inner[0][0] == 0xE7
        base = int.from_bytes(inner[0][1], "big")
        for eid, payload in inner[1:]:
            assert eid == matroska.SIMPLE_BLOCK and payload[0] == 0x81 and payload[3] == 0x80
            (offset,) = struct.unpack(">h", payload[1:3])
            blocks.append((base + offset, payload[4:]))
    assert blocks == frames


def test_photo_names_are_the_stamp_unless_given_and_never_overwrite(tmp_path: Path) -> None:
    folder = MediaFolder(tmp_path / "photos", ".png")
    assert folder.names() == []
    first = folder.new_name(12.3456, None)
    folder.write(first, b"a")
    assert first == "12346"
    second = folder.new_name(12.3456, None)
    assert second == "12347"
    folder.write("mine", b"b")
    assert folder.path("mine").read_bytes() == b"b"
    folder.delete("mine")
    with pytest.raises(NotFound):
        folder.path("mine")
    for bad in ("../x", ".hidden", "a/b", ""):
        with pytest.raises(InvalidRequest):
            folder.new_name(0.0, bad)


def test_a_video_records_frames_on_the_clock_and_saves_when_its_time_is_up(
    tmp_path: Path,
) -> None:
    folder = MediaFolder(tmp_path / "videos", ".mkv")
    recorder = VideoRecorder(SimCamera(lambda: _scan(2.0)), folder)
    job = recorder.start(100.0, view="front", duration=3.0, name=None)
    assert job.state is JobState.WORKING and recorder.recording
    with pytest.raises(Conflict):
        recorder.start(100.5, view="front", duration=3.0, name=None)
    for k in range(1, 60):
        recorder.tick(100.0 + 0.05 * k)
    assert recorder.job(job.job_id).state is JobState.WORKING
    assert recorder.job(job.job_id).progress == pytest.approx(2.95 / 3.0)
    recorder.tick(103.0)
    done = recorder.job(job.job_id)
    assert done.state is JobState.COMPLETE and not recorder.recording
    assert folder.names() == ["100000"]
    segment = _elements(folder.path("100000").read_bytes())[1][1]
    clusters = [p for eid, p in _elements(segment) if eid == matroska.CLUSTER]
    assert len(_elements(clusters[0])) - 1 == int(3.0 * FRAME_RATE)


def test_stopping_a_video_saves_what_was_recorded(tmp_path: Path) -> None:
    folder = MediaFolder(tmp_path / "videos", ".mkv")
    recorder = VideoRecorder(SimCamera(lambda: None), folder)
    job = recorder.start(0.0, view="back", duration=60.0, name="clip")
    recorder.tick(10.0)
    assert recorder.stop(10.0) is True
    stopped = recorder.job(job.job_id)
    assert stopped.state is JobState.CANCELLED
    assert stopped.progress == pytest.approx(10.0 / 60.0, abs=1e-6)
    assert folder.names() == ["clip"] and recorder.saved[job.job_id] == "clip"
    assert recorder.stop(11.0) is False
    for duration in (0.0, -1.0, 1e6):
        with pytest.raises(InvalidRequest):
            recorder.start(20.0, view="front", duration=duration, name=None)
    with pytest.raises(InvalidRequest):
        recorder.start(20.0, view="side", duration=1.0, name=None)
    assert not recorder.recording


def test_a_partial_sweep_shows_nothing_outside_its_field_of_view() -> None:
    # A 180-degree lidar facing forward, a wall 1 m away all round its sweep.
    ranges = np.full(180, 1.0, dtype=np.float32)
    scan = LaserScan(0.0, -math.pi / 2, math.pi / 180, 0.1, 20.0, ranges)
    assert _wall_rows(SimCamera(lambda: scan).capture(0.0, view="front", fmt="png")) > 200
    assert _wall_rows(SimCamera(lambda: scan).capture(0.0, view="back", fmt="png")) == 0
