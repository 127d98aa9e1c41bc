"""The parameter server's wire protocol: keys, value encoding, change events, service types.

Shared by the master (which serves it) and `zenros.param_client` (which speaks it), so the
two cannot drift. Pure: builds key expressions only through `KeySpace.param`.
"""

from __future__ import annotations

import math
from typing import Any

import msgspec

from .errors import (
    InvalidNameError,
    InvalidParameterValueError,
    ParameterError,
    ParameterNotFoundError,
)
from .message import Message, ServiceType, define_service
from .names import KeySpace, join, validate_name

__all__ = [
    "DELETE_PARAM",
    "DUMP_PARAMS",
    "GET_PARAM",
    "HAS_PARAM",
    "JSON_ENCODING",
    "LIST_PARAMS",
    "LOAD_PARAMS",
    "MSGPACK_ENCODING",
    "PARAM_SERVICES",
    "SEARCH_PARAM",
    "SET_PARAM",
    "DeleteParam",
    "DumpParams",
    "GetParam",
    "HasParam",
    "ListParams",
    "LoadParams",
    "ParamResponse",
    "SearchParam",
    "SetParam",
    "decode_stamp",
    "decode_value",
    "encode_stamp",
    "encode_value",
    "error_fields",
    "local_param_name",
    "node_param_name",
    "param_key",
    "param_name",
    "raise_remote",
]

JSON_ENCODING = "application/json"
MSGPACK_ENCODING = "application/msgpack"

SET_PARAM = "/master/set_param"
GET_PARAM = "/master/get_param"
DELETE_PARAM = "/master/delete_param"
HAS_PARAM = "/master/has_param"
SEARCH_PARAM = "/master/search_param"
LIST_PARAMS = "/master/list_params"
DUMP_PARAMS = "/master/dump_params"
LOAD_PARAMS = "/master/load_params"
PARAM_SERVICES = (SET_PARAM, GET_PARAM, DELETE_PARAM, HAS_PARAM, SEARCH_PARAM, LIST_PARAMS,
                  DUMP_PARAMS, LOAD_PARAMS)
"""Every service of the parameter server: a master is ready once all are in the graph."""


# ---------------------------------------------------------------- keys and names


def param_key(keys: KeySpace, name: str) -> str:
    """The key expression of an absolute parameter name (``/`` is ``<prefix>/param``)."""
    return keys.param("" if name == "/" else name)


def param_name(keys: KeySpace, key: str) -> str:
    """The absolute parameter name of a key expression under ``<prefix>/param``.

    Raises:
        InvalidNameError: the key is not under the parameter key space.
    """
    root = keys.param("")
    if key == root:
        return "/"
    if not key.startswith(root + "/"):
        raise InvalidNameError(f"key {key!r} is not a parameter key (expected {root}/...)")
    return key[len(root):]


def node_param_name(node_fqn: str, name: str) -> str:
    """The master name of a node's parameter: ``/nav/planner`` + ``costmap.inflation`` gives
    ``/nav/planner/costmap/inflation``.

    Raises:
        InvalidNameError: the parameter name has no master spelling (e.g. ``max-speed``).
    """
    full = join(node_fqn, name.replace(".", "/"))
    validate_name(full, "parameter")
    return full


def local_param_name(node_fqn: str, name: str) -> str | None:
    """The node's own (dotted) name of a master name under the node, else None."""
    if not name.startswith(node_fqn + "/"):
        return None
    return name[len(node_fqn) + 1:].replace("/", ".")


# ---------------------------------------------------------------- values and stamps


def _json_safe(value: Any) -> bool:
    if isinstance(value, (bytes, bytearray, memoryview)):
        return False
    if isinstance(value, float):
        return math.isfinite(value)
    if isinstance(value, list):
        return all(_json_safe(v) for v in value)
    if isinstance(value, dict):
        return all(_json_safe(v) for v in value.values())
    return True


def encode_value(value: Any) -> tuple[bytes, str]:
    """A value as ``(payload, encoding)``: JSON (readable with ``z_get``) unless it holds
    bytes or a non-finite float, which only MessagePack carries exactly."""
    if _json_safe(value):
        return msgspec.json.encode(value), JSON_ENCODING
    return msgspec.msgpack.encode(value), MSGPACK_ENCODING


def decode_value(data: bytes, encoding: str) -> Any:
    """The value of a payload from `encode_value` (JSON when the encoding is not MessagePack).

    Raises:
        ParameterError: the payload is not valid for its encoding.
    """
    try:
        if encoding.startswith(MSGPACK_ENCODING):
            return msgspec.msgpack.decode(data)
        return msgspec.json.decode(data)
    except msgspec.DecodeError as exc:
        raise ParameterError(f"cannot decode a parameter value ({encoding}): {exc}") from exc


def encode_stamp(time: int, source: str) -> bytes:
    """A write's stamp, as the attachment of a change event."""
    return msgspec.msgpack.encode((time, source))


