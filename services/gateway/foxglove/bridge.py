"""`FoxgloveBridge`: every typed topic of the graph as a Foxglove channel, fed by a zenros
subscription while a Foxglove client subscribes; client-published channels go to zenros.

A large message (a map) is encoded on a worker thread, a slice at a time
(`zenros.json_chunks`): Zenoh's thread, which brings the small topics' messages too, hands
it over and returns, and the SDK's sender (Rust, per client) keeps sending meanwhile.
"""

from __future__ import annotations

import json
import threading
import time
from typing import Any

try:
    import foxglove
    from foxglove import Channel, Schema
    from foxglove.websocket import Capability, ChannelView, Client, ClientChannel, WebSocketServer
except ModuleNotFoundError as exc:  # the optional extra is not installed
    raise ModuleNotFoundError(
        f"{__name__} needs foxglove-sdk, the extra zenros[foxglove]: pip install 'zenros[foxglove]'"
        f" ({exc})", name=exc.name) from exc
from zenros.errors import StartupError, UnknownTypeError, ZenrosError
from zenros.json_chunks import BulkEncoder, encode_yielding, is_bulky
from zenros.message import Message
from zenros.names import Token
from zenros.node import Node
from zenros.registry import lookup_type

from ..rosbridge import encode_message, message_from_json, qos_for_publishers
from .schema import schema_bytes, schema_name

__all__ = ["DEFAULT_PORT", "FoxgloveBridge"]

DEFAULT_PORT = 8765


