"""params: declared typed parameters, overrides, validation and change callbacks;
``name:=value`` arguments; ROS 2 params files."""

from __future__ import annotations

import textwrap
from pathlib import Path
from typing import Any

import pytest
from zenros.errors import (
    InvalidParameterValueError,
    ParameterAlreadyDeclaredError,
    ParameterError,
    ParameterNotDeclaredError,
)
from zenros.params import (
    Parameter,
    Parameters,
    SetParametersResult,
    flatten,
    load_params_file,
    parse_param_arg,
)

# ------------------------------------------------------------------ declare and get


def test_declare_returns_the_default_and_fixes_the_type() -> None:
    p = Parameters("/robot1/chassis")
    assert p.declare("wheel_base", 0.3) == 0.3
    assert p.get("wheel_base") == 0.3
    assert p.has("wheel_base") and not p.has("other")
    [param] = p.describe()
    assert param == Parameter("wheel_base", 0.3, float)


@pytest.mark.parametrize("default", [True, 3, 2.5, "text", b"raw", [1, 2], {"a": 1}])
def test_every_supported_type_can_be_declared(default: Any) -> None:
    p = Parameters("/n")
    assert p.declare("x", default) == default
    assert p.describe()[0].type is type(default)


@pytest.mark.parametrize("default", [None, object(), (1, 2), {1, 2}])
def test_unsupported_defaults_are_rejected(default: Any) -> None:
    with pytest.raises(InvalidParameterValueError, match="default must be"):
        Parameters("/n").declare("x", default)


@pytest.mark.parametrize("name", ["", "a b", "a*", "a/b", "$x", "a?", "a#"])
def test_invalid_parameter_names(name: str) -> None:
    with pytest.raises(ParameterError, match="invalid parameter name"):
        Parameters("/n").declare(name, 1)


def test_dotted_names_are_allowed() -> None:
    p = Parameters("/n")
    assert p.declare("limits.max_speed", 1.0) == 1.0


def test_double_declare_raises() -> None:
    p = Parameters("/n")
    p.declare("speed", 1.0)
    with pytest.raises(ParameterAlreadyDeclaredError, match="'speed' is already declared"):
        p.declare("speed", 2.0)
    assert p.get("speed") == 1.0


def test_undeclared_get_lists_declared_names() -> None:
    p = Parameters("/robot1/nav")
    p.declare("max_speed", 1.0)
    p.declare("inflation", 0.2)
    with pytest.raises(ParameterNotDeclaredError) as exc:
        p.get("max_sped")
    text = str(exc.value)
    assert "'max_sped'" in text and "/robot1/nav" in text
    assert "declared: inflation, max_speed" in text


def test_undeclared_get_on_empty_node_and_set() -> None:
    p = Parameters("/n")
    with pytest.raises(ParameterNotDeclaredError, match="declared: none"):
        p.get("x")
    with pytest.raises(ParameterNotDeclaredError):
        p.set("x", 1)
    with pytest.raises(LookupError):
        p.get("x")


# ------------------------------------------------------------------ overrides and coercion


def test_overrides_replace_defaults() -> None:
    p = Parameters("/n", {"speed": 2.5, "name": "bob", "enabled": False, "ids": [1, 2]})
    assert p.declare("speed", 1.0) == 2.5
    assert p.declare("name", "alice") == "bob"
    assert p.declare("enabled", True) is False
    assert p.declare("ids", []) == [1, 2]
    assert p.declare("untouched", 7) == 7


def test_int_override_of_float_is_coerced() -> None:
    p = Parameters("/n", {"speed": 2})
    value = p.declare("speed", 1.0)
    assert value == 2.0 and isinstance(value, float)


