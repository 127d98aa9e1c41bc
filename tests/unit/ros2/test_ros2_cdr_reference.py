"""zenros's CDR codec and RIHS01 hashes against the ROS 2 wheels (rclpy's serializer and the
type descriptions rosidl generated): byte for byte, both ways, for every zenros type that has
an interface wheel, and for the test_msgs types that exercise every CDR feature."""

from __future__ import annotations

import random
from typing import Any

import pytest
from rosref import (
    SHARE,
    has_wheel,
    needs_wheels,
    padding,
    ros_class,
    ros_message,
    same_but_padding,
    values_of,
    wheel_hash,
    zenros_values,
)
from zenros.codec import from_builtins
from zenros.registry import load_all_packages, registered_types
from zenros.ros2 import cdr_codec, ros_name_of, type_hash
from zenros.ros2.cdr import cdr_codec_for_name
from zenros.ros2.definitions import ACTIONS, MESSAGES, SERVICES
from zenros.ros2.registry import definition, register_interface

pytestmark = needs_wheels


def _zenros_types() -> list[tuple[str, type[Any]]]:
    load_all_packages()  # the same list whatever a worker imported before
    out = []
    for cls in set(registered_types().values()):
        name = ros_name_of(cls)
        if has_wheel(name) and name not in NO_CDR:
            out.append((name, cls))
    return sorted(out, key=lambda nc: nc[0])


NO_CDR = {"test_msgs/msg/WStrings"}  # wstring: zenros's CDR codec does not carry it
ZENROS_TYPES = _zenros_types()


def _serialize(ros_msg: Any) -> bytes:
    from rclpy.serialization import serialize_message
    data: bytes = serialize_message(ros_msg)
    return data


def _deserialize(data: bytes, ros_name: str) -> Any:
    from rclpy.serialization import deserialize_message
    return deserialize_message(data, ros_class(ros_name))


def test_every_zenros_type_with_a_wheel_is_covered() -> None:
    names = {n for n, _ in ZENROS_TYPES}
    for expected in ("std_msgs/msg/String", "geometry_msgs/msg/Twist", "sensor_msgs/msg/LaserScan",
                     "nav_msgs/msg/OccupancyGrid", "std_srvs/srv/SetBool_Request",
                     "rcl_interfaces/msg/Log", "rosgraph_msgs/msg/Clock",
                     "builtin_interfaces/msg/Time"):
        assert expected in names
    assert len(names) >= 45


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize(("ros_name", "cls"), ZENROS_TYPES, ids=[n for n, _ in ZENROS_TYPES])
def test_zenros_type_matches_rclpy_bytes(ros_name: str, cls: type[Any], seed: int) -> None:
    rnd = random.Random(f"{ros_name}{seed}")
    values = values_of(ros_name, rnd, empty=seed == 3)
    ours = from_builtins(_only_fields(zenros_values(ros_name, values), cls), cls)
    theirs = ros_message(ros_name, values)
    codec = cdr_codec(cls)
    ref = _serialize(theirs)
    mine = codec.encode(ours)
    assert same_but_padding(mine, ref, padding(ros_name, values)), \
        f"{ros_name}\nzenros {mine.hex()}\nrclpy  {ref.hex()}"
    assert codec.decode(ref) == ours
    assert _deserialize(mine, ros_name) == theirs


def _only_fields(values: dict[str, Any], cls: type[Any]) -> dict[str, Any]:
    """The zenros class holds every ROS field of the standard types (the definition check)."""
    assert set(values) <= set(cls.__struct_fields__) or values.keys() == {
        "structure_needs_at_least_one_member"}, (cls, set(values) - set(cls.__struct_fields__))
    return {k: v for k, v in values.items() if k in cls.__struct_fields__}


# ---------------------------------------------------------------- hashes


def _defined_with_wheel() -> list[str]:
    names = list(MESSAGES) + list(SERVICES) + list(ACTIONS)
    parts = []
    for n in names:
        if n.split("/")[1] == "srv":
            parts += [f"{n}_Request", f"{n}_Response", f"{n}_Event"]
    return sorted(n for n in names + parts if has_wheel(n))


@pytest.mark.parametrize("ros_name", _defined_with_wheel())
def test_type_hash_matches_the_wheel(ros_name: str) -> None:
    assert type_hash(ros_name) == wheel_hash(ros_name)


def test_hash_coverage() -> None:
    covered = _defined_with_wheel()
    assert len(covered) >= 50
    assert "std_srvs/srv/SetBool" in covered and "action_msgs/srv/CancelGoal" in covered


