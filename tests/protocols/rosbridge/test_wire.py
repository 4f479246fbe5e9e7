"""rosbridge JSON as clients that read it with regular expressions expect: plain decimals, the
messages' key order, no NaN."""

from __future__ import annotations

import json
import math

import numpy as np

from polynav.geometry import Pose2D
from polynav.protocols.rosbridge.wire import dumps
from polynav.rosmsg import encode


def test_numbers_are_plain_decimals_outside_strings() -> None:
    text = dumps({"a": 1e-05, "b": [1.5e20, -2.5e-7, 3.0], "s": "1e-05 stays", "i": 7,
                  "n": np.float32(1e-6)})
    assert text == ('{"a":0.00001,"b":[150000000000000000000.0,-0.00000025,3.0],'
                    '"s":"1e-05 stays","i":7,"n":0.000001}')
    assert json.loads(text)["a"] == 1e-05


def test_nan_and_infinity_are_null() -> None:
    assert dumps({"x": math.nan, "y": [math.inf, -math.inf]}) == '{"x":null,"y":[null,null]}'


def test_message_keys_keep_the_msg_field_order() -> None:
    text = dumps(encode.pose_stamped(3, 1.5, "map", Pose2D(1.0, 2.0, 0.5)))
    assert text.index('"x"') < text.index('"y"') < text.index('"z"') < text.index('"w"')
    assert text.startswith('{"header":{"seq":3,"stamp":{"secs":1,"nsecs":500000000},'
                           '"frame_id":"map"},"pose":{"position":{"x":1.0,"y":2.0,"z":0.0}')