@pytest.mark.parametrize(
    ("default", "override", "expected_name", "got_name"),
    [(True, 1, "bool", "int"), (1, True, "int", "bool"), (1, 1.5, "int", "float"),
     (1.0, "fast", "float", "string"), (1.0, True, "float", "bool"), ("a", 1, "string", "int"),
     ([1], "1", "list", "string"), (1, None, "int", "NoneType")],
)
def test_wrongly_typed_override_names_parameter_expected_and_got(
    default: Any, override: Any, expected_name: str, got_name: str
) -> None:
    p = Parameters("/n", {"param_x": override})
    with pytest.raises(InvalidParameterValueError) as exc:
        p.declare("param_x", default)
    text = str(exc.value)
    assert "'param_x'" in text
    assert f"is {expected_name}, got {got_name} {override!r}" in text
    assert not p.has("param_x")


def test_invalid_parameter_value_is_a_type_error() -> None:
    p = Parameters("/n")
    p.declare("n", 1)
    with pytest.raises(TypeError):
        p.set("n", "one")


# ------------------------------------------------------------------ set


def test_set_changes_the_value_and_coerces_ints_to_floats() -> None:
    p = Parameters("/n")
    p.declare("speed", 1.0)
    p.set("speed", 3)
    assert p.get("speed") == 3.0 and isinstance(p.get("speed"), float)


@pytest.mark.parametrize(("default", "bad"), [(1, True), (True, 1), (True, 0), (1, 2.0), ("s", 1)])
def test_set_rejects_other_types(default: Any, bad: Any) -> None:
    p = Parameters("/n")
    p.declare("x", default)
    with pytest.raises(InvalidParameterValueError, match="parameter 'x' is"):
        p.set("x", bad)
    assert p.get("x") == default


def test_read_only_parameters_cannot_be_set() -> None:
    p = Parameters("/n", {"frame": "base"})
    assert p.declare("frame", "base_link", read_only=True) == "base"  # overrides still apply
    with pytest.raises(ParameterError, match="'frame' is read-only"):
        p.set("frame", "odom")
    assert p.get("frame") == "base"
    assert p.describe()[0].read_only


def test_description_and_read_only_survive_a_set() -> None:
    p = Parameters("/n")
    p.declare("x", 1, description="the x")
    p.set("x", 2)
    assert p.describe()[0] == Parameter("x", 2, int, "the x", False)


def test_validator_can_refuse_a_change() -> None:
    p = Parameters("/n")
    p.declare("speed", 1.0)
    seen: list[list[Parameter]] = []

    def validate(params: list[Parameter]) -> SetParametersResult:
        seen.append(params)
        ok = all(q.value <= 2.0 for q in params)
        return SetParametersResult(ok, "" if ok else "speed above 2.0")

    p.add_validator(validate)
    p.set("speed", 1.5)
    with pytest.raises(InvalidParameterValueError, match=r"'speed' refused: speed above 2\.0"):
        p.set("speed", 9.0)
    assert p.get("speed") == 1.5
    assert [q.value for batch in seen for q in batch] == [1.5, 9.0]


def test_validator_refusal_without_reason() -> None:
    p = Parameters("/n")
    p.declare("x", 1)
    p.add_validator(lambda params: SetParametersResult(False))
    with pytest.raises(InvalidParameterValueError, match="rejected by node"):
        p.set("x", 2)


def test_on_change_fires_only_on_change() -> None:
    p = Parameters("/n")
    p.declare("speed", 1.0)
    p.declare("name", "a")
    per_name: list[Any] = []
    everything: list[tuple[str, Any]] = []
    p.on_change(lambda q: per_name.append(q.value), "speed")
    p.on_change(lambda q: everything.append((q.name, q.value)))
    p.set("speed", 1.0)  # same value: no event
    p.set("speed", 1)  # 1 == 1.0 after coercion: no event
    p.set("speed", 2.0)
    p.set("name", "b")
    p.set("name", "b")
    assert per_name == [2.0]
    assert everything == [("speed", 2.0), ("name", "b")]


def test_refused_change_does_not_fire() -> None:
    p = Parameters("/n")
    p.declare("x", 1)
    fired: list[Parameter] = []
    p.on_change(fired.append)
    p.add_validator(lambda params: SetParametersResult(False, "no"))
    with pytest.raises(InvalidParameterValueError):
        p.set("x", 2)
    assert fired == []


