"""Launch arguments: declared types and limits, ``$(expr ...)``, ``checks``, and every
argument combination of the project's launch files (a working robot or one line)."""

from __future__ import annotations

import textwrap
from pathlib import Path

import pytest
from zenros.errors import LaunchError
from zenros.launch import load_launch
from zenros.launch.expr import ExprError, evaluate
from zenros.launch.substitution import Scope, spans, substitute, substitute_value

ROOT = Path(__file__).resolve().parents[3]
SIM = ROOT / "deploy" / "launch" / "sim.yaml"


def write(path: Path, text: str) -> Path:
    path.write_text(textwrap.dedent(text))
    return path


# ------------------------------------------------------------------ $(expr ...)

@pytest.mark.parametrize(("text", "value"), [
    ("speed != 1", "true"),
    ("speed == 10.0", "true"),
    ("speed > 2 and speed <= 10", "true"),
    ("not (flag or speed < 1)", "false"),
    ("flag == true", "true"),
    ("flag == 'yes'", "true"),  # both booleans
    ("robot == 'robot1'", "true"),
    ("robot != \"robot1\"", "false"),
    ("robot", "robot1"),
    ("1 < 2 and not false", "true"),
    ("1.0 + (speed - 1) * 0.5", "5.5"),
    ("speed * 2 - 4", "16"),
    ("-speed", "-10"),
    ("speed / 4", "2.5"),
    ("speed % 3", "1"),
    ("speed * 2 == 20", "true"),
    ("-1.5", "-1.5"),
])
def test_expressions(text: str, value: str) -> None:
    assert evaluate(text, {"speed": "10", "flag": "true", "robot": "robot1"}) == value


@pytest.mark.parametrize(("text", "why"), [
    ("", "empty expression"),
    ("speed >", "unexpected end"),
    ("(speed > 1", "missing"),
    ("nope == 1", "no such argument 'nope'; declared: speed"),
    ("speed and true", "'and' needs true or false, got '10'"),
    ("'a' < 1", "'<' needs two numbers"),
    ("__import__('os').system('true')", "cannot read"),
    ("__import__", "no such argument '__import__'"),
    ("speed; 1", "cannot read"),
    ("speed == 1 == 1", "unexpected '=='"),
    ("speed / 0", "'/' by zero"),
    ("'a' + 1", "'\\+' needs two numbers"),
    ("speed * true", "'\\*' needs two numbers"),
    ("1e308 * 10", "not a finite number"),
])
def test_bad_expressions(text: str, why: str) -> None:
    with pytest.raises(ExprError, match=why.replace("(", r"\(")):
        evaluate(text, {"speed": "10"})


def test_an_argument_value_is_data_never_expression() -> None:
    """A value that reads like an expression is compared as text, not parsed."""
    names = {"robot": "x or true", "n": "1 == 1"}
    assert evaluate("robot == 'robot1'", names) == "false"
    with pytest.raises(ExprError, match="needs true or false"):
        evaluate("n and true", names)


def test_expr_substitution_nests_parentheses_and_reads_back_typed() -> None:
    scope = Scope(Path("/x/a.yaml"), {"speed": "10", "flag": "false"})
    text = "a $(expr not (flag or speed == 1)) b $(arg speed)"
    assert substitute(text, scope, "k") == "a true b 10"
    assert substitute_value("$(expr speed != 1)", scope, "k") is True
    assert substitute_value("x $(expr speed != 1)", scope, "k") == "x true"
    assert spans("$(expr ')' == robot) $(") == [(0, 20)]
    with pytest.raises(LaunchError, match=r"a.yaml: k: \$\(expr speed >\): unexpected end"):
        substitute("$(expr speed >)", scope, "k")


# ------------------------------------------------------------------ typed args

def test_typed_args_are_checked_and_normalized(tmp_path: Path) -> None:
    (tmp_path / "world.yaml").write_text("image: x.pgm\n")
    f = write(tmp_path / "a.yaml", """
        args:
          flag: {default: "yes", type: bool}
          n: {default: "3", type: int, min: 1, max: 5}
          rate: {default: "2.0", type: float, above: 0}
          map: {default: "$(dirname)/world.yaml", type: file}
          mode: {default: fast, choices: [fast, slow]}
        nodes:
          - {cmd: "echo $(arg flag) $(arg n) $(arg rate) $(arg map) $(arg mode)"}
    """)
    d = load_launch(f)
    assert d.processes[0].cmd[1:] == ("true", "3", "2.0", str(tmp_path / "world.yaml"), "fast")
    assert load_launch(f, {"flag": "Off"}).args["flag"] == "false"


@pytest.mark.parametrize(("given", "why"), [
    ({"flag": "maybe"}, "flag:=maybe: expected true or false, got 'maybe'"),
    ({"n": "2.5"}, "n:=2.5: expected an integer >= 1 and <= 5, got '2.5'"),
    ({"n": "9"}, "n:=9: expected an integer >= 1 and <= 5, got '9'"),
    ({"rate": "0"}, "rate:=0: expected a number > 0, got '0'"),
    ({"rate": "abc"}, "rate:=abc: expected a number > 0, got 'abc'"),
    ({"rate": "inf"}, "rate:=inf: expected a number > 0"),
    ({"map": "/no/such.yaml"}, "map:=/no/such.yaml: no such file: /no/such.yaml"),
    ({"map": "/"}, "map:=/: expected a file, got the directory /"),
    ({"mode": "Fast"}, "mode:=Fast: expected one of fast, slow, got 'Fast'"),
])
def test_a_bad_value_names_the_argument(tmp_path: Path, given: dict[str, str], why: str) -> None:
    (tmp_path / "world.yaml").write_text("image: x.pgm\n")
    f = write(tmp_path / "a.yaml", """
        args:
          flag: {default: "yes", type: bool}
          n: {default: "3", type: int, min: 1, max: 5}
          rate: {default: "2.0", type: float, above: 0}
          map: {default: "$(dirname)/world.yaml", type: file}
          mode: {default: fast, choices: [fast, slow]}
    """)
    with pytest.raises(LaunchError) as info:
        load_launch(f, given)
    assert str(info.value) == f"{f}: {why}" or str(info.value).startswith(f"{f}: {why}")
    assert "\n" not in str(info.value)


