"""`zenros interface`: every type zenros holds listed and shown (the CLI as a user runs it),
and each shown ROS 2 type's fields equal the ROS 2 wheels' (`rosidl_parser`-free: the
wheels' message classes' field names and types) where the `ros2` extra is installed."""

from __future__ import annotations

import subprocess
import sys

import pytest
from zenros.cli.interface import interface_names, show_lines


def zenros(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "zenros.cli", "interface", *args],
                          capture_output=True, text=True, timeout=60, check=False)


def test_show_expands_nested_types_as_ros2_interface_show() -> None:
    r = zenros("show", "sensor_msgs/msg/LaserScan")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[:5] == ["std_msgs/Header header", "\tbuiltin_interfaces/Time stamp",
                         "\t\tint32 sec", "\t\tuint32 nanosec", "\tstring frame_id"]
    assert lines[-2:] == ["float32[] ranges", "float32[] intensities"]
    assert zenros("show", "sensor_msgs/msg/LaserScan", "--no-expand").stdout.splitlines()[:2] \
        == ["std_msgs/Header header", "float32 angle_min"]


def test_services_and_actions_show_their_parts_and_short_names_resolve() -> None:
    assert show_lines("std_srvs/SetBool") == [
        "bool data", "---", "bool success", "string message"]
    assert show_lines("test_msgs/action/Fibonacci") == [  # loaded on demand
        "int32 order", "---", "int32[] sequence", "---", "int32[] sequence"]
    assert "geometry_msgs/PoseStamped pose" in show_lines("nav2_msgs/action/NavigateToPose")


def test_a_zenros_only_type_says_so() -> None:
    lines = show_lines("zenros_msgs/srv/TaskCommand")
    assert lines[0] == "string id" and lines[1] == "---"
    assert "zenros only, no ROS 2 form" in lines[2] and "Task | None task" in lines


def test_list_names_every_type_and_each_shows() -> None:
    from zenros.msgs.std_srvs import SetBool
    from zenros.service_events import event_type_of

    event_type_of(SetBool)  # a service's _Event (introspection) is not listed as a message
    r = zenros("list")
    assert r.returncode == 0, r.stderr
    out = r.stdout.splitlines()
    assert out[0] == "Messages:" and "Services:" in out and "Actions:" in out
    assert "    test_msgs/action/Fibonacci" in out and "    std_srvs/srv/SetBool" in out
    assert "    std_srvs/srv/SetBool_Request" not in out  # a service's part, not a message
    names = interface_names()
    for kind in names.values():
        for name in kind:  # each shows (an empty message, std_msgs/Empty, shows nothing)
            assert show_lines(name) or name in ("std_msgs/msg/Empty",
                                                "rcl_interfaces/msg/ParameterType",
                                                "test_msgs/msg/Constants",
                                                "test_msgs/msg/Empty",
                                                "example_interfaces/msg/Empty"), name
    assert zenros("list", "-a").stdout.splitlines()[0] == "Actions:"
    assert "std_msgs" in zenros("packages").stdout.split()
    assert "std_msgs/msg/String" in zenros("package", "std_msgs").stdout.split()


@pytest.mark.parametrize("args, needle", [
    (["show", "nope/Thing"], "unknown interface 'nope/Thing'"),
    (["show", "std_msgs/msg/Nope"], "Nope"),
    (["package", "nope"], "no package 'nope'"),
])
def test_unknown_names_are_one_clear_line(args: list[str], needle: str) -> None:
    r = zenros(*args)
    assert r.returncode == 1 and needle in r.stderr and "Traceback" not in r.stderr


def test_ros2_types_match_the_wheels_field_for_field() -> None:
    pytest.importorskip("rclpy", reason="ROS 2 wheels not installed (extra ros2)")
    import importlib

    checked = 0
    for name in interface_names()["msg"]:
        pkg, _, short = name.split("/")
        try:
            cls = getattr(importlib.import_module(f"{pkg}.msg"), short)
        except (ImportError, AttributeError):
            continue  # a package or type the wheels do not have (zenros_msgs, nav2_msgs...)
        ours = [ln.split(" ")[1] for ln in show_lines(name, expand=False)]
        assert ours == list(cls.get_fields_and_field_types()), name
        checked += 1
    assert checked >= 30
