"""zenros's standard types against a second, independent reference that needs no ROS 2
install: rosbags (pure Python, its ``ros2_kilted`` type store and CDR codec). For every
message type the store and zenros share: the same fields in the same order, and CDR bytes
that rosbags reads back to the same values and writes again byte for byte."""

from __future__ import annotations

import random
from typing import Any

import pytest
from rosref import values_of, zenros_values
from zenros.action import types as _action_types  # noqa: F401 (action_msgs, UUID)
from zenros.codec import from_builtins
from zenros.registry import load_all_packages
from zenros.ros2 import cdr_codec
from zenros.ros2.registry import definition, zenros_class_of

rosbags_typesys = pytest.importorskip("rosbags.typesys", reason="rosbags not installed "
                                      "(pip install -e '.[test]')")

STORE = rosbags_typesys.get_typestore(rosbags_typesys.Stores.ROS2_KILTED)
_BASE, _NAME, _ARRAY, _SEQUENCE = 1, 2, 3, 4  # rosbags' Nodetype values


def _shared() -> list[str]:
    load_all_packages()
    return sorted(n for n in STORE.types if zenros_class_of(n) is not None)


SHARED = _shared()


def _type_text(node: Any) -> str:
    kind, detail = node
    if kind == _BASE:
        base, bound = detail
        return f"{base}<={bound}" if bound else base
    if kind == _NAME:
        return detail
    inner, size = detail
    text = _type_text(inner)
    if kind == _ARRAY:
        return f"{text}[{size}]"
    return f"{text}[<={size}]" if size else f"{text}[]"


def _ours(name: str) -> list[tuple[str, str]]:
    out = []
    for f in definition(name).fields:
        t = f.type
        base = t.base + (f"<={t.string_bound}" if t.string_bound else "")
        suffix = {"single": "", "array": f"[{t.size}]", "bounded": f"[<={t.size}]",
                  "sequence": "[]"}[t.kind]
        out.append((f.name, base + suffix))
    return out


def test_the_store_and_zenros_share_the_standard_types() -> None:
    assert len(SHARED) >= 140
    for name in ("sensor_msgs/msg/Image", "sensor_msgs/msg/PointCloud2",
                 "visualization_msgs/msg/Marker", "trajectory_msgs/msg/JointTrajectory",
                 "std_msgs/msg/Float64MultiArray", "geometry_msgs/msg/WrenchStamped"):
        assert name in SHARED


@pytest.mark.parametrize("name", SHARED)
def test_fields_match_the_store(name: str) -> None:
    _, fields = STORE.fielddefs[name]
    theirs = [(fname, _type_text(node)) for fname, node in fields]
    if not theirs:  # rosbags lists an empty structure without its placeholder member
        theirs = [("structure_needs_at_least_one_member", "uint8")]
    assert _ours(name) == theirs


@pytest.mark.parametrize("seed", [1, 2])
@pytest.mark.parametrize("name", SHARED)
def test_rosbags_reads_zenros_cdr_and_writes_the_same_bytes(name: str, seed: int) -> None:
    cls = zenros_class_of(name)
    assert cls is not None
    values = zenros_values(name, values_of(name, random.Random(f"{name}{seed}"),
                                           empty=seed == 2))
    fields = set(cls.__struct_fields__)
    msg = from_builtins({k: v for k, v in values.items() if k in fields}, cls)
    ours = cdr_codec(cls).encode(msg)
    theirs = STORE.deserialize_cdr(ours, name)
    assert bytes(STORE.serialize_cdr(theirs, name)) == ours
    assert cdr_codec(cls).decode(STORE.serialize_cdr(theirs, name)) == msg
