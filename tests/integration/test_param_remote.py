"""`AsyncParameterClient` (rclpy's names and arguments) on another node's parameters over real
Zenoh: list by prefix and depth, get, set one by one (a refusal with its reason) and
atomically, describe, types, delete (dynamic typing), and a params file with and without
the wildcard section."""

from __future__ import annotations

import asyncio
from pathlib import Path
from typing import Any

from zenros.msgs.rcl_interfaces import FloatingPointRange, ParameterDescriptor, ParameterType
from zenros.param_remote import AsyncParameterClient


def test_another_nodes_parameters_as_rclpys_async_client_sees_them(
        make_node: Any, tmp_path: Path) -> None:
    target = make_node("arm", 0)
    target.declare_parameter("gain", 0.5, ParameterDescriptor(
        floating_point_range=[FloatingPointRange(from_value=0.0, to_value=1.0, step=0.25)]))
    target.declare_parameter("limits.speed", 2)
    target.declare_parameter("limits.torque.max", 7.5)
    target.declare_parameter("label", "left", ParameterDescriptor(dynamic_typing=True))
    client = AsyncParameterClient(make_node("tool", 1), "arm")
    assert client.remote_node_name == "/arm"
    assert client.wait_for_services(10) and client.services_are_ready()

    async def session() -> None:
        listed = await client.list_parameters(["limits"], 1)
        assert listed.result.names == ["limits.speed"]
        assert {"gain", "label", "limits.torque.max"} <= set(
            (await client.list_parameters()).result.names)
        got = await client.get_parameters(["gain", "limits.speed"])
        assert [(v.double_value, v.integer_value) for v in got.values] == [(0.5, 0), (0.0, 2)]
        # rclpy's service answers no values when one name is not declared
        assert (await client.get_parameters(["gain", "nope"])).values == []
        results = (await client.set_parameters([("gain", 0.75), ("gain", 0.8)])).results
        assert [r.successful for r in results] == [True, False]
        assert "in steps of 0.25" in results[1].reason
        atomic = await client.set_parameters_atomically([("gain", 0.25), ("limits.speed", 3)])
        assert atomic.result.successful
        (desc,) = (await client.describe_parameters(["gain"])).descriptors
        assert desc.floating_point_range[0].step == 0.25
        types = (await client.get_parameter_types(["gain", "limits.speed", "label"])).types
        assert types == [ParameterType.PARAMETER_DOUBLE, ParameterType.PARAMETER_INTEGER,
                         ParameterType.PARAMETER_STRING]
        deleted = (await client.delete_parameters(["label", "gain"])).results
        assert [r.successful for r in deleted] == [True, False]  # gain is statically typed

    asyncio.run(session())
    assert target.get_parameter("gain") == 0.25
    assert target.get_parameter("limits.speed") == 3
    assert not target.has_parameter("label")

    params = tmp_path / "arm.yaml"
    params.write_text("/**:\n  ros__parameters:\n    limits.speed: 9\n"
                      "arm:\n  ros__parameters:\n    gain: 1.0\n")

    async def from_file() -> tuple[list[bool], list[bool]]:
        own = await client.load_parameter_file(params)
        both = await client.load_parameter_file(params, use_wildcard=True)
        return [r.successful for r in own.results], [r.successful for r in both.results]

    own, both = asyncio.run(from_file())
    assert own == [True] and both == [True, True]
    assert target.get_parameter("limits.speed") == 9
    assert target.get_parameter("gain") == 1.0
    client.close()