class FoxgloveBridge:
    """Serves ``node``'s graph on a foxglove-sdk WebSocket server (``foxglove.sdk.v1``).

    Args:
        node: the node whose session and graph are bridged.
        host: the address to bind (127.0.0.1 unless configured).
        port: the TCP port (0 picks a free one; see ``port`` after `start`).
    """

    name = "Foxglove"  # as a front end of the gateway (front_ends.FrontEnd)

    def __init__(self, node: Node, host: str = "127.0.0.1", port: int = DEFAULT_PORT) -> None:
        self.node = node
        self.host = host
        self.port = port
        self.logger = node.logger.getChild("foxglove")
        self._ctx = foxglove.Context()
        self._lock = threading.RLock()
        self.channels: dict[str, Channel] = {}
        self._types: dict[str, type[Message]] = {}
        self._subs: dict[int, tuple[Any, set[int]]] = {}  # channel id -> (subscription, clients)
        self._client_pubs: dict[tuple[int, int], Any] = {}
        self._server: WebSocketServer | None = None
        self._unlisten: Any = None
        self._bulk = BulkEncoder("foxglove-encode")

    def start(self) -> None:
        """Start the server and advertise the graph's topics (and follow it from then on).

        Raises:
            StartupError: the server cannot start (the port is taken).
        """
        try:
            self._server = foxglove.start_server(
                name=f"zenros {self.node.fqn}", host=self.host, port=self.port,
                capabilities=[Capability.ClientPublish], supported_encodings=["json"],
                server_listener=self, context=self._ctx)
        except RuntimeError as exc:  # the SDK's FoxgloveError, e.g. the port is taken
            raise StartupError(f"Foxglove server on {self.host}:{self.port}: {exc}") from exc
        self.port = self._server.port
        graph = self.node.graph
        self._unlisten = graph.add_listener(self._on_graph)
        self.sync()
        self.logger.info("Foxglove server on ws://%s:%d (subprotocol foxglove.sdk.v1)",
                         self.host, self.port)

    # ------------------------------------------------------------------ channels

    def _on_graph(self, event: str, tok: Token) -> None:
        if tok.kind in ("pub", "sub"):
            self.sync()

    def sync(self) -> None:
        """Advertise a channel for every topic with a known type; drop those that vanished."""
        topics = self.node.graph.topics()
        with self._lock:
            for topic, types in topics.items():
                if topic in self.channels or topic == "/rosout" or not types:
                    continue
                try:
                    msg_type = lookup_type(types[0])
                except UnknownTypeError:
                    continue
                self._types[topic] = msg_type
                self.channels[topic] = Channel(
                    topic, message_encoding="json", context=self._ctx,
                    schema=Schema(name=schema_name(types[0]), encoding="jsonschema",
                                  data=schema_bytes(msg_type)))
            for topic in [t for t in self.channels if t not in topics]:
                self.channels.pop(topic).close()
                self._types.pop(topic, None)

    # ------------------------------------------------------------------ ServerListener

    def on_subscribe(self, client: Client, channel: ChannelView) -> None:
        with self._lock:
            entry = self._subs.get(channel.id)
            if entry is None:
                chan = self.channels.get(channel.topic)
                msg_type = self._types.get(channel.topic)
                if chan is None or msg_type is None:
                    return
                tags = [t.qos for t in self.node.graph.publishers(channel.topic)]
                qos = qos_for_publishers(tags)
                sub = self.node.create_subscription(msg_type, channel.topic,
                                                    self._logger_for(chan), qos)
                entry = self._subs[channel.id] = (sub, set())
            entry[1].add(client.id)

    def on_unsubscribe(self, client: Client, channel: ChannelView) -> None:
        with self._lock:
            entry = self._subs.get(channel.id)
            if entry is None:
                return
            entry[1].discard(client.id)
            if not entry[1]:
                del self._subs[channel.id]
                self.node.destroy(entry[0])

    def _logger_for(self, chan: Channel) -> Any:
        in_worker = [0]  # this channel's messages on the bulk encoder: later ones follow them
        lock = threading.Lock()

        def log_now(data: bytes, stamp: int) -> None:
            chan.log(data, log_time=stamp)

        def off_thread(msg: Message, stamp: int, bulky: bool) -> None:
            try:
                data = encode_yielding(msg) if bulky else encode_message(msg)
            finally:
                with lock:
                    in_worker[0] -= 1
            log_now(data, stamp)

        def log(msg: Message) -> None:  # on Zenoh's thread
            stamp, bulky = time.time_ns(), is_bulky(msg)
            with lock:
                offload = bulky or in_worker[0] > 0
                if offload:
                    in_worker[0] += 1
            if offload:
                self._bulk.submit(lambda: off_thread(msg, stamp, bulky))
            else:
                log_now(encode_message(msg), stamp)

        return log

    def on_client_advertise(self, client: Client, channel: ClientChannel) -> None:
        try:
            msg_type = lookup_type(channel.schema_name)
            pub = self.node.create_publisher(msg_type, channel.topic)
        except (UnknownTypeError, ZenrosError, ValueError) as exc:
            self.logger.error("client %d cannot publish %s: %s", client.id, channel.topic, exc)
            return
        with self._lock:
            self._client_pubs[(client.id, channel.id)] = pub

    def on_client_unadvertise(self, client: Client, client_channel_id: int) -> None:
        with self._lock:
            pub = self._client_pubs.pop((client.id, client_channel_id), None)
        if pub is not None:
            self.node.destroy(pub)

    def on_message_data(self, client: Client, client_channel_id: int, data: bytes) -> None:
        pub = self._client_pubs.get((client.id, client_channel_id))
        if pub is None:
            return
        try:
            pub.publish(message_from_json(json.loads(data), pub.msg_type, self.node.now()))
        except (ValueError, TypeError, ZenrosError) as exc:
            self.logger.error("client %d sent a bad %s on %s: %s", client.id, pub.type_name,
                              pub.topic, exc)

    # ------------------------------------------------------------------ end

    def stop(self) -> None:
        self._bulk.close()
        if self._unlisten is not None:
            self._unlisten()
            self._unlisten = None
        if self._server is not None:
            self._server.stop()
            self._server = None
        with self._lock:
            for sub, _ in self._subs.values():
                self.node.destroy(sub)
            self._subs.clear()
            for pub in self._client_pubs.values():
                self.node.destroy(pub)
            self._client_pubs.clear()
            for chan in self.channels.values():
                chan.close()
            self.channels.clear()
