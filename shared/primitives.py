"""ROS's fixed-width primitive types as annotated Python types, for message fields.

``UInt8`` is an ``int`` that msgspec refuses outside 0..255 when it decodes (JSON from a
rosbridge client, a REST body, MessagePack), with the field named in the error; in Python
it is a plain ``int``. Floats are plain ``float`` (float32's range is checked by the CDR
codec when a value goes to ROS 2).
"""

from __future__ import annotations

from typing import Annotated

import msgspec

__all__ = ["INT_BOUNDS", "Byte", "Char", "Int8", "Int16", "Int32", "Int64", "UInt8", "UInt16",
           "UInt32", "UInt64", "int_alias"]

# ROS base type -> (minimum, maximum)
INT_BOUNDS: dict[str, tuple[int, int]] = {
    "byte": (0, 0xFF), "char": (0, 0xFF),
    "int8": (-0x80, 0x7F), "uint8": (0, 0xFF),
    "int16": (-0x8000, 0x7FFF), "uint16": (0, 0xFFFF),
    "int32": (-0x8000_0000, 0x7FFF_FFFF), "uint32": (0, 0xFFFF_FFFF),
    "int64": (-0x8000_0000_0000_0000, 0x7FFF_FFFF_FFFF_FFFF),
    "uint64": (0, 0xFFFF_FFFF_FFFF_FFFF),
}

Byte = Annotated[int, msgspec.Meta(ge=0, le=0xFF)]
Char = Annotated[int, msgspec.Meta(ge=0, le=0xFF)]
Int8 = Annotated[int, msgspec.Meta(ge=-0x80, le=0x7F)]
UInt8 = Annotated[int, msgspec.Meta(ge=0, le=0xFF)]
Int16 = Annotated[int, msgspec.Meta(ge=-0x8000, le=0x7FFF)]
UInt16 = Annotated[int, msgspec.Meta(ge=0, le=0xFFFF)]
Int32 = Annotated[int, msgspec.Meta(ge=-0x8000_0000, le=0x7FFF_FFFF)]
UInt32 = Annotated[int, msgspec.Meta(ge=0, le=0xFFFF_FFFF)]
Int64 = Annotated[int, msgspec.Meta(ge=-0x8000_0000_0000_0000, le=0x7FFF_FFFF_FFFF_FFFF)]
UInt64 = Annotated[int, msgspec.Meta(ge=0)]  # msgspec checks bounds within int64 only

_ALIASES = {"byte": "Byte", "char": "Char", "int8": "Int8", "uint8": "UInt8", "int16": "Int16",
            "uint16": "UInt16", "int32": "Int32", "uint32": "UInt32", "int64": "Int64",
            "uint64": "UInt64"}


def int_alias(base: str) -> str:
    """The name in this module of a ROS integer base type (``uint8`` -> ``UInt8``)."""
    return _ALIASES[base]
