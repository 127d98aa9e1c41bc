"""REP 2011 type descriptions and their RIHS01 hashes, from zenros's own definitions.

The hash is SHA-256 over the type description in canonical JSON: the type and every type it
references (sorted by name), each field as name and type (type_id, capacity, string_capacity,
nested_type_name), default values left out, separators ``', '`` and ``': '``, keys in order.
"""

from __future__ import annotations

import hashlib
import json
from functools import cache
from typing import Any

from .idl import FieldType, MsgDef
from .registry import definition

__all__ = ["field_type_id", "type_description", "type_hash"]

_SCALAR_IDS = {
    "int8": 2, "uint8": 3, "int16": 4, "uint16": 5, "int32": 6, "uint32": 7, "int64": 8,
    "uint64": 9, "float32": 10, "float64": 11, "char": 3, "bool": 15, "byte": 16,
}
_KIND_OFFSET = {"single": 0, "array": 48, "bounded": 96, "sequence": 144}


def field_type_id(t: FieldType) -> int:
    """type_description_interfaces/FieldType's id of a field type."""
    if t.is_nested:
        base = 1
    elif t.is_string:
        wide = t.base == "wstring"
        base = (22 if wide else 21) if t.string_bound else (18 if wide else 17)
    else:
        base = _SCALAR_IDS[t.base]
    return base + _KIND_OFFSET[t.kind]


def _individual(d: MsgDef) -> dict[str, Any]:
    return {
        "type_name": d.name,
        "fields": [
            {
                "name": f.name,
                "type": {
                    "type_id": field_type_id(f.type),
                    "capacity": f.type.size if f.type.kind in ("array", "bounded") else 0,
                    "string_capacity": f.type.string_bound,
                    "nested_type_name": f.type.base if f.type.is_nested else "",
                },
            }
            for f in d.fields
        ],
    }


@cache
def _references(name: str) -> frozenset[str]:
    out: set[str] = set()
    queue = [f.type.base for f in definition(name).fields if f.type.is_nested]
    while queue:
        n = queue.pop()
        if n not in out:
            out.add(n)
            queue.extend(f.type.base for f in definition(n).fields if f.type.is_nested)
    return frozenset(out)


def type_description(name: str) -> dict[str, Any]:
    """The hashable type description of ``name`` (``pkg/msg/Name``; no default values)."""
    return {
        "type_description": _individual(definition(name)),
        "referenced_type_descriptions": [
            _individual(definition(n)) for n in sorted(_references(name))
        ],
    }


@cache
def type_hash(name: str) -> str:
    """``RIHS01_<64 hex>`` of a ROS 2 type (message, service or action) name."""
    text = json.dumps(type_description(name), ensure_ascii=True, allow_nan=False,
                      separators=(", ", ": "), sort_keys=False)
    return "RIHS01_" + hashlib.sha256(text.encode()).hexdigest()