# ---------------------------------------------------------------- test_msgs: every CDR feature

TEST_MSGS = ["Arrays", "BasicTypes", "BoundedPlainSequences", "BoundedSequences", "Builtins",
             "Constants", "Defaults", "Empty", "MultiNested", "Nested", "Strings",
             "UnboundedSequences"]


@pytest.fixture(scope="module", autouse=True)
def _test_msgs() -> None:
    """Register test_msgs from the wheel's own .msg/.srv/.action texts."""
    for kind, ext in (("msg", "msg"), ("srv", "srv"), ("action", "action")):
        for p in sorted((SHARE / "test_msgs" / kind).glob(f"*.{ext}")):
            if p.stem in ("WStrings",):
                continue  # wstring: not supported by zenros's codec
            register_interface(f"test_msgs/{kind}/{p.stem}", p.read_text())


def _test_msgs_names() -> list[str]:
    out = [f"test_msgs/msg/{n}" for n in TEST_MSGS]
    for srv in ("Arrays", "BasicTypes", "Empty"):
        out += [f"test_msgs/srv/{srv}_Request", f"test_msgs/srv/{srv}_Response"]
    out += [f"test_msgs/action/Fibonacci_{p}" for p in (
        "Goal", "Result", "Feedback", "SendGoal_Request", "SendGoal_Response",
        "GetResult_Request", "GetResult_Response", "FeedbackMessage")]
    return out


@pytest.mark.parametrize("seed", [1, 2, 3, 4])
@pytest.mark.parametrize("ros_name", _test_msgs_names())
def test_test_msgs_match_rclpy_bytes(ros_name: str, seed: int) -> None:
    rnd = random.Random(f"{ros_name}{seed}")
    values = values_of(ros_name, rnd, empty=seed == 4)
    codec = cdr_codec_for_name(ros_name)
    ours = from_builtins(zenros_values(ros_name, values), codec.type)
    theirs = ros_message(ros_name, values)
    ref = _serialize(theirs)
    mine = codec.encode(ours)
    assert same_but_padding(mine, ref, padding(ros_name, values)), \
        f"{ros_name}\nzenros {mine.hex()}\nrclpy  {ref.hex()}"
    assert codec.decode(ref) == ours
    assert _deserialize(mine, ros_name) == theirs


@pytest.mark.parametrize("ros_name", [*(f"test_msgs/msg/{n}" for n in TEST_MSGS),
                                      "test_msgs/srv/Arrays", "test_msgs/action/Fibonacci",
                                      "test_msgs/action/NestedMessage"])
def test_test_msgs_hashes(ros_name: str) -> None:
    assert definition(ros_name).name == ros_name
    assert type_hash(ros_name) == wheel_hash(ros_name)


# ---------------------------------------------------------------- every standard type

STANDARD_PACKAGES = ("builtin_interfaces", "std_msgs", "geometry_msgs", "sensor_msgs", "nav_msgs",
                     "diagnostic_msgs", "visualization_msgs", "trajectory_msgs", "shape_msgs",
                     "stereo_msgs", "action_msgs", "lifecycle_msgs", "unique_identifier_msgs",
                     "rosgraph_msgs", "std_srvs", "test_msgs", "rcl_interfaces",
                     "type_description_interfaces", "service_msgs")


def _wheel_interfaces() -> list[str]:
    out = []
    for pkg in STANDARD_PACKAGES:
        for kind in ("msg", "srv", "action"):
            out += [f"{pkg}/{kind}/{p.stem}" for p in sorted((SHARE / pkg / kind).glob(f"*.{kind}"))]
    return out


def test_every_standard_interface_of_the_wheels_is_a_zenros_type() -> None:
    """Each .msg/.srv/.action the interface wheels ship has a zenros type whose definition
    hashes as the wheel's (the byte-for-byte checks above then cover its CDR)."""
    import zenros.action  # noqa: F401 (action_msgs, unique_identifier_msgs)
    from zenros.registry import lookup_action, lookup_service, lookup_type

    names = _wheel_interfaces()
    assert len(names) >= 170
    for name in names:
        pkg, kind, short = name.split("/")
        if kind == "msg":
            lookup_type(name)
        else:
            (lookup_service if kind == "srv" else lookup_action)(f"{pkg}/{short}")
        if short != "WStrings":  # zenros's CDR has no wstring
            assert type_hash(name) == wheel_hash(name), name
