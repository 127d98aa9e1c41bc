"""Each service's config Struct is what its node declares: names, defaults, limits; the nav
core's parameter classes default to what the nav node runs; `zenros param describe` shows
them; a live change out of range is refused."""

from __future__ import annotations

import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import msgspec
import pytest
from zenros.context import Context
from zenros.errors import InvalidParameterValueError
from zenros.node import Node
from zenros.param_config import parameter_specs
from zenros.services.chassis.config import parameter_structs
from zenros.services.chassis.node import ChassisNode
from zenros.services.gateway.foxglove.node import FoxgloveParameters
from zenros.services.gateway.params import GatewayParameters
from zenros.services.gateway.rosbridge import DEFAULT_PORT as ROSBRIDGE_PORT
from zenros.services.gateway.rosbridge.node import RosbridgeNode, RosbridgeParameters
from zenros.services.gateway.testing import running_gateway
from zenros.services.master.node import MasterNode, MasterParameters
from zenros.services.nav.core import NavConfig
from zenros.services.nav.node import NavNode
from zenros.services.nav.params import NavParameters, nav_config
from zenros.services.rmw_zenoh.bridge import RmwZenohBridge
from zenros.services.rmw_zenoh.params import RmwZenohParameters
from zenros.services.tasks.node import TasksNode, TasksParameters
from zenros.services.tf.node import TfNode, TfParameters
from zenros.testing import free_port, loopback_options, unique_prefix

PORT = free_port()


@pytest.fixture
def ctxs() -> Iterator[list[Context]]:
    ctx = Context(loopback_options(PORT), prefix=unique_prefix())
    try:
        yield [ctx]
    finally:
        ctx.close()


def agree(node: Node, config: type[msgspec.Struct], read_only: bool,
          overrides: dict[str, Any] | None = None) -> None:
    declared = {p.name: p for p in node.parameters.describe()}
    for spec in parameter_specs(config):
        p = declared.get(spec.name)
        assert p is not None, f"{node.fqn} does not declare {spec.name}"
        value = (overrides or {}).get(spec.name, spec.default)
        assert (p.value, p.type, p.constraints, p.read_only) == (
            value, type(spec.default), spec.constraints, read_only), spec.name
        assert p.description == spec.description, spec.name


def test_the_nav_classes_default_to_what_the_node_runs() -> None:
    assert nav_config(NavParameters()) == NavConfig()


def test_nav_declares_its_config(ctxs: list[Context], tmp_path: Path) -> None:
    with NavNode("nav", context=ctxs[0], parameter_overrides={
            "maps_dir": str(tmp_path)}) as nav:
        nav.parameters.set("maps_dir", "")  # the one override, back to its default
        agree(nav, NavParameters, read_only=False)
        assert nav.core.config == NavConfig()
        nav.set_parameter("go_charge_percentage", 0.4)
        assert nav.params.go_charge_percentage == 0.4 and nav.autocharge.threshold == 0.4
        with pytest.raises(InvalidParameterValueError, match="within 0 .. 1"):
            nav.set_parameter("go_charge_percentage", 1.5)
        with pytest.raises(InvalidParameterValueError, match="one of ground_truth, odometry"):
            nav.set_parameter("localization", "gps")
        assert nav.core.localizer.mode == "ground_truth"


def test_chassis_declares_its_config(ctxs: list[Context]) -> None:
    with ChassisNode("chassis", context=ctxs[0]) as chassis:
        for struct in parameter_structs():  # its own, then each device's
            agree(chassis, struct, read_only=True)


@pytest.mark.parametrize(("cls", "config"), [
    (TfNode, TfParameters), (MasterNode, MasterParameters), (TasksNode, TasksParameters)])
def test_tf_master_and_tasks_declare_their_config(
        ctxs: list[Context], tmp_path: Path, cls: type[Node], config: type[msgspec.Struct],
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ZENROS_HOME", str(tmp_path))  # data_dir's default, so it stays ""
    with cls(context=ctxs[0]) as node:
        agree(node, config, read_only=False)


def test_param_describe_shows_the_limits(ctxs: list[Context], tmp_path: Path) -> None:
    with NavNode("nav", context=ctxs[0], parameter_overrides={"maps_dir": str(tmp_path)}):
        endpoint = f"tcp/127.0.0.1:{PORT}"
        out = subprocess.run(
            [sys.executable, "-m", "zenros.cli", "param", "describe", "/nav", "max_linear_vel",
             "go_charge_percentage", "--prefix", ctxs[0].keys.prefix, "-e", endpoint],
            capture_output=True, text=True, timeout=30, check=False)
        assert out.returncode == 0, out.stderr
        assert out.stdout.splitlines() == [
            "go_charge_percentage  float, within 0 .. 1  -- battery fraction that sends it "
            "to dock",
            "max_linear_vel        float, > 0  -- m/s",
        ]


def test_the_gateway_declares_its_config(ctxs: list[Context], tmp_path: Path) -> None:
    """Every gateway parameter comes from `GatewayParameters`, with its default and limits;
    the test's overrides (free ports, its own files) are set back to the defaults first."""
    with running_gateway(ctxs[0], tmp_path) as gateway:
        overridden = {"rest_port", "ws_port", "modbus_port", "rosbridge_port",
                      "discovery_port", "config_file", "data_dir"}
        defaults = GatewayParameters()
        for name in overridden:
            gateway.parameters.set(name, getattr(defaults, name))
        agree(gateway, GatewayParameters, read_only=False)
        with pytest.raises(InvalidParameterValueError, match="rest_port"):
            gateway.set_parameter("rest_port", 70000)
        assert GatewayParameters().rosbridge_port == ROSBRIDGE_PORT


@pytest.mark.parametrize(("cls", "config", "read_only", "overrides"), [
    (RmwZenohBridge, RmwZenohParameters, False, {"domain_id": 0}),
    (RosbridgeNode, RosbridgeParameters, True, {"port": 0}),
])
def test_the_bridges_declare_their_config(
        ctxs: list[Context], cls: type[Node], config: type[msgspec.Struct], read_only: bool,
        overrides: dict[str, Any]) -> None:
    with cls(context=ctxs[0], parameter_overrides=overrides) as node:
        agree(node, config, read_only, overrides)


def test_the_dds_bridge_config_has_limits() -> None:
    """Its node needs cyclonedds and a network namespace (tests/integration/ros2/): the
    Struct it declares is checked as parameter specs."""
    pytest.importorskip("cyclonedds", reason="the DDS bridge needs zenros[ros2]")
    from zenros.services.gateway.ros2.params import DdsBridgeParameters
    dds = {s.name: s for s in parameter_specs(DdsBridgeParameters)}
    assert dds["depth"].constraints == {"ge": 1} and dds["deny"].default
    assert dds["service_timeout"].constraints == {"gt": 0}


def test_the_foxglove_config_has_limits() -> None:
    """Its node needs foxglove-sdk: the Struct it declares is checked as parameter specs."""
    fox = {s.name: s for s in parameter_specs(FoxgloveParameters)}
    assert fox["port"].default == 8765 and fox["port"].constraints == {"ge": 0, "le": 65535}
