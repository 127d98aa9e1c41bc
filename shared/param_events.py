"""``/parameter_events`` as ROS 2 has it: each node publishes a `ParameterEvent` when it
declares a parameter (``new_parameters``) and when one changes (``changed_parameters``),
whoever changed it (code, a set call, the parameter server); `ParameterEventHandler` follows
other nodes' parameters (rclpy's class of that name, its methods and semantics).

Values travel as ROS 2's ``rcl_interfaces/ParameterValue``. A zenros parameter may also hold a
dict or a list mixing types, which ROS 2 cannot: such a value is sent as a string of its JSON
text (``PARAMETER_STRING``), and a ``list`` of ints and floats as ``PARAMETER_DOUBLE_ARRAY``.
"""

from __future__ import annotations

import json
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

from .msgs.builtin_interfaces import Time
from .msgs.rcl_interfaces import Parameter as ParameterMsg
from .msgs.rcl_interfaces import ParameterEvent, ParameterType, ParameterValue
from .names import join, validate_namespace
from .params import Parameter
from .qos import Durability, QoSProfile, Reliability

__all__ = ["PARAMETER_EVENTS", "QOS_PARAMETER_EVENTS", "ParameterCallbackHandle",
           "ParameterEventCallbackHandle", "ParameterEventHandler", "from_parameter_value",
           "parameter_event", "to_parameter_value"]

PARAMETER_EVENTS = "/parameter_events"
QOS_PARAMETER_EVENTS = QoSProfile(depth=1000, reliability=Reliability.RELIABLE,
                                  durability=Durability.VOLATILE)
"""rclpy's ``qos_profile_parameter_events``: reliable, volatile, keep the last 1000."""

T = ParameterType


def _array(values: list[Any]) -> ParameterValue | None:
    if all(type(v) is bool for v in values):
        return ParameterValue(type=T.PARAMETER_BOOL_ARRAY, bool_array_value=list(values))
    if all(type(v) is int for v in values):
        return ParameterValue(type=T.PARAMETER_INTEGER_ARRAY, integer_array_value=list(values))
    if all(type(v) in (int, float) for v in values):
        return ParameterValue(type=T.PARAMETER_DOUBLE_ARRAY,
                              double_array_value=[float(v) for v in values])
    if all(type(v) is str for v in values):
        return ParameterValue(type=T.PARAMETER_STRING_ARRAY, string_array_value=list(values))
    return None


def to_parameter_value(value: Any) -> ParameterValue:
    """A zenros parameter value as ROS 2's ``ParameterValue`` (module docstring for dicts)."""
    if value is None:
        return ParameterValue(type=T.PARAMETER_NOT_SET)
    if type(value) is bool:
        return ParameterValue(type=T.PARAMETER_BOOL, bool_value=value)
    if type(value) is int:
        return ParameterValue(type=T.PARAMETER_INTEGER, integer_value=value)
    if type(value) is float:
        return ParameterValue(type=T.PARAMETER_DOUBLE, double_value=value)
    if type(value) is str:
        return ParameterValue(type=T.PARAMETER_STRING, string_value=value)
    if isinstance(value, (bytes, bytearray)):
        return ParameterValue(type=T.PARAMETER_BYTE_ARRAY, byte_array_value=list(value))
    if isinstance(value, list):
        if not value:  # ROS 2 has no untyped array
            return ParameterValue(type=T.PARAMETER_STRING_ARRAY)
        array = _array(value)
        if array is not None:
            return array
    return ParameterValue(type=T.PARAMETER_STRING, string_value=json.dumps(value, default=repr))


def from_parameter_value(pv: ParameterValue) -> Any:
    """The Python value a ``ParameterValue`` holds (rclpy's ``parameter_value_to_python``);
    None for ``PARAMETER_NOT_SET``.

    Raises:
        ValueError: ``pv.type`` is not a ParameterType constant.
    """
    fields = {T.PARAMETER_NOT_SET: None, T.PARAMETER_BOOL: "bool_value",
              T.PARAMETER_INTEGER: "integer_value", T.PARAMETER_DOUBLE: "double_value",
              T.PARAMETER_STRING: "string_value", T.PARAMETER_BYTE_ARRAY: "byte_array_value",
              T.PARAMETER_BOOL_ARRAY: "bool_array_value",
              T.PARAMETER_INTEGER_ARRAY: "integer_array_value",
              T.PARAMETER_DOUBLE_ARRAY: "double_array_value",
              T.PARAMETER_STRING_ARRAY: "string_array_value"}
    if pv.type not in fields:
        raise ValueError(f"unknown parameter type {pv.type} (ParameterType has 0-9)")
    name = fields[pv.type]
    if name == "byte_array_value":
        return bytes(pv.byte_array_value)
    return None if name is None else getattr(pv, name)


