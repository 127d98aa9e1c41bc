"""`TopicHub`: one zenros subscription per topic, fanned out as JSON text to many clients.

Each client holds only the newest frame (a slot plus an event): a slow client skips to the
latest message and never holds up the others, the robot, or Zenoh's receive thread. A large
message (a map: 100-160 ms of JSON encoding in one C call that keeps the GIL) is encoded on
a worker thread, a slice at a time (`zenros.json_chunks`), so the small topics' messages
keep flowing meanwhile.
"""

from __future__ import annotations

import asyncio
import threading
from typing import Any

import msgspec
from zenros.codec import from_builtins, json_bytes
from zenros.errors import DecodeError, UnknownTypeError
from zenros.json_chunks import BulkEncoder, encode_yielding, is_bulky
from zenros.message import Message
from zenros.names import Token
from zenros.node import Node
from zenros.pubsub import Publisher, Subscription
from zenros.qos import Durability, QoSProfile
from zenros.registry import lookup_type

from ..ws_slices import Utf8Text

__all__ = ["Slot", "TopicError", "TopicHub"]



class TopicError(Exception):
    """A topic the hub cannot stream or publish to (unknown type, bad name, bad frame)."""


class Slot:
    """The newest frame for one client, and an event that says a new one is there."""

    def __init__(self, loop: asyncio.AbstractEventLoop) -> None:
        self.loop = loop
        self.frame: str | None = None
        self.event = asyncio.Event()
        self.dropped = 0

    def put(self, frame: str) -> None:  # on the loop
        if self.frame is not None:
            self.dropped += 1
        self.frame = frame
        self.event.set()

    async def get(self) -> str:
        while self.frame is None:
            self.event.clear()
            await self.event.wait()
        frame, self.frame = self.frame, None
        return frame


class _Feed:
    def __init__(self, msg_type: type[Message]) -> None:
        self.sub: Subscription[Any] | None = None
        self.msg_type = msg_type
        self.slots: list[Slot] = []
        self.last: str | None = None
        self.in_worker = 0  # messages on the bulk encoder: later ones follow them


