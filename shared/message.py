"""The `Message` base class, numpy-backed array fields, and the tables types register in.

Looking a type up by name, the standard types loaded first, is `zenros.registry`'s (it sits
above `zenros.msgs`, whose modules register here: the imports point one way).
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass
from typing import Any, ClassVar, Generic, TypeVar

import msgspec
import numpy as np
from typing_extensions import TypeVar as DefaultTypeVar

from .errors import UnknownTypeError

__all__ = [
    "TABLES",
    "ActionType",
    "Float32Array",
    "Float64Array",
    "Int8Array",
    "Message",
    "ServiceType",
    "TypeTables",
    "UInt8Array",
    "array_field",
    "define_action",
    "define_service",
    "find_registered",
    "normalize_type_name",
    "similar_type_names",
]

_MESSAGES: dict[str, type[Message]] = {}
_SERVICES: dict[str, ServiceType[Any, Any]] = {}
_ACTIONS: dict[str, ActionType] = {}

M = TypeVar("M", bound="Message")
# An action's goal, result and feedback types (`ActionType`); Any where not spelled out, so
# that ``ActionType`` alone still means any action.
G = DefaultTypeVar("G", bound="Message", default=Any)
R = DefaultTypeVar("R", bound="Message", default=Any)
F = DefaultTypeVar("F", bound="Message", default=Any)
# A service's request and response types (`ServiceType`), Any where not spelled out.
Q = DefaultTypeVar("Q", bound="Message", default=Any)
S = DefaultTypeVar("S", bound="Message", default=Any)


class Message(msgspec.Struct, kw_only=True):
    """Base of every zenros message: a typed msgspec Struct with a ROS wire type name.

    Subclasses set ``__msgtype__ = "pkg/Name"`` and are registered under that name;
    ``__bulk__ = True`` sends them as MessagePack instead of JSON. Messages are mutable,
    as ROS users expect; a message delivered in-process is shared between subscribers,
    so treat received messages as read-only.
    """

    __msgtype__: ClassVar[str] = ""
    __bulk__: ClassVar[bool] = False

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        name = cls.__dict__.get("__msgtype__")
        if name:
            _MESSAGES[normalize_type_name(name)] = cls

    def __eq__(self, other: object) -> bool:
        """Field-wise equality; numpy array fields compare by value (``np.array_equal``)."""
        if type(other) is not type(self):
            return NotImplemented
        return all(
            _field_eq(getattr(self, f), getattr(other, f)) for f in self.__struct_fields__
        )


def _field_eq(a: Any, b: Any) -> bool:
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return (isinstance(a, np.ndarray) and isinstance(b, np.ndarray)
                and bool(np.array_equal(a, b)))
    return bool(a == b)


def normalize_type_name(name: str) -> str:
    """Map ``pkg/msg/Name``, ``pkg/srv/Name`` and ``pkg/action/Name`` to ``pkg/Name``."""
    parts = name.strip("/").split("/")
    if len(parts) == 3 and parts[1] in ("msg", "srv", "action"):
        return f"{parts[0]}/{parts[2]}"
    return "/".join(parts)


def find_registered(table: dict[str, Any], kind: str, name: str) -> Any:
    """``pkg/Name`` (or ``pkg/msg/Name``), or an unambiguous short ``Name``, in ``table`` (one of
    `TABLES`); `UnknownTypeError` naming the closest registered names otherwise."""
    key = normalize_type_name(name)
    if key in table:
        return table[key]
    if "/" not in key:
        owners = sorted(full for full in table if full.rsplit("/", 1)[-1] == key)
        if len(owners) == 1:
            return table[owners[0]]
        if owners:
            raise UnknownTypeError(f"{kind} type {name!r} is ambiguous: {' or '.join(owners)}")
    close = similar_type_names(key, table)
    hint = (f"; did you mean {' or '.join(close)}?" if close
            else f" (no close match among {len(table)} registered {kind} types)")
    raise UnknownTypeError(f"unknown {kind} type {name!r}{hint}")


def similar_type_names(name: str, names: Any, n: int = 3) -> list[str]:
    """The few registered names closest to a misspelled ``name`` (full or short, any case)."""
    want = name.lower()
    pkg, _, tail = want.rpartition("/")

    def score(full: str) -> float:
        f_pkg, _, f_tail = full.lower().rpartition("/")
        short = difflib.SequenceMatcher(None, tail, f_tail).ratio()
        return short - 0.1 if pkg and pkg != f_pkg else short

    scored = sorted(((score(full), full) for full in names), key=lambda sf: (-sf[0], sf[1]))
    return [full for sc, full in scored[:n] if sc >= 0.75]


@dataclass(frozen=True)
class ServiceType(Generic[Q, S]):
    """A service type: a request and a response message under one name.

    Generic in the two (``ServiceType[AddTwoIntsRequest, AddTwoIntsResponse]``), so the
    clients made from it are typed: ``await client.call_async(request)`` is the response
    (`Node.create_client`), and a port's ``call(srv, request)`` too."""

    name: str
    Request: type[Q]
    Response: type[S]


