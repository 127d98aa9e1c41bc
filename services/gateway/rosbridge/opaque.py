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

from .convert import dumps, long_type, publish_frame

__all__ = ["OpaqueService", "OpaqueTopic", "OpaqueTopics"]


@dataclass
class OpaqueTopic:
    """One unchecked topic: its type name as the clients gave it, who publishes, who listens."""

    type_name: str
    sinks: set[Any] = field(default_factory=set)
    advertisers: set[object] = field(default_factory=set)


@dataclass
class OpaqueService:
    """A service of an unregistered type, served by the rosbridge client ``owner``."""

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
        frame = publish_frame(topic, dumps(msg if msg is not None else {}))
        for sink in tuple(entry.sinks):
            sink.deliver(topic, frame)

    def listeners(self, topic: str) -> int:
        """How many clients subscribe to ``topic``."""
        entry = self.topics.get(topic)
        return len(entry.sinks) if entry is not None else 0

    def advertised_topics(self) -> dict[str, str]:
        """Topics some client advertised, with their types in the long form (for rosapi)."""
        return {n: long_type(e.type_name) for n, e in self.topics.items() if e.advertisers}

    def service_types(self) -> dict[str, str]:
        return {n: long_type(s.type_name, "srv") for n, s in self.services.items()}
