"""The ROS 2 wheels as a reference: rclpy's serializer, the wheels' message classes and their
type-description JSON; and a value generator that fills any definition with varied values."""

from __future__ import annotations

import importlib
import json
import os
import random
import struct
import sys
import warnings
from pathlib import Path
from typing import Any

import pytest
from zenros.ros2.idl import EMPTY_FIELD, PRIMITIVES, FieldType
from zenros.ros2.registry import definition, zenros_class_of

SHARE = Path(sys.prefix) / "share"

try:
    from rclpy.serialization import deserialize_message, serialize_message  # noqa: F401
    with warnings.catch_warnings():  # lark (rosidl's parser) imports the deprecated sre_parse
        warnings.simplefilter("ignore", DeprecationWarning)
        import rosidl_generator_py  # noqa: F401
    HAVE_RCLPY = True
except ImportError:  # pragma: no cover - the wheels are optional
    HAVE_RCLPY = False

needs_wheels = pytest.mark.skipif(
    not HAVE_RCLPY,
    reason="ROS 2 wheels not installed (pip install -e '.[ros2]', see docs/ros2.md)",
)


def has_wheel(ros_name: str) -> bool:
    pkg, kind, name = ros_name.split("/")
    base = name.split("_", 1)[0]
    return (SHARE / pkg / kind / f"{base}.json").exists()


def wheel_json(ros_name: str) -> dict[str, Any]:
    pkg, kind, name = ros_name.split("/")
    data: dict[str, Any] = json.loads((SHARE / pkg / kind / f"{name}.json").read_text())
    return data


def wheel_hash(ros_name: str) -> str:
    """The wheel's RIHS01 hash of ros_name (looked up in the file of its interface)."""
    pkg, kind, name = ros_name.split("/")
    base = name.split("_", 1)[0]
    for h in wheel_json(f"{pkg}/{kind}/{base}")["type_hashes"]:
        if h["type_name"] == ros_name:
            return str(h["hash_string"])
    raise KeyError(ros_name)


_ACTION_PARTS = {
    "SendGoal_Request": ("Impl", "SendGoalService", "Request"),
    "SendGoal_Response": ("Impl", "SendGoalService", "Response"),
    "GetResult_Request": ("Impl", "GetResultService", "Request"),
    "GetResult_Response": ("Impl", "GetResultService", "Response"),
    "FeedbackMessage": ("Impl", "FeedbackMessage"),
    "Goal": ("Goal",), "Result": ("Result",), "Feedback": ("Feedback",),
}


def ros_class(ros_name: str) -> Any:
    """The rclpy message class of a ROS 2 structure name (service and action parts too)."""
    pkg, kind, name = ros_name.split("/")
    mod = importlib.import_module(f"{pkg}.{kind}")
    if kind == "msg":
        return getattr(mod, name)
    base, _, part = name.partition("_")
    obj = getattr(mod, base)
    path = _ACTION_PARTS[part] if kind == "action" else (part,)
    for attr in path:
        obj = getattr(obj, attr)
    return obj


# ------------------------------------------------------------------ values

_INT_RANGES = {
    "int8": (-128, 127), "uint8": (0, 255), "byte": (0, 255), "char": (0, 255),
    "int16": (-32768, 32767), "uint16": (0, 65535), "int32": (-2**31, 2**31 - 1),
    "uint32": (0, 2**32 - 1), "int64": (-2**63, 2**63 - 1), "uint64": (0, 2**64 - 1),
}


def _scalar(base: str, rnd: random.Random) -> Any:
    if base == "bool":
        return rnd.random() < 0.6
    if base in _INT_RANGES:
        lo, hi = _INT_RANGES[base]
        return rnd.choice([lo, hi, rnd.randint(lo, hi), 1])
    if base == "float32":
        return struct.unpack("<f", struct.pack("<f", rnd.uniform(-1e6, 1e6)))[0]
    if base == "float64":
        return rnd.choice([rnd.uniform(-1e9, 1e9), -0.0, 1e-300, 3.25])
    raise AssertionError(base)


def _string(rnd: random.Random, bound: int) -> str:
    s = rnd.choice(["", "a", "base_link", "héllo wörld ✓", "x" * 37, "odom/child"])
    return s[:bound] if bound else s