class FakeBackend:
    def __init__(self, values: dict[str, Any]) -> None:
        self.values = values
        self.stored: list[tuple[str, Any]] = []

    def fetch(self, name: str) -> tuple[bool, Any]:
        return (name in self.values, self.values.get(name))

    def store(self, name: str, value: Any) -> None:
        self.stored.append((name, value))


def test_backend_values_win_and_sets_write_through() -> None:
    p = Parameters("/n", {"speed": 2.0})
    backend = FakeBackend({"speed": 3})
    p.backend = backend
    assert p.declare("speed", 1.0) == 3.0
    assert p.declare("other", "x") == "x"
    p.set("speed", 4.0)
    assert backend.stored == [("speed", 4.0)]


def test_apply_remote_sets_declared_parameters_without_writing_back() -> None:
    p = Parameters("/n")
    backend = FakeBackend({})
    p.backend = backend
    p.declare("speed", 1.0)
    fired: list[Any] = []
    p.on_change(lambda q: fired.append(q.value))
    p.apply_remote("speed", 2.0)
    p.apply_remote("undeclared", 5)  # ignored
    assert p.get("speed") == 2.0 and fired == [2.0]
    assert backend.stored == []


# ------------------------------------------------------------------ name:=value


@pytest.mark.parametrize(
    ("arg", "expected"),
    [
        ("rate:=10", ("rate", 10)),
        ("gain:=0.5", ("gain", 0.5)),
        ("gain:=-2.0", ("gain", -2.0)),
        ("on:=true", ("on", True)),
        ("on:=False", ("on", False)),
        ("ids:=[1, 2, 3]", ("ids", [1, 2, 3])),
        ("names:=[a, b]", ("names", ["a", "b"])),
        ("frame:=base_link", ("frame", "base_link")),
        ("quoted:='42'", ("quoted", "42")),
        ("empty:=", ("empty", "")),
        ("url:=tcp/127.0.0.1:7447", ("url", "tcp/127.0.0.1:7447")),
        ("limits.max:=3", ("limits.max", 3)),
        ("text:=a:=b", ("text", "a:=b")),
    ],
)
def test_parse_param_arg_reads_yaml_values(arg: str, expected: tuple[str, Any]) -> None:
    name, value = parse_param_arg(arg)
    assert (name, value) == expected
    assert type(value) is type(expected[1])


@pytest.mark.parametrize("arg", ["rate=10", "rate", ":=10", ""])
def test_parse_param_arg_rejects_malformed_arguments(arg: str) -> None:
    with pytest.raises(ParameterError, match="expected name:=value"):
        parse_param_arg(arg)


def test_parse_param_arg_rejects_bad_yaml() -> None:
    with pytest.raises(ParameterError, match="invalid value for parameter 'ids'"):
        parse_param_arg("ids:=[1, 2")


# ------------------------------------------------------------------ flatten


def test_flatten() -> None:
    tree = {"a": {"b": 1, "c": {"d": [1, 2]}}, "e": {}, "f": "x"}
    assert flatten(tree) == {"a.b": 1, "a.c.d": [1, 2], "e": {}, "f": "x"}
    assert flatten({}) == {}
    assert flatten({"x": 1}, "pre.") == {"pre.x": 1}


# ------------------------------------------------------------------ params files


def write(tmp_path: Path, text: str, name: str = "params.yaml") -> Path:
    path = tmp_path / name
    path.write_text(textwrap.dedent(text))
    return path


ROS2_FILE = """\
/**:
  ros__parameters:
    use_sim_time: true
    rate: 1
talker:
  ros__parameters:
    rate: 5
    topic: chatter
    limits:
      max: 2.0
      names: [a, b]
/robot1/talker:
  ros__parameters:
    rate: 10
listener:
  ros__parameters:
    rate: 99
"""


def test_params_file_by_base_name(tmp_path: Path) -> None:
    path = write(tmp_path, ROS2_FILE)
    assert load_params_file(path, "/talker") == {
        "use_sim_time": True, "rate": 5, "topic": "chatter",
        "limits.max": 2.0, "limits.names": ["a", "b"],
    }


