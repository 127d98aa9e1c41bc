"""The parameter services every ROS 2 node serves, on every zenros node: ``~/list_parameters``,
``~/describe_parameters``, ``~/get_parameter_types``, ``~/get_parameters``,
``~/set_parameters`` and ``~/set_parameters_atomically`` (``rcl_interfaces/srv``), with rclpy's
semantics, so that ROS 2 tools and rclpy's ``AsyncParameterClient`` read and set a zenros node's
parameters (through the DDS or rmw_zenoh bridge) and zenros clients do the same.

A set goes through the node's own rules (type, limits, read-only, its on-set callbacks) and,
when the node has the parameter server, is written through to it, as `Node.set_parameter`.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any

from .errors import ParameterError
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
    ListParametersResult,
    ParameterType,
    SetParameters,
    SetParametersAtomically,
    SetParametersAtomicallyRequest,
    SetParametersAtomicallyResponse,
    SetParametersRequest,
    SetParametersResponse,
    SetParametersResult,
)
from .msgs.rcl_interfaces import Parameter as ParameterMsg
from .param_descriptors import describe_parameter
from .param_events import from_parameter_value, to_parameter_value
from .params import Parameter, Parameters

__all__ = ["SEPARATOR", "list_parameters", "serve_parameter_services"]

SEPARATOR = "."

CreateService = Callable[[Any, str, Callable[[Any], Any]], Any]


def list_parameters(names: list[str], prefixes: list[str], depth: int) -> ListParametersResult:
    """rclpy's ``list_parameters``: the names under ``prefixes`` (all without), at most
    ``depth`` levels below them (0: every level), and the prefixes of the names listed."""
    def shallow(name: str) -> bool:
        return name.count(SEPARATOR) < depth

    recursive = not prefixes and depth == ListParametersRequest.DEPTH_RECURSIVE
    out = ListParametersResult()
    for name in names:
        if not recursive and not (not prefixes and shallow(name)) and not any(
                name == prefix or (name.startswith(prefix + SEPARATOR) and (
                    depth == ListParametersRequest.DEPTH_RECURSIVE
                    or shallow(name[len(prefix) + 1:])))
                for prefix in prefixes):
            continue
        out.names.append(name)
        cut = name.rfind(SEPARATOR)
        if cut != -1 and name[:cut] not in out.prefixes:
            out.prefixes.append(name[:cut])
    return out


def _type_of(p: Parameter) -> int:
    return to_parameter_value(p.value).type


class _Services:
    def __init__(self, params: Parameters) -> None:
        self.params = params

    def _declared(self, names: list[str]) -> list[Parameter | None]:
        return [self.params.lookup(n) for n in names]

    def list(self, req: ListParametersRequest) -> ListParametersResponse:
        names = [p.name for p in self.params.describe()]
        return ListParametersResponse(result=list_parameters(names, req.prefixes, req.depth))

    def describe(self, req: DescribeParametersRequest) -> DescribeParametersResponse:
        # rclpy answers nothing when one name is not declared (unless undeclared are allowed)
        found = self._declared(req.names)
        if any(p is None for p in found):
            return DescribeParametersResponse()
        return DescribeParametersResponse(
            descriptors=[describe_parameter(p) for p in found if p is not None])

    def types(self, req: GetParameterTypesRequest) -> GetParameterTypesResponse:
        return GetParameterTypesResponse(types=[
            ParameterType.PARAMETER_NOT_SET if p is None else _type_of(p)
            for p in self._declared(req.names)])

    def get(self, req: GetParametersRequest) -> GetParametersResponse:
        found = self._declared(req.names)
        if any(p is None for p in found):
            return GetParametersResponse()  # rclpy: an undeclared name answers no values
        return GetParametersResponse(
            values=[to_parameter_value(p.value) for p in found if p is not None])

    def _set_one(self, msg: ParameterMsg) -> SetParametersResult:
        """A refusal's reason is the error the node raised (it names the parameter)."""
        try:
            value = from_parameter_value(msg.value)  # None (NOT_SET): a dynamic one goes
            p = self.params.lookup(msg.name)
            if p is not None and p.type is dict and isinstance(value, str):
                value = json.loads(value)  # a dict travels as its JSON text
            self.params.set(msg.name, value)
        except (ParameterError, ValueError, TypeError) as exc:
            return SetParametersResult(successful=False, reason=str(exc))
        return SetParametersResult(successful=True)

    def set(self, req: SetParametersRequest) -> SetParametersResponse:
        return SetParametersResponse(results=[self._set_one(m) for m in req.parameters])

    def set_atomically(self, req: SetParametersAtomicallyRequest
                       ) -> SetParametersAtomicallyResponse:
        """All or none: the values are set in order, and if one is refused those already set
        go back to what they were (each change and each going back is a parameter event)."""
        before = {m.name: p.value for m in req.parameters
                  if (p := self.params.lookup(m.name)) is not None}
        for m in req.parameters:
            result = self._set_one(m)
            if not result.successful:
                for name, value in before.items():
                    if self.params.get(name) != value:
                        self.params.set(name, value)
                return SetParametersAtomicallyResponse(result=result)
        return SetParametersAtomicallyResponse(result=SetParametersResult(successful=True))


def serve_parameter_services(params: Parameters, create_service: CreateService) -> None:
    """Serve the six services over ``params`` (`Node` calls it with its own
    ``create_service``, names relative to the node: ``~/list_parameters``...)."""
    s = _Services(params)
    for srv, name, handler in (
        (ListParameters, "~/list_parameters", s.list),
        (DescribeParameters, "~/describe_parameters", s.describe),
        (GetParameterTypes, "~/get_parameter_types", s.types),
        (GetParameters, "~/get_parameters", s.get),
        (SetParameters, "~/set_parameters", s.set),
        (SetParametersAtomically, "~/set_parameters_atomically", s.set_atomically),
    ):
        create_service(srv, name, handler)

