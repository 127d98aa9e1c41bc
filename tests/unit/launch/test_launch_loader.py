"""Launch files: parsing, substitutions, args, includes, groups, and the command lines built."""

from __future__ import annotations

import sys
import textwrap
from pathlib import Path

import pytest
import yaml
from zenros.errors import LaunchError
from zenros.launch.loader import declared_args, load_launch
from zenros.launch.model import ProcessSpec, params_yaml, write_params_files


def write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def test_module_node_gets_the_node_flags(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        nodes:
          - module: zenros.services.nav
    """)
    (spec,) = load_launch(f).processes
    assert spec.name == "nav" and spec.namespace == "/" and spec.label == "nav"
    assert spec.argv() == [sys.executable, "-m", "zenros.services.nav", "--name", "nav", "--ns", "/"]
    assert spec.output == "screen" and not spec.respawn and not spec.required


def test_cmd_and_exec_nodes(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        nodes:
          - {name: shell, cmd: "echo 'two words' x"}
          - {cmd: [python3, -c, "print(1)", 5]}
          - {exec: ./bin/my-node.py, arguments: --fast}
    """)
    shell, py, ex = load_launch(f).processes
    assert shell.argv() == ["echo", "two words", "x"]
    assert py.name == "python3" and py.argv() == ["python3", "-c", "print(1)", "5"]
    assert ex.name == "my_node" and ex.ros_args
    assert ex.argv() == ["./bin/my-node.py", "--name", "my_node", "--ns", "/", "--fast"]


def test_args_defaults_overrides_and_substitution(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        args:
          robot: {default: r1, description: robot name}
          topic: /$(arg robot)/cmd_vel
          speed: 0.5
          use_sim: true
        nodes:
          - name: n
            module: m.x
            namespace: $(arg robot)
            remap: {cmd_vel: $(arg topic)}
            params: {max_speed: $(arg speed), label: "v$(arg speed)", sim: $(arg use_sim)}
    """)
    d = load_launch(f)
    (spec,) = d.processes
    assert d.args == {"robot": "r1", "topic": "/r1/cmd_vel", "speed": "0.5", "use_sim": "true"}
    assert spec.fqn == "/r1/n" and spec.remaps == (("cmd_vel", "/r1/cmd_vel"),)
    assert spec.params == ({"max_speed": 0.5, "label": "v0.5", "sim": True},)
    d2 = load_launch(f, {"robot": "r2", "speed": "2"})
    assert d2.processes[0].fqn == "/r2/n" and d2.args["topic"] == "/r2/cmd_vel"
    assert d2.processes[0].params == ({"max_speed": 2, "label": "v2", "sim": True},)


def test_required_and_unknown_args(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        args:
          map: {description: the map file}
        nodes:
          - {cmd: "echo $(arg map)"}
    """)
    with pytest.raises(LaunchError, match=r"a.yaml: args.map: argument 'map' is required; pass map:="):
        load_launch(f)
    assert load_launch(f, {"map": "x.yaml"}).processes[0].argv() == ["echo", "x.yaml"]
    with pytest.raises(LaunchError, match=r"unknown argument 'mpa'; declared: map"):
        load_launch(f, {"map": "x", "mpa": "y"})
    assert declared_args(f)[0].name == "map" and declared_args(f)[0].default is None


