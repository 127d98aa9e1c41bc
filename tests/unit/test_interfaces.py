"""`zenros.interfaces`: .msg/.srv/.action files made into zenros types, at run time and as a
generated module, with ROS's value syntax for constants and defaults."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import uuid
from pathlib import Path

import numpy as np
import pytest
from zenros.codec import from_builtins
from zenros.errors import UnknownTypeError
from zenros.interfaces import load_interface_package, parse_interface
from zenros.interfaces.values import parse_value
from zenros.registry import lookup_action, lookup_service, lookup_type
from zenros.ros2 import cdr_codec, type_hash
from zenros.ros2.idl import FieldType, InterfaceError

GRIPPER = """# The state of a two-finger gripper.
uint8 OPEN=0
uint8 CLOSED=1
string NAME_PREFIX="g#1"   # a string constant with a hash in it
std_msgs/Header header
uint8 state 1
float32 width 0.085   # metres
float64[3] force [1.5, -2, 3e2]
string<=16 name 'le"ft'
int16[<=4] ticks [1, 2]
bool[] flags
geometry_msgs/Pose tcp
Finger[2] fingers
uint8[] raw
"""
FINGER = "float64 position\nstring label"


def _package(root: Path, name: str) -> Path:
    pkg = root / name
    for kind in ("msg", "srv", "action"):
        (pkg / kind).mkdir(parents=True)
    (pkg / "msg" / "Gripper.msg").write_text(GRIPPER)
    (pkg / "msg" / "Finger.msg").write_text(FINGER)
    (pkg / "srv" / "SetGripper.srv").write_text("uint8 state\nGripper gripper\n---\n"
                                                "bool success\nstring message")
    (pkg / "action" / "Grasp.action").write_text("string object_id\n---\nbool grasped\n"
                                                 "---\nfloat32 progress")
    (pkg / "package.xml").write_text(f"<package><name>{name}</name></package>")
    return pkg


def _unique() -> str:
    return f"test_pkg_{uuid.uuid4().hex[:8]}_msgs"


# ---------------------------------------------------------------- values


@pytest.mark.parametrize(("type_", "text", "value"), [
    (FieldType("int8"), "-128", -128),
    (FieldType("uint8"), "0x10", 16),
    (FieldType("bool"), "true", True),
    (FieldType("bool"), "0", False),
    (FieldType("float32"), "1.5e3  # comment", 1500.0),
    (FieldType("string"), '"a # b"  # comment', "a # b"),
    (FieldType("string"), "plain text # comment", "plain text"),
    (FieldType("string"), r"'it\'s'", "it's"),
    (FieldType("int32", "array", 3), "[1, 2, 3]", [1, 2, 3]),
    (FieldType("string", "bounded", 3), '["a,b", \'c]\']', ["a,b", "c]"]),
    (FieldType("float64", "sequence"), "[]", []),
])
def test_values_parse_as_rosidl_reads_them(type_: FieldType, text: str, value: object) -> None:
    assert parse_value(type_, text, "x") == value


@pytest.mark.parametrize(("type_", "text", "error"), [
    (FieldType("uint8"), "256", "out of uint8's range"),
    (FieldType("int8"), "1.5", "not an integer"),
    (FieldType("bool"), "yes", "not a bool"),
    (FieldType("float32"), "1e39", "float32's range"),
    (FieldType("int32", "array", 3), "[1, 2]", "takes 3 values"),
    (FieldType("int32", "bounded", 1), "[1, 2]", "at most 1"),
    (FieldType("string", string_bound=2), '"abc"', "longer than 2"),
    (FieldType("string"), '"open', "no closing"),
    (FieldType("string"), '"a" b', "unexpected text"),
    (FieldType("int32"), "5 6", "not an integer"),
])
def test_bad_values_are_named(type_: FieldType, text: str, error: str) -> None:
    with pytest.raises(InterfaceError, match=error):
        parse_value(type_, text, "pkg/msg/X line 3")


def test_interface_files_parse_with_constants_defaults_and_description() -> None:
    spec = parse_interface("my_msgs/msg/Gripper", GRIPPER)
    (s,) = spec.parts
    assert s.doc == "The state of a two-finger gripper."
    assert [(c.name, c.value) for c in s.constants] == [
        ("OPEN", 0), ("CLOSED", 1), ("NAME_PREFIX", "g#1")]
    defaults = {f.name: f.default for f in s.fields if f.has_default}
    assert defaults == {"state": 1, "width": 0.085, "force": [1.5, -2.0, 300.0],
                        "name": 'le"ft', "ticks": [1, 2]}
    assert [f.name for f in s.fields][:2] == ["header", "state"]
    srv = parse_interface("my_msgs/srv/S", "int32 a\n---\nint32 b")
    assert [p.ros_name for p in srv.parts] == ["my_msgs/srv/S_Request", "my_msgs/srv/S_Response"]


@pytest.mark.parametrize(("name", "text", "error"), [
    ("my_msgs/msg/X", "int32 lower=1", "upper case"),
    ("my_msgs/msg/X", "geometry_msgs/Pose P=1", "primitive or a string"),
    ("my_msgs/msg/X", "int32 a\nint32 a", "declared twice"),
    ("my_msgs/msg/X", "int32 Bad", "bad field name"),
    ("My-msgs/msg/X", "int32 a", "bad package name"),
    ("my_msgs/msg/lower", "int32 a", "bad type name"),
    ("my_msgs/srv/X", "int32 a", "expected 2 parts"),
    ("my_msgs/msg/X", "int32[<=] a", "bounded sequence without a bound"),
])
def test_malformed_files_are_refused_with_the_line(name: str, text: str, error: str) -> None:
    with pytest.raises(InterfaceError, match=error):
        parse_interface(name, text)


# ---------------------------------------------------------------- made at run time


def test_a_package_loads_into_types_every_tool_finds(tmp_path: Path) -> None:
    name = _unique()
    load_interface_package(_package(tmp_path, name))
    Gripper = lookup_type(f"{name}/msg/Gripper")
    g = Gripper()
    assert (g.state, g.name, list(g.force), g.ticks, Gripper.CLOSED) == (
        1, 'le"ft', [1.5, -2.0, 300.0], [1, 2], 1)
    assert len(g.fingers) == 2 and g.raw.size == 0 and g.raw.dtype == np.uint8
    srv = lookup_service(f"{name}/srv/SetGripper")
    act = lookup_action(f"{name}/action/Grasp")
    assert srv.Request().gripper.width == pytest.approx(0.085)
    assert act.Feedback().progress == 0.0
    # CDR both ways, and RIHS01 hashes for the message, the service and the action
    msg = from_builtins({"state": 2, "width": 0.5, "raw": [1, 2, 255], "fingers": [
        {"position": 0.5, "label": "l"}, {"position": -0.5, "label": "r"}]}, Gripper)
    codec = cdr_codec(Gripper)
    assert codec.decode(codec.encode(msg)) == msg
    for n in (f"{name}/msg/Gripper", f"{name}/srv/SetGripper", f"{name}/action/Grasp"):
        assert type_hash(n).startswith("RIHS01_")
    # a second load of the same folder is a no-op; bad input to the type is refused
    load_interface_package(tmp_path / name)
    with pytest.raises(Exception, match="state"):
        from_builtins({"state": 300}, Gripper)


def test_a_package_nesting_an_unknown_type_or_shadowing_a_shipped_one_is_refused(
        tmp_path: Path) -> None:
    bad = tmp_path / _unique()
    (bad / "msg").mkdir(parents=True)
    (bad / "msg" / "A.msg").write_text("other_pkg_xyz/Thing t")
    with pytest.raises(InterfaceError, match="other_pkg_xyz/msg/Thing is not defined"):
        load_interface_package(bad)
    shadow = tmp_path / "std_msgs"
    (shadow / "msg").mkdir(parents=True)
    (shadow / "msg" / "String.msg").write_text("string data")
    with pytest.raises(InterfaceError, match="defined already"):
        load_interface_package(shadow)


# ---------------------------------------------------------------- the CLI and the path


def _cli(*args: str, env: dict[str, str] | None = None,
         cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "zenros.cli", *args], capture_output=True,
                          text=True, timeout=60, check=False, env=env, cwd=cwd)


def test_zenros_interface_path_makes_a_package_known_to_every_tool(tmp_path: Path) -> None:
    name = _unique()
    _package(tmp_path / "src", name)
    env = {**os.environ, "ZENROS_INTERFACE_PATH": str(tmp_path / "src")}
    r = _cli("interface", "show", f"{name}/srv/SetGripper", "--no-expand", env=env)
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines() == ["uint8 state", "Gripper gripper", "---", "bool success",
                                     "string message"]
    listed = _cli("interface", "package", name, env=env)
    assert f"{name}/action/Grasp" in listed.stdout.split()
    unknown = _cli("interface", "show", f"{name}/msg/Nope", env=env)
    assert unknown.returncode != 0 and "unknown" in unknown.stderr


def test_generate_writes_a_module_that_imports_and_matches_the_loaded_types(
        tmp_path: Path) -> None:
    name = _unique()
    _package(tmp_path / "src", name)
    r = _cli("interface", "generate", str(tmp_path / "src"), "-o", str(tmp_path / "out"))
    assert r.returncode == 0, r.stderr
    module = tmp_path / "out" / f"{name}.py"
    assert r.stdout.split() == [str(module)]
    source = module.read_text()
    assert "class Gripper(Message):" in source and f'"{name}/Gripper"' in source
    # the module's hashes equal those of the same package loaded from its files
    script = (f"import json, {name} as m\n"
              "from zenros.ros2 import type_hash\n"
              f"print(json.dumps([type_hash('{name}/msg/Gripper'), "
              f"type_hash('{name}/srv/SetGripper'), m.Gripper.CLOSED, m.Gripper().name]))")
    ran = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                         timeout=60, check=False,
                         env={**os.environ, "PYTHONPATH": str(tmp_path / "out")})
    assert ran.returncode == 0, ran.stderr
    loaded = _unique()
    _package(tmp_path / "again", loaded)
    load_interface_package(tmp_path / "again" / loaded)
    hashes = json.loads(ran.stdout)
    assert hashes[2:] == [1, 'le"ft']
    # same text, other package name: the hashes differ only through the name
    assert hashes[0] != type_hash(f"{loaded}/msg/Gripper")
    bad = _cli("interface", "generate", str(tmp_path / "nowhere"))
    assert bad.returncode != 0 and "no such folder" in bad.stderr


def test_unknown_names_stay_unknown_with_a_path_set(tmp_path: Path) -> None:
    os.environ["ZENROS_INTERFACE_PATH"] = str(tmp_path)
    try:
        with pytest.raises(UnknownTypeError):
            lookup_type(f"{_unique()}/msg/Thing")
    finally:
        del os.environ["ZENROS_INTERFACE_PATH"]
