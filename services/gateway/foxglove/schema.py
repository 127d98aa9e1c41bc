"""JSON schemas of zenros messages, named as ROS 2 names them (``sensor_msgs/msg/LaserScan``)."""

from __future__ import annotations

import json
from typing import Any

import msgspec
from zenros.message import Message, _TypedArray, normalize_type_name

__all__ = ["json_schema", "schema_bytes", "schema_name"]

_INTS = {"Int8Array", "UInt8Array"}


def _hook(tp: type) -> dict[str, Any]:
    if isinstance(tp, type) and issubclass(tp, _TypedArray):
        kind = "integer" if tp.__name__ in _INTS else "number"
        return {"type": "array", "items": {"type": kind}}
    raise NotImplementedError(f"no JSON schema for {tp!r}")


def schema_name(type_name: str) -> str:
    """The name Foxglove matches panels on: ``nav_msgs/OccupancyGrid`` → ``nav_msgs/msg/OccupancyGrid``."""
    pkg, _, name = normalize_type_name(type_name).rpartition("/")
    return f"{pkg}/msg/{name}" if pkg else name


def json_schema(msg_type: type[Message]) -> dict[str, Any]:
    """A self-contained JSON schema (draft 2020-12) of a message type, root type first."""
    schema: dict[str, Any] = msgspec.json.schema(msg_type, schema_hook=_hook)
    schema["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    return schema


def schema_bytes(msg_type: type[Message]) -> bytes:
    return json.dumps(json_schema(msg_type), separators=(",", ":")).encode()
