"""`Bridge`: the zenros endpoints every rosbridge client shares (one per topic, service,
action), created on demand through a zenros `Node` and released when the last client goes."""

from __future__ import annotations

import asyncio
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Protocol

from zenros.action.cancel import send_cancel
from zenros.action.types import CancelGoalRequest, CancelGoalResponse
from zenros.errors import InvalidNameError, UnknownTypeError, ZenrosError
from zenros.json_chunks import BulkEncoder, is_bulky
from zenros.message import ActionType, Message, ServiceType, normalize_type_name
from zenros.node import Node
from zenros.param_client import ParameterClient
from zenros.qos import Durability, QoSProfile, Reliability
from zenros.registry import lookup_type

from .actionlib import ActionlibBridge, actionlib_topics
from .convert import long_type
from .encodings import Encodings
from .opaque import OpaqueTopics
from .rosapi import Rosapi
from .tf_republisher import ACTION as TF_REPUBLISH_ACTION
from .tf_republisher import SERVICE as TF_REPUBLISH_SERVICE
from .tf_republisher import TFRepublisher

if TYPE_CHECKING:
    from zenros.pubsub import Publisher, Subscription
    from zenros.rpc import Client

__all__ = ["Bridge", "BridgeError", "Encode", "Sink", "qos_for_publishers"]


class BridgeError(ValueError):
    """A request the bridge refuses (unknown type, type conflict, no such topic)."""


Encode = Callable[[str], bytes]
"""A topic message as a frame of the format named (encodings.py), encoded once per format."""


class Sink(Protocol):
    """A client that receives topic frames."""

    def deliver(self, topic: str, encode: Encode) -> None: ...

    def format_of(self, topic: str) -> str:
        """The format (`FORMATS`) this client takes ``topic`` in."""
        ...


def qos_for_publishers(tags: list[str]) -> QoSProfile:
    """A subscription profile that hears every publisher: latched if any is, best effort
    only if all are."""
    profiles = [QoSProfile.from_tag(t) for t in tags]
    latched = any(p.latched for p in profiles)
    best_effort = bool(profiles) and all(p.reliability == Reliability.BEST_EFFORT
                                         for p in profiles)
    return QoSProfile(
        depth=10,
        reliability=Reliability.BEST_EFFORT if best_effort else Reliability.RELIABLE,
        durability=Durability.TRANSIENT_LOCAL if latched else Durability.VOLATILE,
    )


class TopicFeed:
    """One subscription shared by every client on a topic; encodes each message once per
    format. A large message (a map, a cloud) is encoded on the bridge's worker thread, a
    slice at a time, in the formats its clients take: neither Zenoh's thread (which brings
    the small messages too) nor the loop (which sends them) waits for it."""

    def __init__(self, bridge: Bridge, topic: str, msg_type: type[Message]) -> None:
        self.topic = topic
        self.msg_type = msg_type
        self.type_name = normalize_type_name(msg_type.__msgtype__)
        self.sinks: set[Sink] = set()
        self._loop = bridge.loop
        self._bulk = bridge.bulk
        self._lock = threading.Lock()
        self._pending: list[Encodings] = []
        self._in_worker = 0  # messages of this topic on the worker: later ones follow them
        self._now = bridge.node.now
        self._scheduled = False
        tags = [t.qos for t in bridge.node.graph.publishers(topic)]
        self.sub: Subscription[Any] = bridge.node.create_subscription(
            msg_type, topic, self._on_message, qos_for_publishers(tags))

    def _on_message(self, msg: Message) -> None:  # on Zenoh's thread
        bulky = is_bulky(msg)
        encodings = Encodings(self.topic, msg, now=self._now, bulky=bulky)
        with self._lock:
            offload = bulky or self._in_worker > 0
            if offload:
                self._in_worker += 1
        if offload:
            self._bulk.submit(lambda: self._encode_off_loop(encodings))
            return
        encodings("json")  # small: at once, here (most clients take JSON)
        self._queue(encodings)

    def _encode_off_loop(self, encodings: Encodings) -> None:  # on the worker
        try:
            for fmt in {sink.format_of(self.topic) for sink in tuple(self.sinks)}:
                try:
                    encodings(fmt)
                except (ValueError, TypeError, ZenrosError):
                    pass  # reported to each client that asks for it (ClientProtocol.deliver)
        finally:
            with self._lock:
                self._in_worker -= 1
        self._queue(encodings)

    def _queue(self, encodings: Encodings) -> None:
        with self._lock:
            self._pending.append(encodings)
            if self._scheduled:
                return
            self._scheduled = True
        try:  # one loop wake-up carries every frame that arrives before it runs
            self._loop.call_soon_threadsafe(self._fan_out)
        except RuntimeError:  # the loop closed under a late sample at shutdown
            pass

    def _fan_out(self) -> None:
        with self._lock:
            batch, self._pending = self._pending, []
            self._scheduled = False
        sinks = tuple(self.sinks)
        for encodings in batch:
            for sink in sinks:
                sink.deliver(self.topic, encodings)


