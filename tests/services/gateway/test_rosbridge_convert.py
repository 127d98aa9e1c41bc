"""rosbridge JSON ↔ messages, type names and fragments."""

from __future__ import annotations

import json

import pytest
from zenros.errors import DecodeError
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.example_interfaces import AddTwoIntsRequest
from zenros.msgs.geometry_msgs import PoseStamped, Twist
from zenros.services.gateway.rosbridge.convert import (
    encode_message,
    long_type,
    message_from_json,
    publish_frame,
    request_args,
)
from zenros.services.gateway.rosbridge.fragments import (
    Defragmenter,
    FragmentError,
    Fragments,
    fragment,
)


def test_long_type_names() -> None:
    assert long_type("std_msgs/String") == "std_msgs/msg/String"
    assert long_type("std_msgs/msg/String") == "std_msgs/msg/String"
    assert long_type("example_interfaces/AddTwoInts", "srv") == "example_interfaces/srv/AddTwoInts"


def test_missing_fields_take_defaults_and_unknown_fields_fail() -> None:
    msg = message_from_json({"linear": {"x": 1}}, Twist)
    assert isinstance(msg, Twist) and msg.linear.x == 1.0 and msg.angular.z == 0.0
    with pytest.raises(DecodeError, match="unknown field 'speed'"):
        message_from_json({"speed": 1}, Twist)
    with pytest.raises(DecodeError, match=r"\$\.linear\.x"):
        message_from_json({"linear": {"x": "fast"}}, Twist)
    with pytest.raises(TypeError, match="JSON object"):
        message_from_json([1], Twist)


def test_missing_header_stamp_is_now() -> None:
    now = Time(sec=5, nanosec=6)
    msg = message_from_json({"header": {"frame_id": "map"}}, PoseStamped, now)
    assert isinstance(msg, PoseStamped)
    assert msg.header.stamp == now and msg.header.frame_id == "map"
    given = message_from_json({"header": {"stamp": {"sec": 1, "nanosec": 2}}}, PoseStamped, now)
    assert isinstance(given, PoseStamped) and given.header.stamp == Time(sec=1, nanosec=2)


def test_positional_service_args() -> None:
    assert request_args([1, 2], AddTwoIntsRequest) == {"a": 1, "b": 2}
    with pytest.raises(TypeError, match="takes 2 fields"):
        request_args([1, 2, 3], AddTwoIntsRequest)


def test_publish_frame_is_json() -> None:
    frame = publish_frame("/cmd_vel", encode_message(Twist()))
    assert json.loads(frame)["msg"]["linear"] == {"x": 0.0, "y": 0.0, "z": 0.0}


def test_fragment_round_trip() -> None:
    frame = json.dumps({"op": "publish", "topic": "/t", "msg": {"data": "é" * 100}}).encode()
    parts = [json.loads(p) for p in fragment(frame, 30, "m")]
    assert len(parts) > 1 and all(len(p["data"]) <= 30 for p in parts)
    d = Defragmenter(lambda: 0.0)
    joined = [d.add(p) for p in reversed(parts)]
    assert joined[:-1] == [None] * (len(parts) - 1)
    assert joined[-1] is not None and json.loads(joined[-1]) == json.loads(frame)
    assert fragment(frame, 10_000) == [frame]


def test_fragments_are_made_as_taken_and_shared_by_clients() -> None:
    """A large frame's fragments are made one at a time, as the writer takes them (no 3 ms
    of decoding a 5 MB map on the loop at once), and the same frame split again (the message
    to the next client) gives the same pieces; raw UTF-8 is cut by characters."""
    frame = json.dumps({"op": "publish", "topic": "/t", "msg": {"data": list(range(50))}})
    pieces = fragment(frame.encode(), 40)
    assert isinstance(pieces, Fragments) and len(pieces) == -(-len(frame) // 40)
    assert pieces[1] and pieces._made.count(None) == len(pieces) - 1  # only that one made
    again = fragment(pieces.frame, 40)
    assert again is pieces
    assert fragment(frame.encode(), 40) is not pieces  # an equal frame: another message
    assert "".join(json.loads(p)["data"] for p in pieces) == frame
    assert [json.loads(p)["num"] for p in pieces[-2:]] == [len(pieces) - 2, len(pieces) - 1]
    utf8 = json.dumps({"msg": {"data": "é" * 100}}, ensure_ascii=False).encode()
    parts = [json.loads(p) for p in fragment(utf8, 30, "u")]
    assert all(len(p["data"]) <= 30 for p in parts) and len(parts) == -(-len(utf8.decode()) // 30)
    assert "".join(p["data"] for p in parts) == utf8.decode()
    assert fragment("é".encode() * 20, 30) == ["é".encode() * 20]  # 40 bytes, 20 characters


def test_bad_fragments() -> None:
    d = Defragmenter(lambda: 0.0)
    with pytest.raises(FragmentError):
        d.add({"id": "x", "data": "a", "num": 3, "total": 2})
    with pytest.raises(FragmentError):
        d.add({"data": "a", "num": 0, "total": 2})


def test_incomplete_fragments_expire() -> None:
    now = [0.0]
    d = Defragmenter(lambda: now[0], timeout=10)
    d.add({"id": "x", "data": "a", "num": 0, "total": 2})
    now[0] = 11
    d.add({"id": "y", "data": "a", "num": 0, "total": 2})
    assert len(d) == 1


def test_cbor_frames_go_binary_and_every_json_frame_text() -> None:
    from zenros.msgs.builtin_interfaces import Time
    from zenros.msgs.std_msgs import String
    from zenros.services.gateway.rosbridge.cbor import (
        cbor_frame,
        cbor_frame_from_json,
        cbor_raw_frame,
        is_binary,
    )
    from zenros.services.gateway.rosbridge.convert import dumps
    from zenros.services.gateway.rosbridge.fragments import fragment

    msg = String(data="{not json")
    for frame in (cbor_frame("/t", msg), cbor_raw_frame("/t", msg, Time(sec=1)),
                  cbor_frame_from_json({"op": "publish", "topic": "/t", "msg": {"data": "x"}})):
        assert is_binary(frame)
    text = dumps({"op": "publish", "topic": "/t", "msg": {"data": "{x"}})
    assert not is_binary(text)
    assert not any(is_binary(f) for f in fragment(text * 3, 10))
