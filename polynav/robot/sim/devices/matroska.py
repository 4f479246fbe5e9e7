"""A minimal Matroska (MKV) writer for Motion-JPEG video: what the simulated recorder saves.

Matroska is EBML: each element is an ID, a variable-length size and a payload (RFC 8794; the
Matroska element IDs from RFC 9559). The file here holds the EBML header, then one Segment with
a ``SeekHead`` (where the next elements are), ``Info`` (timestamps in milliseconds, the
duration), ``Tracks`` (one ``V_MJPEG`` video track) and ``Cluster`` elements of
``SimpleBlock`` frames, a new cluster every ``CLUSTER_SPAN`` milliseconds because a block's
timestamp is a signed 16-bit offset from its cluster's. Every frame is a key frame (JPEG frames
stand alone). Players (ffmpeg, VLC, mpv) open such files.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence

CLUSTER_SPAN = 30_000  # [ms]

EBML = 0x1A45DFA3
SEGMENT = 0x18538067
INFO = 0x1549A966
TRACKS = 0x1654AE6B
CLUSTER = 0x1F43B675
SIMPLE_BLOCK = 0xA3
SEEK_HEAD = 0x114D9B74


def element_id(value: int) -> bytes:
    return value.to_bytes((value.bit_length() + 7) // 8, "big")


def size_vint(size: int) -> bytes:
    """An EBML variable-length size (the all-ones value of each length is reserved)."""
    for length in range(1, 9):
        if size < (1 << (7 * length)) - 1:
            return (size | (1 << (7 * length))).to_bytes(length, "big")
    raise ValueError(f"element too large: {size} bytes")


def element(eid: int, payload: bytes) -> bytes:
    return element_id(eid) + size_vint(len(payload)) + payload


def uint(eid: int, value: int) -> bytes:
    return element(eid, value.to_bytes(max(1, (value.bit_length() + 7) // 8), "big"))


def text(eid: int, value: str) -> bytes:
    return element(eid, value.encode("utf-8"))


def mjpeg_mkv(frames: Sequence[tuple[int, bytes]], width: int, height: int) -> bytes:
    """A Matroska file of JPEG ``frames``: (timestamp [ms] from the start, JPEG bytes)."""
    # The last frame shows for as long as the one before it did.
    step = frames[-1][0] - frames[-2][0] if len(frames) > 1 else 1
    duration = float(frames[-1][0] + step) if frames else 0.0
    header = element(EBML, b"".join((
        uint(0x4286, 1), uint(0x42F7, 1), uint(0x42F2, 4), uint(0x42F3, 8),
        text(0x4282, "matroska"), uint(0x4287, 4), uint(0x4285, 2),
    )))
    info = element(INFO, b"".join((
        uint(0x2AD7B1, 1_000_000),  # timestamps in ms
        text(0x4D80, "polynav"), text(0x5741, "polynav simulated camera"),
        element(0x4489, struct.pack(">d", duration)),
    )))
    video = element(0xE0, uint(0xB0, width) + uint(0xBA, height))
    track = element(0xAE, b"".join((
        uint(0xD7, 1), uint(0x73C5, 1), uint(0x83, 1), uint(0x9C, 0),
        text(0x86, "V_MJPEG"), video,
    )))
    tracks = element(TRACKS, track)
    clusters: list[bytes] = []
    blocks: list[bytes] = []
    base = None
    for stamp, jpeg in frames:
        if base is None or stamp - base >= CLUSTER_SPAN:
            if blocks:
                clusters.append(element(CLUSTER, uint(0xE7, base or 0) + b"".join(blocks)))
            base, blocks = stamp, []
        # Track 1 as a 1-byte vint, the time offset, flags: key frame.
        blocks.append(element(SIMPLE_BLOCK, b"\x81" + struct.pack(">hB", stamp - base, 0x80)
                              + jpeg))
    if blocks:
        clusters.append(element(CLUSTER, uint(0xE7, base or 0) + b"".join(blocks)))
    # The index of the top-level elements, first in the segment, as most readers expect;
    # fixed-width positions keep its own size independent of the values.
    targets = [(INFO, info), (TRACKS, tracks)] + ([(CLUSTER, clusters[0])] if clusters else [])
    seek_head = _seek_head([(eid, 0) for eid, _ in targets])
    position, entries = len(seek_head), []
    for eid, body in targets:
        entries.append((eid, position))
        position += len(body)
    seek_head = _seek_head(entries)
    return header + element(SEGMENT, seek_head + info + tracks + b"".join(clusters))


def _seek_head(entries: Sequence[tuple[int, int]]) -> bytes:
    """A SeekHead: each element ID with its position [bytes] from the segment's payload."""
    return element(SEEK_HEAD, b"".join(
        element(0x4DBB, element(0x53AB, element_id(eid))
                + element(0x53AC, position.to_bytes(8, "big")))
        for eid, position in entries
    ))