def parameter_event(kind: str, p: Parameter, node: str, stamp: Time) -> ParameterEvent:
    """The event a node publishes when it declared (``kind`` "new"), changed ("changed") or
    deleted ("deleted": a dynamically typed parameter set to PARAMETER_NOT_SET) ``p``; `Node`
    publishes it on /parameter_events."""
    event = ParameterEvent(stamp=stamp, node=node)
    if kind == "deleted":
        event.deleted_parameters.append(ParameterMsg(name=p.name))
        return event
    msg = ParameterMsg(name=p.name, value=to_parameter_value(p.value))
    (event.new_parameters if kind == "new" else event.changed_parameters).append(msg)
    return event


class EventNode(Protocol):
    """What `ParameterEventHandler` needs of its node (a `zenros.node.Node`)."""

    namespace: str

    def create_subscription(self, msg_type: Any, topic: str, callback: Any,
                            qos: Any = ...) -> Any: ...


@dataclass(eq=False)
class ParameterCallbackHandle:
    """What `ParameterEventHandler.add_parameter_callback` returns (to remove it)."""

    parameter_name: str
    node_name: str
    callback: Callable[[ParameterMsg], None]


@dataclass(eq=False)
class ParameterEventCallbackHandle:
    """What `ParameterEventHandler.add_parameter_event_callback` returns."""

    callback: Callable[[ParameterEvent], None]


class ParameterEventHandler:
    """Follow the parameters of other nodes, as rclpy's ``ParameterEventHandler``: a callback
    per (parameter, node), called with the new ``Parameter`` when that node declares or
    changes it, and callbacks for every event. Node names are resolved against ``node``'s
    namespace (``"talker"`` from a node in ``/robot1`` is ``/robot1/talker``)."""

    def __init__(self, node: EventNode,
                 qos_profile: QoSProfile = QOS_PARAMETER_EVENTS) -> None:
        self.node = node
        self._lock = threading.Lock()
        self._parameter_callbacks: dict[tuple[str, str], list[ParameterCallbackHandle]] = {}
        self._event_callbacks: list[ParameterEventCallbackHandle] = []
        self.subscription = node.create_subscription(ParameterEvent, PARAMETER_EVENTS,
                                                     self.event_callback, qos_profile)

    def _resolve(self, node_name: str) -> str:
        if node_name.startswith("/"):
            return node_name
        return join(validate_namespace(self.node.namespace), node_name)

    def add_parameter_callback(self, parameter_name: str, node_name: str,
                               callback: Callable[[ParameterMsg], None]
                               ) -> ParameterCallbackHandle:
        """Call ``callback(parameter)`` on each event of ``node_name`` naming
        ``parameter_name`` (declared or changed); the newest callback is called first."""
        handle = ParameterCallbackHandle(parameter_name, self._resolve(node_name), callback)
        with self._lock:
            self._parameter_callbacks.setdefault(
                (parameter_name, handle.node_name), []).insert(0, handle)
        return handle

    def remove_parameter_callback(self, handle: ParameterCallbackHandle) -> None:
        """Raises RuntimeError if ``handle`` is not registered (rclpy does the same)."""
        with self._lock:
            handles = self._parameter_callbacks.get((handle.parameter_name, handle.node_name))
            if not handles or handle not in handles:
                raise RuntimeError("Callback doesn't exist")
            handles.remove(handle)
            if not handles:
                del self._parameter_callbacks[(handle.parameter_name, handle.node_name)]

    def add_parameter_event_callback(self, callback: Callable[[ParameterEvent], None]
                                     ) -> ParameterEventCallbackHandle:
        """Call ``callback(event)`` for every parameter event of every node."""
        handle = ParameterEventCallbackHandle(callback)
        with self._lock:
            self._event_callbacks.insert(0, handle)
        return handle

    def remove_parameter_event_callback(self, handle: ParameterEventCallbackHandle) -> None:
        with self._lock:
            if handle not in self._event_callbacks:
                raise RuntimeError("Callback doesn't exist")
            self._event_callbacks.remove(handle)

    def event_callback(self, event: ParameterEvent) -> None:
        with self._lock:
            wanted = [(h, p) for (name, node), hs in self._parameter_callbacks.items()
                      if node == event.node
                      and (p := self.get_parameter_from_event(event, name, node)) is not None
                      for h in hs]
            every = list(self._event_callbacks)
        for h, p in wanted:
            h.callback(p)
        for e in every:
            e.callback(event)

    @staticmethod
    def get_parameter_from_event(event: ParameterEvent, parameter_name: str,
                                 node_name: str) -> ParameterMsg | None:
        """The parameter ``parameter_name`` of ``node_name`` declared or changed in
        ``event``, else None."""
        if event.node != node_name:
            return None
        for p in (*event.new_parameters, *event.changed_parameters):
            if p.name == parameter_name:
                return p
        return None

    @staticmethod
    def get_parameters_from_event(event: ParameterEvent) -> list[ParameterMsg]:
        """Every parameter declared or changed in ``event``."""
        return [*event.new_parameters, *event.changed_parameters]

    def destroy(self) -> None:
        self.subscription.close()