def test_undeclared_arg_in_a_substitution(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        args: {robot: r1}
        nodes:
          - {cmd: "echo $(arg robto)"}
    """)
    with pytest.raises(LaunchError, match=r"a.yaml: nodes\[0\].cmd: \$\(arg robto\): no such "
                       r"argument; declared: robot"):
        load_launch(f)


def test_env_substitutions(tmp_path: Path) -> None:
    f = write(tmp_path / "sub" / "a.yaml", """
        nodes:
          - {cmd: "echo $(env ZR_X) $(env ZR_MISSING fallback) [$(optenv ZR_MISSING)] $(dirname)"}
    """)
    (spec,) = load_launch(f, environ={"ZR_X": "hello"}).processes
    assert spec.argv() == ["echo", "hello", "fallback", "[]", str((tmp_path / "sub").resolve())]
    g = write(tmp_path / "b.yaml", "nodes: [{cmd: 'echo $(env ZR_MISSING)'}]\n")
    with pytest.raises(LaunchError, match="ZR_MISSING is not set and has no default"):
        load_launch(g, environ={})
    h = write(tmp_path / "c.yaml", "nodes: [{cmd: 'echo $(find-pkg-share x)'}]\n")
    with pytest.raises(LaunchError, match=r"unknown substitution \$\(find-pkg-share x\); valid:"):
        load_launch(h)


def test_params_inline_and_files(tmp_path: Path) -> None:
    write(tmp_path / "params" / "nav.yaml", "nav: {ros__parameters: {a: 1}}\n")
    f = write(tmp_path / "a.yaml", """
        nodes:
          - module: zenros.services.nav
            namespace: r1
            params: [params/nav.yaml, {max_speed: 1.0, costmap: {inflation: 0.3}}]
    """)
    (spec,) = load_launch(f).processes
    assert spec.params[0] == str((tmp_path / "params" / "nav.yaml").resolve())
    paths = write_params_files(spec, tmp_path / "run")
    assert paths[0] == spec.params[0]
    assert yaml.safe_load(Path(paths[1]).read_text()) == {
        "/r1/nav": {"ros__parameters": {"max_speed": 1.0, "costmap": {"inflation": 0.3}}}
    }
    argv = spec.argv(paths)
    assert argv[-4:] == ["--params-file", paths[0], "--params-file", paths[1]]
    g = write(tmp_path / "b.yaml", "nodes: [{module: a.b, params: missing.yaml}]\n")
    with pytest.raises(LaunchError, match=r"b.yaml: nodes\[0\].params: no such file: .*missing"):
        load_launch(g)


def test_params_yaml_is_ros2_layout() -> None:
    text = params_yaml("/r1/nav", {"speed": 1, "flag": True})
    assert yaml.safe_load(text) == {"/r1/nav": {"ros__parameters": {"speed": 1, "flag": True}}}


def test_remaps_as_mapping_or_list(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        nodes:
          - {module: a.b, name: x, remap: [cmd_vel:=/safe/cmd_vel, "~/out:=/o"]}
          - {module: a.b, name: y, remap: {scan: base_scan}}
    """)
    x, y = load_launch(f).processes
    assert x.remaps == (("cmd_vel", "/safe/cmd_vel"), ("~/out", "/o"))
    assert x.argv()[-4:] == ["-r", "cmd_vel:=/safe/cmd_vel", "-r", "~/out:=/o"]
    assert y.remaps == (("scan", "base_scan"),)
    g = write(tmp_path / "b.yaml", "nodes: [{module: a.b, remap: ['a:=b c']}]\n")
    with pytest.raises(LaunchError, match=r"b.yaml: nodes\[0\].remap: invalid remap target"):
        load_launch(g)
    h = write(tmp_path / "c.yaml", "nodes: [{cmd: 'echo', remap: {a: b}}]\n")
    with pytest.raises(LaunchError, match="remap and params need ros_args: true"):
        load_launch(h)


