"""The direction of imports (docs/architecture.md): no service imports another, and in the
gateway no port (nor the state) imports a door. Read with ast by scripts/import_graph.py,
the same walk the architecture page is written from."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "import_graph.py"


@pytest.fixture(scope="module")
def graph_mod() -> ModuleType:
    spec = importlib.util.spec_from_file_location("import_graph", SCRIPT)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("import_graph", mod)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def arrows(graph_mod: ModuleType) -> dict[str, set[str]]:
    """Every module's imports of zenros modules, those made for type checking included."""
    mods = graph_mod.modules()
    known = set(mods)
    return {m: graph_mod.imports_of(m, p, known, True) for m, p in mods.items()}


def test_no_import_points_the_wrong_way(graph_mod: ModuleType,
                                        arrows: dict[str, set[str]]) -> None:
    assert graph_mod.wrong_way(arrows) == []


def test_every_gateway_module_is_in_a_layer(graph_mod: ModuleType,
                                           arrows: dict[str, set[str]]) -> None:
    parts = {graph_mod.gateway_part(m) for m in arrows} - {""}
    assert {"state", "ports", "http", "modbus", "serial", "rosbridge", "foxglove"} <= parts
    assert parts <= set(graph_mod.GATEWAY_LAYERS), parts - set(graph_mod.GATEWAY_LAYERS)


@pytest.mark.parametrize(("importer", "imported", "why"), [
    ("zenros.services.gateway.ports.nav_services", "zenros.services.gateway.http.api",
     "ports (layer 2) imports http (layer 3)"),
    ("zenros.services.gateway.state.presence", "zenros.services.gateway.ports.robot_topics",
     "state (layer 1) imports ports (layer 2)"),
    ("zenros.services.gateway.modbus.front", "zenros.services.gateway.node",
     "modbus (layer 3) imports node (layer 4)"),
    ("zenros.services.gateway.http.api", "zenros.services.tasks.robot",
     "one service imports another"),
    ("zenros.services.gateway.cloud.x", "zenros.services.gateway.state.core",
     "not in a gateway layer"),
])
def test_the_check_catches_a_wrong_arrow(graph_mod: ModuleType, importer: str, imported: str,
                                         why: str) -> None:
    """The rule is not vacuous: each kind of wrong arrow is reported, naming both ends."""
    bad = graph_mod.wrong_way({importer: {imported}})
    assert len(bad) == 1 and bad[0].startswith(f"{importer} -> {imported}: ")
    assert why in bad[0]


def test_right_arrows_pass(graph_mod: ModuleType) -> None:
    ok = {"zenros.services.gateway.http.api": {"zenros.services.gateway.ports.nav_services",
                                               "zenros.services.gateway.state.tokens",
                                               "zenros.services.gateway.errors", "zenros.node"},
          "zenros.services.gateway.ports.nav_actions": {"zenros.services.gateway.state.core"},
          "zenros.services.tasks.link": {"zenros.maps.maproute"}}
    assert graph_mod.wrong_way(ok) == []


def test_the_library_has_no_import_circle(graph_mod: ModuleType,
                                          arrows: dict[str, set[str]]) -> None:
    """No module of zenros reaches itself through its imports, type-checking ones included:
    the smach helpers, the action server and client, the parameter backend and the type
    registry are typed against protocols (`smach.parent.Parent`, `action.host.ActionHost`,
    `param_backend.ParameterOwner`) instead of importing what imports them."""
    assert graph_mod.library_circles(arrows) == []


def test_no_service_has_an_import_circle_inside(graph_mod: ModuleType,
                                                arrows: dict[str, set[str]]) -> None:
    """Nor does a module of a service reach itself, type-checking imports included: the
    helpers of the rosbridge, the DDS bridge and the rmw_zenoh bridge see the bridge that
    makes them as a protocol of what they use (each package's ``host.BridgeHost``)."""
    assert graph_mod.service_circles(arrows) == []
    two = {"zenros.services.gateway.ros2.bridge": {"zenros.services.gateway.ros2.graph"},
           "zenros.services.gateway.ros2.graph": {"zenros.services.gateway.ros2.bridge"}}
    assert len(graph_mod.service_circles(two)) == 1


def test_the_message_base_does_not_import_the_messages(arrows: dict[str, set[str]]) -> None:
    assert not {t for t in arrows["zenros.message"] if t.startswith("zenros.msgs")}
    assert "zenros.msgs" in arrows["zenros.registry"]
    assert "zenros.msgs.std_msgs" in arrows["zenros.msgs"]  # a package imports its modules


@pytest.mark.parametrize("graph", [
    {"zenros.message": {"zenros.msgs"}, "zenros.msgs": {"zenros.msgs.std_msgs"},
     "zenros.msgs.std_msgs": {"zenros.message"}},
    {"zenros.smach.container": {"zenros.smach.snapshot"},
     "zenros.smach.snapshot": {"zenros.smach.container"}},
])
def test_the_circle_check_catches_a_circle(graph_mod: ModuleType,
                                           graph: dict[str, set[str]]) -> None:
    """The rule is not vacuous: the circles the library had are reported, naming each module."""
    found = graph_mod.library_circles(graph)
    assert len(found) == 1 and all(m in found[0] for m in graph)


def test_a_compiled_module_is_not_its_package(graph_mod: ModuleType,
                                              arrows: dict[str, set[str]]) -> None:
    """``from . import _speedups`` (a C module) in zenros.tf.accel imports no Python module."""
    assert "zenros.tf._speedups" in graph_mod.extensions()
    assert "zenros.tf" not in arrows["zenros.tf.accel"]
