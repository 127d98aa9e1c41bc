"""The parameter wire protocol: keys, node names, value encoding, stamps, remote errors."""

from __future__ import annotations

import math
from typing import Any

import pytest
from zenros.errors import (
    InvalidNameError,
    InvalidParameterValueError,
    ParameterError,
    ParameterNotFoundError,
)
from zenros.names import KeySpace
from zenros.param_protocol import (
    JSON_ENCODING,
    MSGPACK_ENCODING,
    SetParamResponse,
    decode_stamp,
    decode_value,
    encode_stamp,
    encode_value,
    local_param_name,
    node_param_name,
    param_key,
    param_name,
    raise_remote,
)


def test_keys_and_names_round_trip() -> None:
    keys = KeySpace("zenros")
    assert param_key(keys, "/nav/max_speed") == "zenros/param/nav/max_speed"
    assert param_key(keys, "/") == "zenros/param"
    assert param_name(keys, "zenros/param/nav/max_speed") == "/nav/max_speed"
    assert param_name(keys, "zenros/param") == "/"
    with pytest.raises(InvalidNameError, match="not a parameter key"):
        param_name(keys, "zenros/topic/x")


def test_node_parameter_names() -> None:
    assert node_param_name("/nav/planner", "costmap.inflation") == "/nav/planner/costmap/inflation"
    assert node_param_name("/talker", "rate") == "/talker/rate"
    assert local_param_name("/nav/planner", "/nav/planner/costmap/inflation") == "costmap.inflation"
    assert local_param_name("/nav/planner", "/nav/other/x") is None
    assert local_param_name("/nav/planner", "/nav/planner2/x") is None
    with pytest.raises(InvalidNameError):
        node_param_name("/talker", "max-speed")


@pytest.mark.parametrize("value,encoding", [
    (0.5, JSON_ENCODING), (2.0, JSON_ENCODING), (True, JSON_ENCODING), (7, JSON_ENCODING),
    (2**64 - 1, JSON_ENCODING), ("text", JSON_ENCODING), ([1, "a", [True]], JSON_ENCODING),
    ({"a": {"b": 1.0}, "c": []}, JSON_ENCODING), ({}, JSON_ENCODING),
    (b"\x00\x01", MSGPACK_ENCODING), ({"blob": [b"x"]}, MSGPACK_ENCODING),
    (math.inf, MSGPACK_ENCODING),
])
def test_values_keep_their_types(value: Any, encoding: str) -> None:
    data, enc = encode_value(value)
    assert enc == encoding
    back = decode_value(data, enc)
    assert back == value and type(back) is type(value)
    if isinstance(value, float) and value == 2.0:
        assert data == b"2.0"


def test_nan_survives() -> None:
    data, enc = encode_value(math.nan)
    assert math.isnan(decode_value(data, enc))


def test_bad_payload_is_a_parameter_error() -> None:
    with pytest.raises(ParameterError, match="cannot decode"):
        decode_value(b"{", JSON_ENCODING)


def test_stamps() -> None:
    assert decode_stamp(encode_stamp(123, "abc")) == (123, "abc")
    assert decode_stamp(None) == (0, "")
    assert decode_stamp(b"\xff\xfe") == (0, "")


@pytest.mark.parametrize("kind,cls", [
    ("ParameterNotFoundError", ParameterNotFoundError),
    ("InvalidParameterValueError", InvalidParameterValueError),
    ("InvalidNameError", InvalidNameError),
    ("SomethingElse", ParameterError),
])
def test_remote_errors_keep_their_class(kind: str, cls: type[Exception]) -> None:
    raise_remote("/master/set_param", SetParamResponse())  # no error: no raise
    with pytest.raises(cls, match="the reason"):
        raise_remote("/master/set_param", SetParamResponse(error="the reason", error_type=kind))