def test_groups_nest_namespaces(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        group:
          - namespace: robot1
            nodes:
              - {module: a.chassis}
              - {module: a.tf, namespace: sensors}
              - {module: a.nav, namespace: /abs}
            group:
              - namespace: inner
                nodes: [{module: a.deep}]
              - namespace: /other
                nodes: [{module: a.top}]
    """)
    assert [s.fqn for s in load_launch(f).processes] == [
        "/robot1/chassis", "/robot1/sensors/tf", "/abs/nav", "/robot1/inner/deep", "/other/top",
    ]


def test_include_with_args_and_namespace(tmp_path: Path) -> None:
    write(tmp_path / "lib" / "robot.yaml", """
        args:
          name: {}
          speed: "1.0"
        nodes:
          - {module: a.chassis, name: $(arg name), params: {speed: $(arg speed)}}
        include:
          - file: sensors.yaml
    """)
    write(tmp_path / "lib" / "sensors.yaml", "nodes: [{module: a.lidar}]\n")
    f = write(tmp_path / "main.yaml", """
        args: {fast: "3.0"}
        group:
          - namespace: r1
            include:
              - file: lib/robot.yaml
                args: {name: base, speed: $(arg fast)}
        include:
          - {file: lib/robot.yaml, namespace: r2, args: {name: base}}
    """)
    d = load_launch(f)
    assert [s.fqn for s in d.processes] == ["/r1/base", "/r1/lidar", "/r2/base", "/r2/lidar"]
    assert d.processes[0].params == ({"speed": 3.0},)
    assert d.processes[2].params == ({"speed": 1.0},)
    assert len(d.files) == 5


def test_include_errors(tmp_path: Path) -> None:
    write(tmp_path / "child.yaml", "args: {x: {}}\nnodes: [{cmd: 'echo $(arg x)'}]\n")
    f = write(tmp_path / "a.yaml", "include: [{file: child.yaml, args: {y: 1}}]\n")
    with pytest.raises(LaunchError) as info:
        load_launch(f)
    assert "child.yaml: args: unknown argument 'y'; declared: x" in str(info.value)
    assert "a.yaml: include[0]" in str(info.value)
    g = write(tmp_path / "b.yaml", "include: [nothere.yaml]\n")
    with pytest.raises(LaunchError, match=r"b.yaml: include\[0\].file: no such file"):
        load_launch(g)
    write(tmp_path / "loop1.yaml", "include: [loop2.yaml]\n")
    write(tmp_path / "loop2.yaml", "include: [loop1.yaml]\n")
    with pytest.raises(LaunchError, match=r"include cycle: .*loop1.yaml -> .*loop2.yaml -> .*loop1"):
        load_launch(tmp_path / "loop1.yaml")


def test_supervision_fields(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        args: {again: "yes"}
        nodes:
          - {cmd: a, respawn: $(arg again), respawn_delay: 0.25, output: log}
          - {cmd: b, required: true}
    """)
    a, b = load_launch(f).processes
    assert a.respawn and a.respawn_delay == 0.25 and a.output == "log"
    assert b.required and not b.respawn


@pytest.mark.parametrize(
    ("node", "match"),
    [
        ("{cmd: a, respawn_delay: -1}", r"respawn_delay: expected a number of seconds >= 0"),
        ("{cmd: a, respawn_delay: soon}", r"respawn_delay: expected a number of seconds >= 0"),
        ("{cmd: a, respawn: maybe}", r"nodes\[0\].respawn: expected true or false, got 'maybe'"),
        ("{cmd: a, output: file}", r"output: expected screen or log, got 'file'"),
        ("{cmd: a, module: b}", "give exactly one of module, exec, cmd or container"),
        ("{name: x}", "give exactly one of module, exec, cmd or container"),
        ("{module: 'not a module'}", "is not a dotted module name"),
        ("{cmd: a, name: 9lives}", r"nodes\[0\].name: invalid node name '9lives'"),
        ("{cmd: a, namespce: x}", r"nodes\[0\].namespce: unknown key; valid: name, module"),
        ("{cmd: []}", "the command is empty"),
        ("{cmd: a, namespace: 'bad ns'}", r"nodes\[0\].namespace: invalid namespace name"),
    ],
)
def test_node_errors_name_file_and_key(tmp_path: Path, node: str, match: str) -> None:
    f = write(tmp_path / "bad.yaml", f"nodes:\n  - {node}\n")
    with pytest.raises(LaunchError, match=match) as info:
        load_launch(f)
    assert str(f.resolve()) in str(info.value)