def test_a_bad_default_and_bad_declarations(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", "args:\n  n: {default: x, type: int}\n")
    with pytest.raises(LaunchError, match=r"args.n \(default 'x'\): expected an integer"):
        load_launch(f)
    g = write(tmp_path / "b.yaml", "args:\n  n: {type: complex}\n")
    with pytest.raises(LaunchError, match="args.n.type: expected one of str, bool, int"):
        load_launch(g, {"n": "1"})
    h = write(tmp_path / "c.yaml", "args:\n  n: {type: int, min: low}\n")
    with pytest.raises(LaunchError, match="args.n.min: expected a number, got 'low'"):
        load_launch(h, {"n": "1"})


def test_checks_stop_a_combination_that_cannot_work(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        args:
          speed: {default: "1", type: float}
          sim: {default: "$(expr speed != 1)", type: bool}
        checks:
          - fail_if: $(expr speed != 1 and not sim)
            error: "sim:=false cannot run with speed:=$(arg speed)"
        nodes:
          - {cmd: "echo $(arg sim)"}
    """)
    assert load_launch(f).processes[0].cmd[1:] == ("false",)
    assert load_launch(f, {"speed": "10"}).processes[0].cmd[1:] == ("true",)
    assert load_launch(f, {"sim": "true"}).processes[0].cmd[1:] == ("true",)
    with pytest.raises(LaunchError, match=r"a.yaml: sim:=false cannot run with speed:=10\Z"):
        load_launch(f, {"speed": "10", "sim": "false"})
    g = write(tmp_path / "b.yaml", "checks:\n  - {fail_if: true}\n")
    with pytest.raises(LaunchError, match=r"checks\[0\]: a check needs fail_if and error"):
        load_launch(g)


# ------------------------------------------------------------------ the project's files

def _param(args: dict[str, str], node: str, name: str) -> object:
    spec = load_launch(SIM, args).process(node)
    merged: dict[str, object] = {}
    for p in spec.params:
        assert isinstance(p, dict)
        merged.update(p)
    return merged[name]


@pytest.mark.parametrize(("args", "speed", "sim_time"), [
    ({}, 1, False),
    ({"speed": "10"}, 10, True),  # what a user types: the world follows sim time
    ({"speed": "10", "use_sim_time": "true"}, 10, True),
    ({"use_sim_time": "true"}, 1, True),
    ({"speed": "0"}, 0, True),
    ({"speed": "1.0", "use_sim_time": "no"}, 1.0, False),
])
def test_sim_speed_and_sim_time(args: dict[str, str], speed: float, sim_time: bool) -> None:
    """The chassis publishes /clock exactly when the nodes follow it (speed != 1 needs it)."""
    assert _param(args, "chassis", "speed") == speed
    assert _param(args, "chassis", "publish_clock") is sim_time
    for node in ("tf", "nav", "tasks", "gateway", "talker", "listener"):
        assert _param(args, node, "use_sim_time") is sim_time, node


@pytest.mark.parametrize(("file", "args", "names"), [
    ("sim.yaml", {"speed": "10", "use_sim_time": "false"}, "use_sim_time:=false"),
    ("sim.yaml", {"speed": "-1"}, "speed:=-1"),
    ("sim.yaml", {"speed": "abc"}, "speed:=abc"),
    ("sim.yaml", {"map": "/no/such/map.yaml"}, "map:=/no/such/map.yaml"),
    ("sim.yaml", {"rate": "0"}, "rate:=0"),
    ("sim.yaml", {"use_sim_time": "maybe"}, "use_sim_time:=maybe"),
    ("sim.yaml", {"record": "2"}, "record:=2"),
    ("sim.yaml", {"sped": "10"}, "unknown argument 'sped'"),
    ("robot.yaml", {"map": "nowhere.yaml"}, "map:=nowhere.yaml"),
    ("robot.yaml", {"heartbeat_rate": "-5"}, "heartbeat_rate:=-5"),
    ("robot.yaml", {"robot": "2bad"}, "(from robot:=2bad)"),
    ("station.yaml", {"heartbeat": "sometimes"}, "heartbeat:=sometimes"),
    ("demo.yaml", {"rate": "fast"}, "rate:=fast"),
])
def test_every_bad_argument_is_one_line_that_names_it(
    file: str, args: dict[str, str], names: str
) -> None:
    with pytest.raises(LaunchError) as info:
        load_launch(ROOT / "deploy" / "launch" / file, args)
    text = str(info.value)
    assert names in text and "\n" not in text, text


def test_every_project_launch_file_loads_with_its_defaults() -> None:
    for file in sorted((ROOT / "deploy" / "launch").glob("*.yaml")):
        assert load_launch(file).processes, file
