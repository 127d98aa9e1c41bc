"""JSON Schemas generated from message types validate what the codec writes."""

from __future__ import annotations

import base64
import json
import math
from typing import Any

import jsonschema
import msgspec
import numpy as np
import pytest
from zenros.bag.schema import message_encoding, schema_for
from zenros.codec import codec_for
from zenros.msgs.nav_msgs import MapMetaData, OccupancyGrid, Odometry
from zenros.msgs.sensor_msgs import BatteryState, Imu, LaserScan
from zenros.msgs.tf2_msgs import TFMessage
from zenros.registry import registered_types


def _json_view(obj: Any) -> Any:
    if isinstance(obj, bytes):
        return base64.b64encode(obj).decode()
    if isinstance(obj, dict):
        return {k: _json_view(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_json_view(v) for v in obj]
    return obj


def validate(msg: Any) -> None:
    codec = codec_for(type(msg))
    encoding, data = schema_for(codec.type_name)
    assert encoding == "jsonschema"
    schema = json.loads(data)
    assert schema["type"] == "object" and schema["title"] == codec.type_name
    payload = codec.encode(msg)
    obj = (_json_view(msgspec.msgpack.decode(payload)) if codec.bulk
           else json.loads(payload))
    jsonschema.Draft202012Validator(schema).validate(obj)


@pytest.mark.parametrize("msg", [
    Odometry(child_frame_id="base_link"),
    TFMessage(),
    Imu(),
    BatteryState(voltage=math.nan),  # NaN travels as null
    LaserScan(ranges=np.arange(10, dtype=np.float32)),
    OccupancyGrid(info=MapMetaData(width=2, height=2), data=np.array([0, 100, -1, 5], np.int8)),
], ids=lambda m: type(m).__name__)
def test_schema_validates_encoded_messages(msg: Any) -> None:
    validate(msg)


def test_every_registered_type_has_a_schema() -> None:
    for name, cls in registered_types().items():
        encoding, data = schema_for(name)
        assert encoding == "jsonschema", name
        assert json.loads(data)["type"] == "object", name
        try:
            msg = cls()
        except TypeError:  # a type with required fields: its schema was still checked above
            continue
        validate(msg)


def test_schema_rejects_a_wrong_shape() -> None:
    schema = json.loads(schema_for("geometry_msgs/Twist")[1])
    with pytest.raises(jsonschema.ValidationError):
        jsonschema.validate({"linear": {"x": "fast"}}, schema)


def test_unknown_type_gets_no_schema() -> None:
    assert schema_for("no_pkg/Nothing") == ("", b"")


def test_message_encodings() -> None:
    assert message_encoding("application/json") == "json"
    assert message_encoding("application/msgpack") == "msgpack"