def test_file_level_errors(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", "nodes: [\n")
    with pytest.raises(LaunchError, match="a.yaml: cannot read launch file: while parsing"):
        load_launch(f)
    g = write(tmp_path / "b.yaml", "node: []\n")
    with pytest.raises(LaunchError, match="b.yaml: node: unknown key; valid: args, env, nodes"):
        load_launch(g)
    h = write(tmp_path / "c.yaml", "- a\n")
    with pytest.raises(LaunchError, match="c.yaml: top level: expected a mapping"):
        load_launch(h)
    with pytest.raises(LaunchError, match="launch file not found"):
        load_launch(tmp_path / "none.yaml")
    empty = write(tmp_path / "empty.yaml", "")
    assert load_launch(empty).processes == []


def test_duplicate_names_are_refused(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        nodes:
          - {module: a.nav}
        group:
          - {nodes: [{module: b.nav}]}
    """)
    with pytest.raises(LaunchError, match=r"two nodes are named /nav: .*nodes\[0\] and "
                       r".*group\[0\].nodes\[0\]"):
        load_launch(f)


def test_conditions(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        args: {sim: "true"}
        nodes:
          - {cmd: a, if: $(arg sim)}
          - {cmd: b, unless: $(arg sim)}
        group:
          - {if: "false", nodes: [{cmd: c}]}
    """)
    assert [s.name for s in load_launch(f).processes] == ["a"]
    assert [s.name for s in load_launch(f, {"sim": "false"}).processes] == ["b"]


def test_env_is_inherited_and_overridden(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        env: {A: file, B: file}
        group:
          - env: {B: group, C: 3}
            nodes:
              - {cmd: x, env: {C: node}}
    """)
    (spec,) = load_launch(f).processes
    assert spec.env == {"A": "file", "B": "group", "C": "node"}


def test_lookup_by_label() -> None:
    from zenros.launch.model import LaunchDescription

    d = LaunchDescription([ProcessSpec("nav", ("x",), "/r1"), ProcessSpec("tf", ("y",))])
    assert d.process("r1/nav").name == "nav" and d.process("nav").namespace == "/r1"
    assert d.process("/tf").name == "tf"
    with pytest.raises(KeyError, match="processes: r1/nav, tf"):
        d.process("chassis")


def test_cli_print_and_show_args(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from zenros.launch.cli import main

    f = write(tmp_path / "a.yaml", """
        args:
          robot: {default: r1, description: robot name}
          map: {}
        nodes:
          - {module: a.nav, namespace: $(arg robot), params: {x: 1}}
    """)
    assert main([str(f), "--show-args"]) == 0
    assert capsys.readouterr().out == "robot (default: 'r1'): robot name\nmap (required)\n"
    assert main([str(f), "map:=m.yaml", "robot:=r2", "--print"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("r2/nav: ") and "--ns /r2 --params-file '<inline params>'" in out
    assert main([str(f), "--print"]) == 3
    assert "argument 'map' is required" in capsys.readouterr().err


def test_foreach_repeats_an_include_with_its_variable(tmp_path: Path) -> None:
    write(tmp_path / "robot.yaml", """
        args:
          robot: {}
          x: {default: "0", type: float}
        group:
          - namespace: $(arg robot)
            nodes:
              - {module: m.chassis, params: {start_x: $(arg x)}}
    """)
    f = write(tmp_path / "fleet.yaml", """
        args:
          robots: {default: "3", type: int, min: 0}
        include:
          - file: robot.yaml
            foreach: {var: k, count: $(arg robots)}
            args: {robot: "robot$(arg k)", x: "$(expr (k - 1) * 0.8)"}
            unless: $(expr k == 2)
    """)
    specs = load_launch(f).processes
    assert [s.label for s in specs] == ["robot1/chassis", "robot3/chassis"]
    assert [s.params for s in specs] == [({"start_x": 0},), ({"start_x": 1.6},)]
    assert load_launch(f, {"robots": "0"}).processes == []
    group = write(tmp_path / "g.yaml", """
        group:
          - foreach: {var: i, count: 2, start: 5}
            namespace: r$(arg i)
            nodes: [{module: m.x}]
    """)
    assert [s.label for s in load_launch(group).processes] == ["r5/x", "r6/x"]


@pytest.mark.parametrize(("foreach", "why"), [
    ("{var: k}", "foreach needs var and count"),
    ("{var: k, count: many}", "foreach.count: expected a whole number, got 'many'"),
    ("{var: k, count: 1001}", "foreach.count: expected 0 to 1000, got 1001"),
    ("{var: 'a b', count: 1}", "foreach.var: 'a b' is not a name"),
    ("{var: n, count: 1}", "foreach.var: 'n' is already an argument of this file"),
    ("{var: k, count: 1, step: 2}", "step"),
])
def test_bad_foreach_says_where_and_why(tmp_path: Path, foreach: str, why: str) -> None:
    f = write(tmp_path / "a.yaml", f"""
        args: {{n: "1"}}
        group:
          - foreach: {foreach}
            nodes: [{{module: m.x}}]
    """)
    with pytest.raises(LaunchError, match=why):
        load_launch(f)