def value_of(t: FieldType, rnd: random.Random, empty: bool = False) -> Any:
    """A value of field type ``t`` as plain data (dicts for structures)."""
    if t.kind == "single":
        return _one(t, rnd, empty)
    if t.kind == "array":
        n = t.size
    elif empty:
        n = 0
    else:
        n = rnd.randint(1, min(t.size, 4)) if t.kind == "bounded" else rnd.randint(0, 4)
    return [_one(t, rnd, empty) for _ in range(n)]


def _one(t: FieldType, rnd: random.Random, empty: bool) -> Any:
    if t.is_nested:
        return values_of(t.base, rnd, empty)
    if t.is_string:
        return "" if empty else _string(rnd, t.string_bound)
    if empty:
        return False if t.base == "bool" else 0
    return _scalar(t.base, rnd)


# Fields whose zenros class narrows the ROS range (zenros refuses other values at decode)
NARROWED = {("action_msgs/msg/GoalStatus", "status"): (0, 6)}


def values_of(ros_name: str, rnd: random.Random, empty: bool = False) -> dict[str, Any]:
    values = {f.name: 0 if f == EMPTY_FIELD else value_of(f.type, rnd, empty)
              for f in definition(ros_name).fields}
    for (name, field), (lo, hi) in NARROWED.items():
        if name == ros_name and not empty:
            values[field] = rnd.randint(lo, hi)
    return values


def ros_message(ros_name: str, values: dict[str, Any]) -> Any:
    """Build the rclpy message of ``ros_name`` from plain values."""
    msg = ros_class(ros_name)()
    for f in definition(ros_name).fields:
        if f.name == EMPTY_FIELD.name:
            continue  # rclpy's classes of empty structures do not show it
        v = values[f.name]
        t = f.type
        if t.is_nested:
            v = (ros_message(t.base, v) if t.kind == "single"
                 else [ros_message(t.base, x) for x in v])
        elif t.base == "byte":
            v = bytes([v]) if t.kind == "single" else [bytes([x]) for x in v]
        setattr(msg, f.name, v)
    return msg


def zenros_values(ros_name: str, values: dict[str, Any]) -> dict[str, Any]:
    """Plain values as zenros's classes take them: an empty structure's placeholder member
    left out where zenros has a class for it (its classes of empty structures have no
    fields); lists of numbers for bytes fields are converted by `from_builtins` itself."""
    out: dict[str, Any] = {}
    cls = zenros_class_of(ros_name)
    for f in definition(ros_name).fields:
        if f == EMPTY_FIELD and cls is not None:
            continue
        v = values[f.name]
        t = f.type
        if t.is_nested:
            v = zenros_values(t.base, v) if t.kind == "single" else [
                zenros_values(t.base, x) for x in v]
        out[f.name] = v
    return out


def ament_env() -> dict[str, str]:
    return {**os.environ, "AMENT_PREFIX_PATH": sys.prefix}


def padding(ros_name: str, values: dict[str, Any]) -> set[int]:
    """Offsets (from the start of the payload, header included) of the CDR alignment padding
    of ``values``: a plain walk of the definition, independent of the codec's generator."""
    pads: set[int] = set()

    def align(off: int, n: int) -> int:
        while (off - 4) % n:
            pads.add(off)
            off += 1
        return off

    def one(t: FieldType, v: Any, off: int) -> int:
        if t.is_nested:
            return struct_(t.base, v, off)
        if t.is_string:
            return align(off, 4) + 4 + len(v.encode()) + 1
        size = PRIMITIVES[t.base][1]
        return align(off, size) + size

    def struct_(name: str, vals: dict[str, Any], off: int) -> int:
        for f in definition(name).fields:
            v = vals[f.name]
            if f.type.kind == "single":
                off = one(f.type, v, off)
                continue
            if f.type.kind != "array":
                off = align(off, 4) + 4
            for x in v:
                off = one(f.type, x, off)
        return off

    struct_(ros_name, values, 4)
    return pads


def same_but_padding(mine: bytes, ref: bytes, pads: set[int]) -> bool:
    """Equal outside the padding, which rclpy (rmw_fastrtps) leaves uninitialised, as it does
    the few bytes it may send past the end (its buffer is sized by an upper estimate that
    aligns empty sequences and counts bounded ones at their bound); ours is zero and stops
    at the last field."""
    if len(ref) < len(mine):
        return False
    if any(mine[i] for i in pads):
        return False
    return all(a == b for i, (a, b) in enumerate(zip(mine, ref[:len(mine)], strict=True))
               if i not in pads)
