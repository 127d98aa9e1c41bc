"""ROS 2 wire compatibility: CDR <-> msgspec, ROS 2 type names, RIHS01 type hashes, and the
key and token layout of rmw_zenoh.

Everything here works from zenros's own type definitions (`zenros.ros2.definitions`); the ROS 2
wheels are only the tests' reference, never a runtime dependency.
"""

from __future__ import annotations

from .cdr import CdrCodec, cdr_codec, cdr_codec_for_name
from .idl import FieldType, MsgDef, RosField, parse_msg
from .registry import definition, ros_name_of, zenros_class_of
from .typehash import type_description, type_hash

__all__ = [
    "CdrCodec",
    "FieldType",
    "MsgDef",
    "RosField",
    "cdr_codec",
    "cdr_codec_for_name",
    "definition",
    "parse_msg",
    "ros_name_of",
    "type_description",
    "type_hash",
    "zenros_class_of",
]
