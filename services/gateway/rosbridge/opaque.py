"""Types zenros has no definition for (``rospy_tutorials/AddTwoInts``, ``actionlib/TestAction``
...), carried between the rosbridge clients of one server as JSON nobody checks.

The reference server knows every type installed on its machine; zenros knows the types it
registers. A topic or service whose type is not registered is still served between rosbridge
clients: messages go from a client's ``publish`` to the other clients' subscriptions as the
client wrote them, a call goes to the client that advertised the service and its answer comes
back, all without a zenros endpoint (no zenros node sees them).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from zenros.message import normalize_type_name

from .convert import dumps, long_type, publish_frame
from .encodings import Encodings

__all__ = ["ROS1_DEFAULTS", "OpaqueService", "OpaqueTopic", "OpaqueTopics"]

_STAMP = {"secs": 0, "nsecs": 0}
_HEADER = {"seq": 0, "stamp": _STAMP, "frame_id": ""}
_GOAL_ID = {"stamp": _STAMP, "id": ""}
_STATUS = {"goal_id": _GOAL_ID, "status": 0, "text": ""}


def _action(goal: dict[str, Any], result: dict[str, Any],
            feedback: dict[str, Any]) -> dict[str, dict[str, Any]]:
    return {"Goal": {"header": _HEADER, "goal_id": _GOAL_ID, "goal": goal},
            "Result": {"header": _HEADER, "status": _STATUS, "result": result},
            "Feedback": {"header": _HEADER, "status": _STATUS, "feedback": feedback}}


ROS1_DEFAULTS: dict[str, dict[str, Any]] = {
    "actionlib_msgs/GoalID": _GOAL_ID,
    "actionlib_msgs/GoalStatus": _STATUS,
    "actionlib_msgs/GoalStatusArray": {"header": _HEADER, "status_list": []},
    **{f"actionlib/TestAction{k}": v for k, v in _action(
        {"goal": 0}, {"result": 0}, {"feedback": 0}).items()},
    **{f"actionlib_tutorials/FibonacciAction{k}": v for k, v in _action(
        {"order": 0}, {"sequence": []}, {"sequence": []}).items()},
}
"""The default values of a few ROS 1 types that cross unchecked, filled in where a client
left a field out, as the reference (which knows the types) does: actionlib_msgs, and the
actionlib test and tutorial actions (actionlib/TestAction, actionlib_tutorials/Fibonacci).
roslibjs cancels with ``{}``, roslibpy with ``{"id": ...}``, and roslibpy's SimpleActionServer
ends a preempted goal without a ``result``; their peers read those fields."""


def _filled(defaults: Any, msg: Any) -> Any:
    if not isinstance(defaults, dict) or not isinstance(msg, dict):
        return msg
    out = {k: v for k, v in defaults.items() if k not in msg}
    for k, v in msg.items():
        out[k] = _filled(defaults.get(k), v)
    return out


@dataclass
class OpaqueTopic:
    """One unchecked topic: its type name as the clients gave it, who publishes, who listens."""

    type_name: str
    sinks: set[Any] = field(default_factory=set)
    advertisers: set[object] = field(default_factory=set)


@dataclass
class OpaqueService:
    """A service of an unregistered type, served by the rosbridge client ``owner`` (its
    session's `ops_services.ServiceOps`)."""

    type_name: str
    owner: Any


class OpaqueTopics:
    """The unchecked topics and services of one bridge (used on its loop only)."""

    def __init__(self) -> None:
        self.topics: dict[str, OpaqueTopic] = {}
        self.services: dict[str, OpaqueService] = {}
        self.hooks: dict[str, Callable[[Any], None]] = {}
        """Topics the bridge itself reads (tf_republisher.py): called with each message."""

    def _topic(self, topic: str, type_name: str) -> OpaqueTopic:
        entry = self.topics.get(topic)
        if entry is None:
            entry = self.topics[topic] = OpaqueTopic(type_name)
        return entry

    def attach(self, topic: str, type_name: str, sink: Any) -> None:
        self._topic(topic, type_name).sinks.add(sink)

    def detach(self, topic: str, sink: Any) -> None:
        entry = self.topics.get(topic)
        if entry is not None:
            entry.sinks.discard(sink)
            self._gc(topic, entry)

    def advertise(self, topic: str, type_name: str, owner: object) -> None:
        self._topic(topic, type_name).advertisers.add(owner)

    def unadvertise(self, topic: str, owner: object) -> None:
        entry = self.topics.get(topic)
        if entry is not None:
            entry.advertisers.discard(owner)
            self._gc(topic, entry)

    def _gc(self, topic: str, entry: OpaqueTopic) -> None:
        if not entry.sinks and not entry.advertisers:
            del self.topics[topic]

    def publish(self, topic: str, msg: Any) -> None:
        """Hand ``msg`` (a JSON object, unchecked) to every client subscribed to ``topic``
        (and to the bridge's own reader of it, if any)."""
        hook = self.hooks.get(topic)
        if hook is not None:
            hook(msg)
        entry = self.topics.get(topic)
        if entry is None:
            return
        defaults = ROS1_DEFAULTS.get(normalize_type_name(entry.type_name))
        if defaults is not None:
            msg = _filled(defaults, msg)
        encodings = Encodings(topic, json_frame=publish_frame(
            topic, dumps(msg if msg is not None else {})))
        for sink in tuple(entry.sinks):
            sink.deliver(topic, encodings)

    def listeners(self, topic: str) -> int:
        """How many clients subscribe to ``topic``."""
        entry = self.topics.get(topic)
        return len(entry.sinks) if entry is not None else 0

    def advertised_topics(self) -> dict[str, str]:
        """Topics some client advertised, with their types in the long form (for rosapi)."""
        return {n: long_type(e.type_name) for n, e in self.topics.items() if e.advertisers}

    def service_types(self) -> dict[str, str]:
        return {n: long_type(s.type_name, "srv") for n, s in self.services.items()}
