"""Parameter parsing: query strings and JSON bodies give the same typed values; bad ones are
refused naming the parameter."""

from __future__ import annotations

import pytest

from polynav.errors import InvalidRequest
from polynav.protocols.galileo.params import Params


def test_query_text_and_json_values_parse_alike() -> None:
    query = Params({"i": "3", "f": "1.5", "b": "True", "s": "map1", "l": "[1, 2]"})
    body = Params({"i": 3, "f": 1.5, "b": True, "s": "map1", "l": [1, 2]})
    for p in (query, body):
        assert p.integer("i") == 3
        assert p.number("f") == 1.5
        assert p.boolean("b") is True
        assert p.text("s") == "map1"
        assert p.structure("l") == [1, 2]
    assert Params({"b": "0"}).boolean("b") is False
    assert Params({"n": 7}).text("n") == "7"


def test_defaults_apply_only_when_absent() -> None:
    p = Params({"x": "2"})
    assert p.integer("y", -1) == -1
    assert p.text("y", None) is None
    assert p.integer("x", -1) == 2
    assert "x" in p and "y" not in p


@pytest.mark.parametrize(("values", "call"), [
    ({}, lambda p: p.integer("i")),
    ({"i": "3.5"}, lambda p: p.integer("i")),
    ({"i": True}, lambda p: p.integer("i")),
    ({"f": "abc"}, lambda p: p.number("f")),
    ({"f": "nan"}, lambda p: p.number("f")),
    ({"f": "inf"}, lambda p: p.number("f")),
    ({"b": "maybe"}, lambda p: p.boolean("b")),
    ({"s": [1]}, lambda p: p.text("s")),
    ({"l": "{oops"}, lambda p: p.structure("l")),
    ({"l": "5"}, lambda p: p.structure("l")),
])
def test_missing_or_mistyped_parameters_raise_invalid_request(values, call) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidRequest):
        call(Params(values))


def test_missing_file_part_names_it() -> None:
    with pytest.raises(InvalidRequest, match="file"):
        Params({}).file("file")