class Bridge:
    """Shared endpoints and the rosapi, for the clients of one rosbridge server.

    Every method runs on the server's event loop (``loop``).
    """

    def __init__(self, node: Node, loop: asyncio.AbstractEventLoop) -> None:
        self.node = node
        self.loop = loop
        self.bulk = BulkEncoder("rosbridge-encode")
        """Encodes large messages off Zenoh's thread and off the loop (TopicFeed)."""
        self.feeds: dict[str, TopicFeed] = {}
        self.publishers: dict[str, tuple[Publisher[Any], set[object]]] = {}
        self._clients: dict[tuple[str, str], Client] = {}
        self._action_clients: dict[tuple[str, str], Any] = {}
        self.params = ParameterClient(node.context, timeout=2.5)
        self.opaque = OpaqueTopics()
        self.tf_republisher = TFRepublisher(self)
        self.background: set[asyncio.Task[Any]] = set()
        """Tasks the bridge runs for no one client (actionlib.py), kept until done."""
        self.actionlib = ActionlibBridge(self)
        self.rosapi = Rosapi(node.graph, self.params, node.now, local=self._local_names)

    def _local_names(self) -> tuple[dict[str, str], dict[str, str]]:
        """Topics and services only rosbridge clients see, for rosapi: those clients
        advertised (unregistered types), else the actionlib topics of the actions the bridge
        offers ROS 1 clients (the zenros actions and tf2_web_republisher's)."""
        services = self.opaque.service_types()
        services[TF_REPUBLISH_SERVICE] = "tf2_web_republisher/srv/RepublishTFs"
        topics = self.actionlib.offered_topics()
        topics.update(actionlib_topics(TF_REPUBLISH_ACTION, "tf2_web_republisher/TFSubscription"))
        topics.update(self.opaque.advertised_topics())
        return topics, services

    @staticmethod
    def known(type_name: str, lookup: Callable[[str], Any] = lookup_type) -> bool:
        """Whether zenros has a definition for ``type_name``."""
        try:
            lookup(type_name)
        except UnknownTypeError:
            return False
        return True

    # ------------------------------------------------------------------ types

    def topic_type(self, topic: str, requested: str | None) -> type[Message]:
        """The message class for a subscription: the requested type, else the graph's.

        Raises:
            BridgeError: unknown type, or no type given for a topic nobody advertises.
        """
        if requested:
            try:
                return lookup_type(requested)
            except UnknownTypeError as exc:
                raise BridgeError(str(exc)) from None
        known = self.node.graph.topics().get(topic, [])
        if not known:
            raise BridgeError(f"Cannot infer topic type for topic {topic} as it is not yet "
                              "advertised")
        try:
            return lookup_type(known[0])
        except UnknownTypeError as exc:
            raise BridgeError(str(exc)) from None

    # ------------------------------------------------------------------ topics

    def attach(self, topic: str, msg_type: type[Message], sink: Sink) -> None:
        """Start feeding ``sink`` with ``topic``.

        Raises:
            BridgeError: the topic is already bridged with another type.
            InvalidNameError: the topic name is not valid.
        """
        feed = self.feeds.get(topic)
        if feed is None:
            feed = self.feeds[topic] = TopicFeed(self, topic, msg_type)
        elif feed.msg_type is not msg_type:
            raise BridgeError(f"{topic} already established with type "
                              f"{long_type(feed.type_name)}, not {long_type(msg_type.__msgtype__)}")
        feed.sinks.add(sink)

    def detach(self, topic: str, sink: Sink) -> None:
        self.opaque.detach(topic, sink)
        feed = self.feeds.get(topic)
        if feed is None:
            return
        feed.sinks.discard(sink)
        if not feed.sinks:
            del self.feeds[topic]
            self.node.destroy(feed.sub)

    def advertise(self, topic: str, msg_type: type[Message], owner: object, latch: bool,
                  queue_size: int) -> Publisher[Any]:
        """A publisher of ``topic`` shared by its advertisers (``owner`` is one of them).

        Raises:
            BridgeError: the topic is published here with another type.
        """
        entry = self.publishers.get(topic)
        if entry is None:
            qos = QoSProfile(depth=max(1, min(queue_size or 10, 1000)),
                             durability=Durability.TRANSIENT_LOCAL if latch else Durability.VOLATILE)
            entry = self.publishers[topic] = (
                self.node.create_publisher(msg_type, topic, qos), set())
        elif entry[0].msg_type is not msg_type:
            raise BridgeError(f"{topic} already advertised with type "
                              f"{long_type(entry[0].type_name)}, not "
                              f"{long_type(msg_type.__msgtype__)}")
        entry[1].add(owner)
        return entry[0]

    def unadvertise(self, topic: str, owner: object) -> None:
        entry = self.publishers.get(topic)
        if entry is None:
            return
        entry[1].discard(owner)
        if not entry[1]:
            del self.publishers[topic]
            self.node.destroy(entry[0])

    # ------------------------------------------------------------------ services, actions

    def service_type_of(self, service: str) -> str | None:
        types = self.node.graph.services().get(service)
        return types[0] if types else None

    def client(self, srv_type: ServiceType, name: str) -> Client:
        key = (name, srv_type.name)
        c = self._clients.get(key)
        if c is None:
            c = self._clients[key] = self.node.create_client(srv_type, name)
        return c

    def action_client(self, action_type: ActionType, name: str) -> Any:
        key = (name, action_type.name)
        c = self._action_clients.get(key)
        if c is None:
            c = self._action_clients[key] = self.node.create_action_client(action_type, name)
        return c

    def has_action(self, action: str) -> bool:
        """Whether a zenros action server of ``action`` is in the graph."""
        return bool(self.node.graph.actions().get(action))

    def cancel_goals(self, action: str, request: CancelGoalRequest,
                     timeout: float) -> CancelGoalResponse:
        """The ROS 2 hidden service ``<action>/_action/cancel_goal`` of a zenros action: one
        goal, every goal (zero ``goal_id``) or every goal accepted by ``stamp``. Blocks (call
        it off the loop)."""
        ctx = self.node.context
        key = ctx.keys.action(action, "cancel_goal")
        return send_cancel(ctx.session, key, action, request, timeout, ctx.destination(key))

    def serve(self, srv_type: ServiceType, name: str, handler: Callable[..., Any]) -> Any:
        """A zenros service whose requests ``handler`` answers (a browser's service)."""
        try:
            return self.node.create_service(srv_type, name, handler)
        except InvalidNameError as exc:
            raise BridgeError(str(exc)) from None

    def release(self, endpoint: Any) -> None:
        self.node.destroy(endpoint)

    def close(self) -> None:
        self.bulk.close()
        self.tf_republisher.close()
        self.actionlib.close()
        for topic in list(self.feeds):
            feed = self.feeds.pop(topic)
            self.node.destroy(feed.sub)
        for pub, _ in self.publishers.values():
            self.node.destroy(pub)
        self.publishers.clear()
        for c in self._clients.values():
            self.node.destroy(c)
        self._clients.clear()
        for ac in self._action_clients.values():
            self.node.destroy(ac)
        self._action_clients.clear()