def decode_stamp(data: bytes | None) -> tuple[int, str]:
    """The stamp of a change event; ``(0, "")`` when it carries none or a malformed one."""
    if not data:
        return 0, ""
    try:
        time, source = msgspec.msgpack.decode(data, type=tuple[int, str])
    except msgspec.DecodeError:
        return 0, ""
    return time, source


# ---------------------------------------------------------------- services

_ERRORS: dict[str, type[ParameterError | InvalidNameError]] = {
    "ParameterNotFoundError": ParameterNotFoundError,
    "InvalidParameterValueError": InvalidParameterValueError,
    "InvalidNameError": InvalidNameError,
    "ParameterError": ParameterError,
}


class ParamResponse(Message):
    """Fields every parameter response carries: an expected failure travels as data, so
    the master does not log a caller's typo as a server error."""

    error: str = ""
    error_type: str = ""


def error_fields(exc: Exception) -> dict[str, str]:
    """The ``error``/``error_type`` of a response that reports ``exc``."""
    return {"error": str(exc), "error_type": type(exc).__name__}


def raise_remote(service: str, response: ParamResponse) -> None:
    """Raise the error a response reports (as the same class when it is a known one)."""
    if not response.error_type and not response.error:
        return
    cls = _ERRORS.get(response.error_type, ParameterError)
    raise cls(response.error or f"{service} failed ({response.error_type})")


class SetParamRequest(Message):
    __msgtype__ = "zenros_msgs/SetParamRequest"
    __bulk__ = True  # MessagePack keeps bytes and int/float exactly
    name: str = ""
    value: Any = None
    caller: str = ""


class SetParamResponse(ParamResponse):
    __msgtype__ = "zenros_msgs/SetParamResponse"
    name: str = ""
    time: int = 0
    source: str = ""


class GetParamRequest(Message):
    __msgtype__ = "zenros_msgs/GetParamRequest"
    name: str = ""
    caller: str = ""


class GetParamResponse(ParamResponse):
    __msgtype__ = "zenros_msgs/GetParamResponse"
    __bulk__ = True  # as SetParamRequest
    name: str = ""
    value: Any = None


class DeleteParamRequest(Message):
    """Delete the leaf ``name``; a namespace (the root ``/`` included) only with ``namespace``
    set, so that an empty or truncated request cannot wipe a subtree."""

    __msgtype__ = "zenros_msgs/DeleteParamRequest"
    name: str = ""
    caller: str = ""
    namespace: bool = False


class DeleteParamResponse(ParamResponse):
    __msgtype__ = "zenros_msgs/DeleteParamResponse"
    name: str = ""
    time: int = 0
    source: str = ""


class HasParamRequest(Message):
    __msgtype__ = "zenros_msgs/HasParamRequest"
    name: str = ""
    caller: str = ""


class HasParamResponse(ParamResponse):
    __msgtype__ = "zenros_msgs/HasParamResponse"
    name: str = ""
    has: bool = False


class SearchParamRequest(Message):
    __msgtype__ = "zenros_msgs/SearchParamRequest"
    key: str = ""
    caller: str = ""


class SearchParamResponse(ParamResponse):
    __msgtype__ = "zenros_msgs/SearchParamResponse"
    found: bool = False
    name: str = ""


class ListParamsRequest(Message):
    __msgtype__ = "zenros_msgs/ListParamsRequest"
    prefix: str = "/"
    caller: str = ""


class ListParamsResponse(ParamResponse):
    __msgtype__ = "zenros_msgs/ListParamsResponse"
    names: list[str] = msgspec.field(default_factory=list)


class DumpParamsRequest(Message):
    __msgtype__ = "zenros_msgs/DumpParamsRequest"
    prefix: str = "/"
    caller: str = ""


class DumpParamsResponse(ParamResponse):
    __msgtype__ = "zenros_msgs/DumpParamsResponse"
    yaml: str = ""


class LoadParamsRequest(Message):
    __msgtype__ = "zenros_msgs/LoadParamsRequest"
    yaml: str = ""
    namespace: str = "/"
    source: str = "<string>"


class LoadParamsResponse(ParamResponse):
    __msgtype__ = "zenros_msgs/LoadParamsResponse"
    names: list[str] = msgspec.field(default_factory=list)


SetParam: ServiceType = define_service("zenros_msgs/SetParam", SetParamRequest, SetParamResponse)
GetParam: ServiceType = define_service("zenros_msgs/GetParam", GetParamRequest, GetParamResponse)
DeleteParam: ServiceType = define_service(
    "zenros_msgs/DeleteParam", DeleteParamRequest, DeleteParamResponse
)
HasParam: ServiceType = define_service("zenros_msgs/HasParam", HasParamRequest, HasParamResponse)
SearchParam: ServiceType = define_service(
    "zenros_msgs/SearchParam", SearchParamRequest, SearchParamResponse
)
ListParams: ServiceType = define_service(
    "zenros_msgs/ListParams", ListParamsRequest, ListParamsResponse
)
DumpParams: ServiceType = define_service(
    "zenros_msgs/DumpParams", DumpParamsRequest, DumpParamsResponse
)
LoadParams: ServiceType = define_service(
    "zenros_msgs/LoadParams", LoadParamsRequest, LoadParamsResponse
)
