"""`TopicOps`: the rosbridge topic ops (advertise, publish, subscribe and their reverses), a
`Capability` of one client's session."""

from __future__ import annotations

from typing import Any

from .capability import Capability, Session
from .convert import message_from_json
from .frames import (
    Advertise,
    OpError,
    Publish,
    SubOptions,
    Subscribe,
    Unadvertise,
    Unsubscribe,
    frame_int,
    frame_name,
    frame_text,
)

__all__ = ["CBOR", "COMPRESSIONS", "TopicOps"]

CBOR = ("cbor", "cbor-raw")
"""The ``compression`` values sent as binary CBOR frames (cbor.py)."""
COMPRESSIONS = ("png", *CBOR)
"""The ``compression`` values served; any other is sent as plain JSON, as the reference does."""


class TopicOps(Capability):
    """One client's advertisements and subscriptions; its session is the bridge `Sink` the
    topics are fed to, in the format `compression` says."""

    ops = {Advertise: "op_advertise", Unadvertise: "op_unadvertise", Publish: "op_publish",
           Subscribe: "op_subscribe", Unsubscribe: "op_unsubscribe"}

    def __init__(self, session: Session) -> None:
        super().__init__(session)
        self.outbox = session.outbox
        self.advertised: set[str] = set()
        self.subs: dict[str, dict[Any, SubOptions]] = {}
        self.compression: dict[str, str] = {}
        """Topics sent compressed (``png``, ``cbor`` or ``cbor-raw``), the others as JSON
        (encodings.py)."""

    def format_of(self, topic: str) -> str:
        return self.compression.get(topic, "json")

    def op_advertise(self, frame: Advertise) -> None:
        topic = frame_name(frame, "topic")
        type_name = frame_text(frame, "type")
        if not self.bridge.known(type_name):  # carried between rosbridge clients, unchecked
            self.bridge.opaque.advertise(topic, type_name, self.session)
            self.bridge.actionlib.advertised(topic, type_name)
            return
        msg_type = self.bridge.topic_type(topic, type_name)
        if topic in self.advertised and self.bridge.publishers[topic][0].msg_type is msg_type:
            return  # a replay after reconnect, or a second advertise: nothing to do
        self.bridge.advertise(topic, msg_type, self.session, frame.latch,
                              frame_int(frame, "queue_size", 100))
        self.advertised.add(topic)

    def op_unadvertise(self, frame: Unadvertise) -> None:
        topic = frame_name(frame, "topic")
        self.bridge.opaque.unadvertise(topic, self.session)
        if topic in self.advertised:
            self.advertised.discard(topic)
            self.bridge.unadvertise(topic, self.session)

    def op_publish(self, frame: Publish) -> None:
        topic = frame_name(frame, "topic")
        if topic not in self.advertised and topic in self.bridge.opaque.topics:
            if topic not in self.bridge.opaque.hooks:  # the zenros action may have come since
                self.bridge.actionlib.advertised(topic, self.bridge.opaque.topics[topic].type_name)
            self.bridge.opaque.publish(topic, frame.msg)
            return
        if topic not in self.advertised:
            entry = self.bridge.publishers.get(topic)
            known = self.bridge.node.graph.topics().get(topic)
            if entry is None and not known:
                raise OpError(f"Cannot infer topic type for topic {topic} as it is not yet "
                              "advertised")
            msg_type = entry[0].msg_type if entry else self.bridge.topic_type(topic, None)
            self.bridge.advertise(topic, msg_type, self.session,
                                  frame.latch, 100)
            self.advertised.add(topic)
        pub = self.bridge.publishers[topic][0]
        msg = message_from_json(frame.msg, pub.msg_type, self.bridge.node.now())
        pub.publish(msg)

    def op_subscribe(self, frame: Subscribe) -> None:
        topic = frame_name(frame, "topic")
        type_name = frame.type
        compression = frame.compression
        opts = SubOptions(throttle_rate=frame_int(frame, "throttle_rate"),
                          queue_length=frame_int(frame, "queue_length"),
                          fragment_size=frame_int(frame, "fragment_size"),
                          compression=compression if compression in COMPRESSIONS else "none")
        opaque = self.bridge.opaque.topics.get(topic)
        if topic not in self.subs:
            if type_name and not self.bridge.known(type_name):  # unchecked, between clients
                self.bridge.opaque.attach(topic, type_name, self.session)
                self.bridge.actionlib.subscribed(topic, type_name, self.session)
            elif not type_name and opaque is not None and topic not in self.bridge.feeds:
                self.bridge.opaque.attach(topic, opaque.type_name, self.session)
            else:
                msg_type = self.bridge.topic_type(topic, type_name or None)
                self.bridge.attach(topic, msg_type, self.session)
            self.subs[topic] = {}
        elif type_name and topic in self.bridge.feeds:
            feed = self.bridge.feeds[topic]
            if self.bridge.topic_type(topic, type_name) is not feed.msg_type:
                raise OpError(f"{topic} is already subscribed with type {feed.type_name}")
        self.subs[topic][frame.id] = opts
        self._configure(topic)

    def _configure(self, topic: str) -> None:
        opts = list(self.subs[topic].values())
        fragments = [o.fragment_size for o in opts if o.fragment_size > 0]
        self.outbox.configure(topic, min(o.throttle_rate for o in opts),
                              max(o.queue_length for o in opts),
                              min(fragments) if fragments else 0)
        wanted = {o.compression for o in opts}  # as the reference: cbor-raw, cbor, png, none
        fmt = next((f for f in ("cbor-raw", "cbor", "png") if f in wanted), None)
        if fmt is None:
            self.compression.pop(topic, None)
        else:
            self.compression[topic] = fmt

    def op_unsubscribe(self, frame: Unsubscribe) -> None:
        topic = frame_name(frame, "topic")
        ids = self.subs.get(topic)
        if ids is None:
            return
        mid = frame.id
        if mid is not None and mid in ids and len(ids) > 1:
            del ids[mid]
            self._configure(topic)
            return
        if mid is not None and mid not in ids:
            return
        self._drop_subscription(topic)

    def _drop_subscription(self, topic: str) -> None:
        self.subs.pop(topic, None)
        self.compression.pop(topic, None)
        self.outbox.remove(topic)
        self.bridge.detach(topic, self.session)

    def close(self) -> None:
        for topic in list(self.subs):
            self._drop_subscription(topic)
        for topic in list(self.advertised):
            self.bridge.unadvertise(topic, self.session)
        self.advertised.clear()
        opaque = self.bridge.opaque
        for topic in [t for t, e in opaque.topics.items() if self.session in e.advertisers]:
            opaque.unadvertise(topic, self.session)