@dataclass(frozen=True)
class ActionType(Generic[G, R, F]):
    """An action type: goal, result and feedback messages under one name.

    Generic in the three (``ActionType[FibonacciGoal, FibonacciResult, FibonacciFeedback]``),
    so the servers and clients made from it are typed (`Node.create_action_server`)."""

    name: str
    Goal: type[G]
    Result: type[R]
    Feedback: type[F]


def define_service(name: str, request: type[Q], response: type[S]) -> ServiceType[Q, S]:
    """Register and return a service type, typed by its request and response."""
    srv = ServiceType(normalize_type_name(name), request, response)
    _SERVICES[srv.name] = srv
    return srv


def define_action(
    name: str, goal: type[G], result: type[R], feedback: type[F]
) -> ActionType[G, R, F]:
    """Register and return an action type."""
    act = ActionType(normalize_type_name(name), goal, result, feedback)
    _ACTIONS[act.name] = act
    return act


@dataclass(frozen=True)
class TypeTables:
    """The registered types by normalized name (``pkg/Name``): what has registered so far."""

    messages: dict[str, type[Message]]
    services: dict[str, ServiceType[Any, Any]]
    actions: dict[str, ActionType]


TABLES = TypeTables(_MESSAGES, _SERVICES, _ACTIONS)


# ---------------------------------------------------------------- numpy array fields


class _TypedArray(np.ndarray):
    dtype_: ClassVar[Any] = np.float64


class Float32Array(_TypedArray):
    """A float32 array field: numpy on the Python side, a list in JSON, raw bytes in MessagePack."""

    dtype_ = np.float32


class Float64Array(_TypedArray):
    """A float64 array field."""

    dtype_ = np.float64


class Int8Array(_TypedArray):
    """An int8 array field (occupancy grid cells)."""

    dtype_ = np.int8


class UInt8Array(_TypedArray):
    """A uint8[] / byte[] / char[] field (an image's, a point cloud's bytes): numpy in Python,
    base64 in JSON (as rosbridge sends it; a list of numbers is read too), raw bytes in
    MessagePack, a zero-copy view of the payload when received."""

    dtype_ = np.uint8


def to_array(cls: type[_TypedArray], value: Any) -> Any:
    """Coerce bytes (zero-copy view), a list or an array into ``cls``."""
    if isinstance(value, (bytes, bytearray, memoryview)):
        arr = np.frombuffer(value, dtype=cls.dtype_)
    else:
        arr = np.asarray(value, dtype=cls.dtype_)
        if arr.ndim != 1:
            arr = arr.reshape(-1)
    return arr.view(cls)


def array_field(cls: type[_TypedArray], values: Any = ()) -> Any:
    """A struct field default: an array of ``cls`` (empty unless ``values`` given)."""
    return msgspec.field(default_factory=lambda: to_array(cls, list(values)))
