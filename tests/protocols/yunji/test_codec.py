"""Yunji framing: whole, split, byte by byte, several per read, bad escapes, oversize."""

from __future__ import annotations

import json

import pytest

from polynav.protocols.yunji import codec
from polynav.protocols.yunji.codec import Command, FrameTooLong, MalformedCommand

MOVE = b"/api/move?marker=room_205&uuid=42"
MOVE_COMMAND = Command("/api/move", {"marker": "room_205", "uuid": "42"}, MOVE.decode())


def _drain(buf: bytes, *, end_of_read: bool = False) -> tuple[list[Command], bytes]:
    got: list[Command] = []
    while buf:
        used, command = codec.decode(buf, end_of_read=end_of_read)
        buf = buf[used:]
        if command is None:
            break
        got.append(command)
    return got, buf


def test_decode_takes_a_newline_terminated_command() -> None:
    assert codec.decode(MOVE + b"\n") == (len(MOVE) + 1, MOVE_COMMAND)


def test_decode_drops_carriage_return_before_newline() -> None:
    assert codec.decode(MOVE + b"\r\n") == (len(MOVE) + 2, MOVE_COMMAND)


def test_decode_waits_for_more_without_delimiter_until_end_of_read() -> None:
    assert codec.decode(MOVE) == (0, None)
    assert codec.decode(MOVE, end_of_read=True) == (len(MOVE), MOVE_COMMAND)


def test_decode_accepts_a_command_in_two_halves() -> None:
    half = len(MOVE) // 2
    assert codec.decode(MOVE[:half]) == (0, None)
    assert codec.decode(MOVE[:half] + MOVE[half:] + b"\n") == (len(MOVE) + 1, MOVE_COMMAND)


def test_decode_accepts_a_command_byte_by_byte() -> None:
    wire = MOVE + b"\n"
    buf = b""
    got: list[Command] = []
    for i in range(len(wire)):
        buf += wire[i : i + 1]
        more, buf = _drain(buf)
        got += more
    assert got == [MOVE_COMMAND]
    assert buf == b""


def test_decode_splits_several_commands_in_one_read_by_newline_or_next_api_token() -> None:
    wire = b"/api/robot_status\n/api/move?marker=a\r\n/api/move/cancel/api/robot_info"
    got, rest = _drain(wire, end_of_read=True)
    assert [(c.path, c.params) for c in got] == [
        ("/api/robot_status", {}),
        ("/api/move", {"marker": "a"}),
        ("/api/move/cancel", {}),
        ("/api/robot_info", {}),
    ]
    assert rest == b""


def test_decode_skips_blank_lines() -> None:
    assert codec.decode(b"\r\n\n") == (3, None)


def test_decode_strips_the_legacy_http_prefix() -> None:
    raw = b"http://192.168.10.10:8808/api/markers/delete?name=205_room\n"
    used, command = codec.decode(raw)
    assert used == len(raw)
    assert command == Command(
        "/api/markers/delete", {"name": "205_room"}, raw.decode().rstrip("\n")
    )


def test_decode_percent_decodes_utf8_and_keeps_plus_signs() -> None:
    raw = b"/api/markers/insert?name=%E5%89%8D%E5%8F%B0&x=+1.5\n"
    _, command = codec.decode(raw)
    assert command is not None
    assert command.params == {"name": "前台", "x": "+1.5"}


def test_decode_keeps_the_last_of_a_repeated_parameter() -> None:
    _, command = codec.decode(b"/api/move?marker=a&marker=b\n")
    assert command is not None
    assert command.params == {"marker": "b"}
    assert command.uuid == ""


@pytest.mark.parametrize("query", [b"marker=%zz", b"marker=%4", b"marker=%FF%FE"])
def test_decode_rejects_bad_percent_encoding_and_says_how_far_it_went(query: bytes) -> None:
    raw = b"/api/move?" + query + b"&uuid=7\n/api/robot_info\n"
    with pytest.raises(MalformedCommand) as info:
        codec.decode(raw)
    assert info.value.used == raw.index(b"/api/robot_info")
    assert (info.value.path, info.value.uuid, info.value.field) == ("/api/move", "7", "marker")


def test_decode_rejects_a_line_that_is_not_a_command() -> None:
    with pytest.raises(MalformedCommand) as info:
        codec.decode(b"hello\n/api/robot_info")
    assert info.value.used == 6


def test_decode_rejects_invalid_utf8() -> None:
    with pytest.raises(MalformedCommand):
        codec.decode(b"/api/move?marker=\xff\n")


def test_decode_raises_frame_too_long_without_delimiter_beyond_max() -> None:
    assert codec.decode(b"/api/move?marker=" + b"a" * 47, max_bytes=64) == (0, None)
    with pytest.raises(FrameTooLong):
        codec.decode(b"/api/move?marker=" + b"a" * 48, max_bytes=64)
    with pytest.raises(FrameTooLong):
        codec.decode(b"x" * 5000)


def test_encode_reply_is_compact_json_on_one_line() -> None:
    packet = codec.encode_reply("/api/move", "42", "OK", task_id="00000000000000000000000000000001")
    assert packet == (
        b'{"type":"response","command":"/api/move","uuid":"42","status":"OK",'
        b'"error_message":"","task_id":"00000000000000000000000000000001"}\n'
    )


def test_encode_reply_distinguishes_missing_results_from_null() -> None:
    assert "results" not in json.loads(codec.encode_reply("/api/estop", "", "OK"))
    assert json.loads(codec.encode_reply("/api/markers/query_list", "", "OK", results=None))[
        "results"
    ] is None


def test_encode_callback_and_notification() -> None:
    assert codec.encode_callback("robot_status", {"a": 1}) == (
        b'{"type":"callback","topic":"robot_status","results":{"a":1}}\n'
    )
    assert json.loads(codec.encode_notification("01001", "info", "The move task is started.",
                                                 {"target": "room_205"})) == {
        "type": "notification", "code": "01001", "level": "info",
        "description": "The move task is started.", "data": {"target": "room_205"},
    }