def test_params_file_by_full_name(tmp_path: Path) -> None:
    path = write(tmp_path, ROS2_FILE)
    params = load_params_file(str(path), "/robot1/talker")
    assert params["rate"] == 10  # the full-name section comes later and wins
    assert params["topic"] == "chatter"  # the base-name section still applies
    assert params["use_sim_time"] is True


def test_params_file_wildcard_only(tmp_path: Path) -> None:
    path = write(tmp_path, ROS2_FILE)
    assert load_params_file(path, "/robot2/other") == {"use_sim_time": True, "rate": 1}


def test_params_file_full_name_without_leading_slash(tmp_path: Path) -> None:
    path = write(tmp_path, """\
    robot1/talker:
      ros__parameters:
        rate: 7
    """)
    assert load_params_file(path, "/robot1/talker") == {"rate": 7}


def test_params_file_nested_namespace_sections(tmp_path: Path) -> None:
    path = write(tmp_path, """\
    robot1:
      chassis:
        ros__parameters:
          wheel_base: 0.3
      sensors:
        lidar:
          ros__parameters:
            hz: 10
    /robot2:
      chassis:
        ros__parameters:
          wheel_base: 0.5
    """)
    assert load_params_file(path, "/robot1/chassis") == {"wheel_base": 0.3}
    assert load_params_file(path, "/robot1/sensors/lidar") == {"hz": 10}
    assert load_params_file(path, "/robot2/chassis") == {"wheel_base": 0.5}
    assert load_params_file(path, "/robot3/chassis") == {}


def test_params_file_single_star_matches_one_level(tmp_path: Path) -> None:
    path = write(tmp_path, """\
    /robot1/*:
      ros__parameters:
        child: true
    """)
    assert load_params_file(path, "/robot1/talker") == {"child": True}
    # ROS 2: '*' matches one name segment, '**' any number
    assert load_params_file(path, "/robot1/arm/talker") == {}


def test_params_file_double_star_stays_inside_its_namespace(tmp_path: Path) -> None:
    path = write(tmp_path, """\
    /robot1/**:
      ros__parameters:
        fleet: 1
    /**/lidar:
      ros__parameters:
        hz: 20
    """)
    assert load_params_file(path, "/robot1/talker") == {"fleet": 1}
    assert load_params_file(path, "/robot1/a/b/talker") == {"fleet": 1}
    assert load_params_file(path, "/lidar") == {"hz": 20}
    assert load_params_file(path, "/robot1/sensors/lidar") == {"fleet": 1, "hz": 20}
    # another namespace that merely starts with the same letters
    assert load_params_file(path, "/robot10/talker") == {}


def test_params_file_empty_sections(tmp_path: Path) -> None:
    path = write(tmp_path, """\
    talker:
      ros__parameters:
    """)
    assert load_params_file(path, "/talker") == {}
    assert load_params_file(write(tmp_path, "", "empty.yaml"), "/talker") == {}


def test_params_file_values_feed_parameters(tmp_path: Path) -> None:
    path = write(tmp_path, ROS2_FILE)
    p = Parameters("/talker", load_params_file(path, "/talker"))
    assert p.declare("rate", 1.0) == 5.0
    assert p.declare("limits.max", 1.0) == 2.0
    with pytest.raises(InvalidParameterValueError, match="'topic'"):
        p.declare("topic", 3)


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("- a\n- b\n", "expected a mapping of node names"),
        ("talker:\n  ros__parameters: [1, 2]\n", "ros__parameters of talker is not a mapping"),
        ("talker: [1,\n", "cannot read params file"),
        ("'unterminated\n", "cannot read params file"),
    ],
)
def test_bad_params_files(tmp_path: Path, text: str, match: str) -> None:
    path = write(tmp_path, text)
    with pytest.raises(ParameterError, match=match):
        load_params_file(path, "/talker")


def test_missing_params_file(tmp_path: Path) -> None:
    with pytest.raises(ParameterError, match=r"cannot read params file .*missing\.yaml"):
        load_params_file(tmp_path / "missing.yaml", "/talker")
