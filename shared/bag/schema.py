"""JSON Schemas for bag channels, generated from our message types."""

from __future__ import annotations

import json
from functools import cache
from typing import Any

import msgspec

from ..codec import MSGPACK, codec_for
from ..message import Message, UInt8Array, _TypedArray
from ..registry import lookup_type

__all__ = ["message_encoding", "schema_for", "schema_of_type"]

JSON_ENCODING = "json"
MSGPACK_ENCODING = "msgpack"


def message_encoding(mime: str) -> str:
    """The MCAP message encoding of a Zenoh payload mime (``application/msgpack`` -> msgpack)."""
    return MSGPACK_ENCODING if mime == MSGPACK else JSON_ENCODING


def _hook(binary: bool) -> Any:
    def hook(tp: type) -> dict[str, Any]:
        if isinstance(tp, type) and issubclass(tp, _TypedArray):
            dtype = str(tp.dtype_().dtype) if callable(tp.dtype_) else str(tp.dtype_)
            if binary:
                return {"type": "string", "contentEncoding": "base64",
                        "description": f"little-endian {dtype} array (MessagePack bin)"}
            if issubclass(tp, UInt8Array):  # uint8[]: base64 in JSON, as rosbridge writes it
                return {"type": "string", "contentEncoding": "base64", "description": "bytes"}
            return {"type": "array", "items": {"type": "number"}, "description": f"{dtype} array"}
        raise NotImplementedError(f"no JSON schema for {tp!r}")

    return hook


def _nullable_numbers(node: Any) -> Any:
    """Our JSON writes NaN and infinities as ``null`` (as rosbridge does): allow it."""
    if isinstance(node, dict):
        out = {k: _nullable_numbers(v) for k, v in node.items()}
        if out.get("type") == "number":
            out["type"] = ["number", "null"]
        return out
    if isinstance(node, list):
        return [_nullable_numbers(v) for v in node]
    return node


@cache
def schema_of_type(msg_type: type[Message], binary: bool) -> bytes:
    """The JSON Schema of ``msg_type`` as UTF-8 bytes: an object at the root, as Foxglove
    wants, with nested types under ``$defs``. ``binary``: array fields travel as MessagePack
    ``bin`` (bulk types) rather than JSON lists."""
    raw = msgspec.json.schema(msg_type, schema_hook=_hook(binary))
    defs: dict[str, Any] = dict(raw.get("$defs", {}))
    root_name = raw["$ref"].rsplit("/", 1)[-1] if "$ref" in raw else None
    root: dict[str, Any] = dict(defs.pop(root_name)) if root_name else dict(raw)
    root["title"] = codec_for(msg_type).type_name
    root["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    if defs:
        # the root's own name may still be referenced by a nested field (recursive types)
        if root_name and f'"#/$defs/{root_name}"' in json.dumps(defs):
            defs[root_name] = dict(root)
        root["$defs"] = defs
    return json.dumps(_nullable_numbers(root), separators=(",", ":")).encode()


def schema_for(type_name: str) -> tuple[str, bytes]:
    """(MCAP schema encoding, schema data) for a wire type name; an unknown type gets no
    schema (encoding ``""``, empty data), so its channel is still recorded."""
    try:
        msg_type = lookup_type(type_name)
    except (KeyError, LookupError):
        return "", b""
    return "jsonschema", schema_of_type(msg_type, codec_for(msg_type).bulk)
