"""JSON schemas for Foxglove channels: ROS 2 names, and real messages validate against them."""

from __future__ import annotations

import jsonschema
import pytest
from zenros.message import Message
from zenros.msgs.geometry_msgs import TransformStamped
from zenros.msgs.nav_msgs import OccupancyGrid, Path
from zenros.msgs.sensor_msgs import LaserScan
from zenros.msgs.tf2_msgs import TFMessage
from zenros.services.gateway.foxglove.schema import json_schema, schema_name
from zenros.services.gateway.rosbridge.convert import to_json


def test_schema_names_are_ros2_names() -> None:
    assert schema_name("nav_msgs/OccupancyGrid") == "nav_msgs/msg/OccupancyGrid"
    assert schema_name("tf2_msgs/msg/TFMessage") == "tf2_msgs/msg/TFMessage"


@pytest.mark.parametrize("msg", [
    OccupancyGrid(data=[0, 100, -1]),
    LaserScan(ranges=[1.0, 2.5]),
    TFMessage(transforms=[TransformStamped(child_frame_id="base_link")]),
    Path(),
], ids=lambda m: type(m).__name__)
def test_messages_validate(msg: Message) -> None:
    schema = json_schema(type(msg))
    jsonschema.Draft202012Validator.check_schema(schema)
    jsonschema.validate(to_json(msg), schema)
    assert schema["$ref"] == f"#/$defs/{type(msg).__name__}"