class TopicHub:
    """Streams topics to `Slot`s and publishes client frames, for the WebSocket front end."""

    def __init__(self, node: Node) -> None:
        self.node: Node = node
        self._feeds: dict[str, _Feed] = {}
        self._pubs: dict[str, Publisher[Any]] = {}
        self._lock = threading.Lock()
        self._bulk = BulkEncoder("topic-hub-encode")

    def resolve(self, path: str) -> str:
        """The topic a URL path names (relative to the robot's namespace)."""
        name = path.strip("/")
        if not name:
            raise TopicError("no topic in the URL: use ws://host:port/<topic>")
        try:
            return str(self.node.resolve_name(name))
        except ValueError as exc:
            raise TopicError(f"bad topic name {name!r}: {exc}") from exc

    def type_of(self, topic: str) -> tuple[type[Message], bool]:
        """The message type the graph knows for ``topic`` and whether it is latched."""
        graph = self.node.graph
        tokens = graph.publishers(topic) + graph.subscribers(topic)
        types = sorted({t.type for t in tokens if t.type})
        if not types:
            raise TopicError(f"unknown topic {topic}: nobody publishes or subscribes to it")
        try:
            cls = lookup_type(types[0])
        except UnknownTypeError as exc:
            raise TopicError(str(exc)) from exc
        latched = any(QoSProfile.from_tag(t.qos).latched for t in graph.publishers(topic))
        return cls, latched

    async def wait_listed(self, topic: str) -> None:
        """Return once the graph lists a typed publisher or subscriber of ``topic`` (a client
        may connect before the graph has heard of the topic's first endpoint)."""
        loop = asyncio.get_running_loop()
        listed = asyncio.Event()

        def on_change(event: str, token: Token) -> None:  # on Zenoh's thread
            if event == "put" and token.name == topic and token.type:
                loop.call_soon_threadsafe(listed.set)

        remove = self.node.graph.add_listener(on_change)
        try:
            graph = self.node.graph
            if not any(t.type for t in graph.publishers(topic) + graph.subscribers(topic)):
                await listed.wait()
        finally:
            remove()

    def attach(self, topic: str, slot: Slot) -> None:
        """Start feeding ``slot``; a latched topic's last value comes first."""
        msg_type, latched = self.type_of(topic)
        with self._lock:
            feed = self._feeds.get(topic)
            created = feed is None
            if feed is None:
                feed = self._feeds[topic] = _Feed(msg_type)
            feed.slots.append(slot)
            last = feed.last
        if created:
            # outside the lock: latched history may be delivered during this call
            qos = QoSProfile(depth=1, durability=Durability.TRANSIENT_LOCAL) if latched \
                else QoSProfile(depth=1)
            the_feed = feed
            feed.sub = self.node.create_subscription(
                msg_type, topic, lambda m: self._on_message(the_feed, m), qos)
        elif last is not None:
            slot.loop.call_soon_threadsafe(slot.put, last)

    def detach(self, topic: str, slot: Slot) -> None:
        with self._lock:
            feed = self._feeds.get(topic)
            if feed is None or slot not in feed.slots:
                return
            feed.slots.remove(slot)
            if not feed.slots:
                del self._feeds[topic]
                if feed.sub is not None:
                    self.node.destroy(feed.sub)

    def slots(self, topic: str) -> list[Slot]:
        with self._lock:
            feed = self._feeds.get(topic)
            return list(feed.slots) if feed is not None else []

    def _on_message(self, feed: _Feed, msg: Message) -> None:  # on Zenoh's thread
        bulky = is_bulky(msg)
        with self._lock:
            offload = bulky or feed.in_worker > 0
            if offload:
                feed.in_worker += 1
        if offload:
            self._bulk.submit(lambda: self._encode_off_thread(feed, msg, bulky))
        else:
            self._fan_out(feed, json_bytes(msg).decode())  # straight to JSON, one pass

    def _encode_off_thread(self, feed: _Feed, msg: Message, bulky: bool) -> None:
        try:
            # bulky: its clients' senders write these bytes, not the text encoded again each
            frame: str = (Utf8Text(encode_yielding(msg)) if bulky
                          else json_bytes(msg).decode())
        finally:
            with self._lock:
                feed.in_worker -= 1
        self._fan_out(feed, frame)

    def _fan_out(self, feed: _Feed, frame: str) -> None:
        with self._lock:
            feed.last = frame
            slots = list(feed.slots)
        by_loop: dict[asyncio.AbstractEventLoop, list[Slot]] = {}
        for s in slots:
            by_loop.setdefault(s.loop, []).append(s)
        for loop, group in by_loop.items():
            try:
                loop.call_soon_threadsafe(_put_all, group, frame)
            except RuntimeError:  # loop closed at shutdown
                pass

    def publish_json(self, topic: str, text: str) -> None:
        """Decode a client's JSON frame as the topic's type and publish it.

        Raises:
            TopicError: not JSON, not an object, or not a valid message of the topic's type.
        """
        try:
            obj = msgspec.json.decode(text)
        except msgspec.DecodeError as exc:
            raise TopicError(f"malformed JSON: {exc}") from exc
        except RecursionError as exc:
            raise TopicError("malformed JSON: nested too deep") from exc
        if not isinstance(obj, dict):
            raise TopicError(f"expected a JSON object, got {type(obj).__name__}")
        msg_type, _ = self.type_of(topic)
        try:
            msg = from_builtins(obj, msg_type)
        except DecodeError as exc:
            raise TopicError(str(exc)) from exc
        with self._lock:
            pub = self._pubs.get(topic)
            if pub is None or pub.msg_type is not msg_type:
                pub = self.node.create_publisher(msg_type, topic, 10)
                self._pubs[topic] = pub
        pub.publish(msg)


def _put_all(slots: list[Slot], frame: str) -> None:
    for s in slots:
        s.put(frame)
