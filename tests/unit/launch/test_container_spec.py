"""Containers in launch files, and the container's component specs (`zenros.container`)."""

from __future__ import annotations

import json
import sys
import textwrap
from pathlib import Path

import pytest
from zenros.container import Component, ComponentError, load_plugin
from zenros.errors import LaunchError
from zenros.examples.talker import Talker
from zenros.launch.loader import load_launch


def write(path: Path, text: str) -> Path:
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def test_a_container_is_one_process_with_its_components(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        group:
          - namespace: robot1
            nodes:
              - container: robot
                respawn: true
                components:
                  - plugin: zenros.services.chassis.node:ChassisNode
                    name: chassis
                    params: [{speed: 2.0}]
                    remap: {/tf: tf}
                  - {plugin: "zenros.services.nav.node:NavNode", name: nav, namespace: /other}
                  - {plugin: "a.b:C", name: off, if: "false"}
    """)
    (spec,) = load_launch(f).processes
    assert spec.label == "robot1/robot" and spec.respawn
    assert [c.fqn for c in spec.components] == ["/robot1/chassis", "/other/nav"]
    argv = spec.argv([])
    assert argv[:3] == [sys.executable, "-m", "zenros.container"]
    first = json.loads(argv[argv.index("--component") + 1])
    assert first == {"plugin": "zenros.services.chassis.node:ChassisNode", "name": "chassis",
                     "namespace": "/robot1", "remaps": [["/tf", "tf"]],
                     "params": [{"speed": 2.0}]}
    assert Component.parse(json.dumps(first)).overrides() == {"speed": 2.0}


@pytest.mark.parametrize(("body", "why"), [
    ("{container: c}", "a container needs components"),
    ("{module: m.x, components: []}", "only a container has them"),
    ("{container: c, components: []}", "at least one component"),
    ("{container: c, components: [{name: x}]}", "a component needs 'plugin'"),
    ("{container: c, components: [{plugin: 'a.b:C'}]}", "a component needs 'name'"),
    ("{container: c, components: [{plugin: a.b, name: x}]}", "is not package.module:Class"),
    ("{container: c, components: [{plugin: 'a:B', name: 'x y'}]}", "components\\[0\\].name"),
    ("{container: c, components: [{plugin: 'a:B', name: x, exec: y}]}", "components\\[0\\].exec: unknown key"),
])
def test_bad_containers_say_where_and_why(tmp_path: Path, body: str, why: str) -> None:
    f = write(tmp_path / "a.yaml", f"nodes: [{body}]\n")
    with pytest.raises(LaunchError, match=why):
        load_launch(f)


def test_a_component_named_like_another_node_is_an_error(tmp_path: Path) -> None:
    f = write(tmp_path / "a.yaml", """
        nodes:
          - {module: zenros.examples.talker, name: talker}
          - {container: c, components: [{plugin: "zenros.examples.talker:Talker", name: talker}]}
    """)
    with pytest.raises(LaunchError, match="two nodes are named /talker"):
        load_launch(f)


def test_component_params_apply_in_order_files_and_mappings(tmp_path: Path) -> None:
    params = write(tmp_path / "p.yaml", """
        /robot1/nav:
          ros__parameters: {a: 1, b: {c: 2}}
        other:
          ros__parameters: {a: 99}
    """)
    c = Component(plugin="m:C", name="nav", namespace="/robot1",
                  params=[{"a": 0, "d": 4}, str(params), {"b": {"c": 3}}])
    assert c.overrides() == {"a": 1, "b.c": 3, "d": 4}


@pytest.mark.parametrize(("text", "why"), [
    ("not json", "bad --component"),
    ('{"plugin": "m:C"}', "missing required field `name`"),
    ('{"plugin": "m:C", "name": "x", "extra": 1}', "unknown field `extra`"),
])
def test_bad_component_json_is_a_component_error(text: str, why: str) -> None:
    with pytest.raises(ComponentError, match=why):
        Component.parse(text)


def test_plugins_load_node_classes_only() -> None:
    assert load_plugin("zenros.examples.talker:Talker") is Talker
    for plugin, why in [("zenros.examples.talker", "expected package.module:Class"),
                        ("zenros.no_such_module:X", "cannot import zenros.no_such_module"),
                        ("zenros.examples.talker:String", "has no Node class String")]:
        with pytest.raises(ComponentError, match=why):
            load_plugin(plugin)
