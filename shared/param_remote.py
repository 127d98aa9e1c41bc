"""`AsyncParameterClient`: another node's parameters through its ROS 2 parameter services
(``<node>/list_parameters``, ``get_parameters``, ``set_parameters``, ...), with the names and
arguments of rclpy's ``rclpy.parameter_client.AsyncParameterClient``; each call is awaitable
(zenros's `Client.call_async`) and answers the service's response.

Values go in as plain Python values, ``(name, value)`` pairs, zenros `Parameter`s or
``rcl_interfaces/Parameter`` messages, as rclpy takes its ``Parameter`` or the message.
It works with any node that offers the services: a zenros node, or an rclpy node through a
bridge (docs/ros2.md).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .msgs.rcl_interfaces import (
    DescribeParameters,
    DescribeParametersRequest,
    DescribeParametersResponse,
    GetParameters,
    GetParametersRequest,
    GetParametersResponse,
    GetParameterTypes,
    GetParameterTypesRequest,
    GetParameterTypesResponse,
    ListParameters,
    ListParametersRequest,
    ListParametersResponse,
    ParameterType,
    ParameterValue,
    SetParameters,
    SetParametersAtomically,
    SetParametersAtomicallyRequest,
    SetParametersAtomicallyResponse,
    SetParametersRequest,
    SetParametersResponse,
)
from .msgs.rcl_interfaces import Parameter as ParameterMsg
from .names import resolve
from .param_events import to_parameter_value
from .params import Parameter, load_params_file

if TYPE_CHECKING:
    from .node import Node
    from .rpc import Client

__all__ = ["AsyncParameterClient"]

ParameterLike = ParameterMsg | Parameter | tuple[str, Any]


def _message(p: ParameterLike) -> ParameterMsg:
    if isinstance(p, ParameterMsg):
        return p
    if isinstance(p, Parameter):
        return ParameterMsg(name=p.name, value=to_parameter_value(p.value))
    if isinstance(p, tuple) and len(p) == 2 and isinstance(p[0], str):
        return ParameterMsg(name=p[0], value=to_parameter_value(p[1]))
    raise TypeError(f"a parameter is a (name, value) pair, a zenros Parameter or an "
                    f"rcl_interfaces/Parameter message, not {p!r}")


class AsyncParameterClient:
    """The parameters of ``remote_node_name`` (resolved in ``node``'s namespace), as rclpy's."""

    def __init__(self, node: Node, remote_node_name: str, timeout: float = 5.0) -> None:
        self.remote_node_name = resolve(remote_node_name, node.namespace, node.fqn, "node")
        self.timeout = timeout
        base = self.remote_node_name.rstrip("/")
        self._list: Client[ListParametersRequest, ListParametersResponse] = \
            node.create_client(ListParameters, f"{base}/list_parameters")
        self._get: Client[GetParametersRequest, GetParametersResponse] = \
            node.create_client(GetParameters, f"{base}/get_parameters")
        self._set: Client[SetParametersRequest, SetParametersResponse] = \
            node.create_client(SetParameters, f"{base}/set_parameters")
        self._atomic: Client[SetParametersAtomicallyRequest, SetParametersAtomicallyResponse] = \
            node.create_client(SetParametersAtomically, f"{base}/set_parameters_atomically")
        self._describe: Client[DescribeParametersRequest, DescribeParametersResponse] = \
            node.create_client(DescribeParameters, f"{base}/describe_parameters")
        self._types: Client[GetParameterTypesRequest, GetParameterTypesResponse] = \
            node.create_client(GetParameterTypes, f"{base}/get_parameter_types")
        self._clients: list[Client[Any, Any]] = [self._list, self._get, self._set, self._atomic,
                                                 self._describe, self._types]

    def services_are_ready(self) -> bool:
        """Whether the graph lists a server for each of the remote node's services."""
        return all(c.service_is_ready() for c in self._clients)

    def wait_for_services(self, timeout_sec: float | None = None) -> bool:
        """Block until every service is listed (False when ``timeout_sec`` passes first)."""
        return all(c.wait_for_service(timeout_sec) for c in self._clients)

    async def list_parameters(self, prefixes: Sequence[str] | None = None,
                              depth: int | None = None) -> ListParametersResponse:
        """The names (and prefixes) under ``prefixes``, ``depth`` levels deep (0: all)."""
        request = ListParametersRequest(prefixes=list(prefixes or []), depth=depth or 0)
        return await self._list.call_async(request, self.timeout)

    async def get_parameters(self, names: Sequence[str]) -> GetParametersResponse:
        """The values of ``names`` (``PARAMETER_NOT_SET`` for one the node lacks)."""
        return await self._get.call_async(GetParametersRequest(names=list(names)), self.timeout)

    async def set_parameters(self, parameters: Iterable[ParameterLike]) -> SetParametersResponse:
        """Set each parameter on its own: one result (successful, reason) each."""
        request = SetParametersRequest(parameters=[_message(p) for p in parameters])
        return await self._set.call_async(request, self.timeout)

    async def set_parameters_atomically(
            self, parameters: Iterable[ParameterLike]) -> SetParametersAtomicallyResponse:
        """Set all of them or none: one result."""
        request = SetParametersAtomicallyRequest(parameters=[_message(p) for p in parameters])
        return await self._atomic.call_async(request, self.timeout)

    async def describe_parameters(self, names: Sequence[str]) -> DescribeParametersResponse:
        """The descriptors (ranges, read-only, constraints) of ``names``."""
        request = DescribeParametersRequest(names=list(names))
        return await self._describe.call_async(request, self.timeout)

    async def get_parameter_types(self, names: Sequence[str]) -> GetParameterTypesResponse:
        """The ``ParameterType`` of each of ``names``."""
        request = GetParameterTypesRequest(names=list(names))
        return await self._types.call_async(request, self.timeout)

    async def delete_parameters(self, names: Sequence[str]) -> SetParametersResponse:
        """Undeclare ``names`` (rclpy's way: set them to ``PARAMETER_NOT_SET``; refused for a
        parameter declared without ``dynamic_typing``)."""
        unset = ParameterValue(type=ParameterType.PARAMETER_NOT_SET)
        return await self.set_parameters([ParameterMsg(name=n, value=unset) for n in names])

    async def load_parameter_file(self, parameter_file: str | Path,
                                  use_wildcard: bool = False) -> SetParametersResponse:
        """Set the values a ROS 2 params file gives the remote node (its own section; the
        ``/**`` one too with ``use_wildcard``)."""
        return await self.set_parameters(self._from_file(parameter_file, use_wildcard))

    async def load_parameter_file_atomically(
            self, parameter_file: str | Path,
            use_wildcard: bool = False) -> SetParametersAtomicallyResponse:
        """As `load_parameter_file`, all or none."""
        return await self.set_parameters_atomically(
            self._from_file(parameter_file, use_wildcard))

    def _from_file(self, path: str | Path, use_wildcard: bool) -> list[ParameterLike]:
        return list(load_params_file(path, self.remote_node_name,
                                     wildcards=use_wildcard).items())

    def close(self) -> None:
        for c in self._clients:
            c.close()
