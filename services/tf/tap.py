"""`TfTap`: subscriptions to ``/tf`` and ``/tf_static`` that also say who sent each message.

A `TFMessage` carries no sender, and a typed `Subscription` hands its callback the message
only. The buffer server wants the authority of every link (tf_monitor shows it), so it
subscribes here on the raw Zenoh samples and names the sender from the sample's timestamp:
its id is the publishing session, and the graph knows which nodes of that session publish
the topic. Otherwise it behaves as a subscription: a liveliness token puts it in the graph,
``/tf_static`` is latched (history from every publisher), in-process publishers deliver
directly, and a sample that does not decode is logged (rate-limited) and counted.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

import zenoh
from zenoh import ext as zext
from zenros.codec import codec_for
from zenros.errors import CodecError
from zenros.graph import Graph
from zenros.log import Throttle
from zenros.msgs.tf2_msgs import TFMessage
from zenros.names import Token
from zenros.node import Node
from zenros.qos import QoSProfile
from zenros.tf.listener import DYNAMIC_LISTENER_QOS, STATIC_LISTENER_QOS

__all__ = ["OnMessage", "TfTap"]

OnMessage = Callable[[TFMessage, bool, str], None]
"""``on_message(msg, is_static, authority)``."""

_SESSION = "session "


class _Authorities:
    """Session id → the names of its nodes that publish a topic, cached until the graph
    changes."""

    def __init__(self, graph: Graph) -> None:
        self._graph = graph
        self._cache: dict[tuple[str, str], str] = {}
        graph.add_listener(self._on_graph)

    def _on_graph(self, event: str, token: Token) -> None:
        if token.kind in ("node", "pub"):
            self._cache.clear()

    def of(self, zid: str, topic: str) -> str:
        name = self._cache.get((zid, topic))
        if name is None:
            nodes = self._graph.nodes_of_zid(zid, topic)
            if not nodes:  # the graph has not caught up yet: do not cache this
                return f"{_SESSION}{zid}"
            name = self._cache[(zid, topic)] = ", ".join(nodes)
        return name

    def resolve(self, authority: str) -> str:
        """``authority`` with a ``session <zid>`` placeholder replaced by node names, if
        the graph knows them by now."""
        if not authority.startswith(_SESSION):
            return authority
        nodes = self._graph.nodes_of_zid(authority[len(_SESSION):])
        return ", ".join(nodes) if nodes else authority


class _Endpoint:
    """One topic of the tap."""

    def __init__(self, node: Node, topic: str, static: bool, qos: QoSProfile,
                 on_message: OnMessage, authorities: _Authorities) -> None:
        ctx = node.context
        self._ctx = ctx
        self.topic = node.resolve_name(topic)
        self.static = static
        self._on_message = on_message
        self._authorities = authorities
        self._logger = node.logger
        self._throttle = Throttle(5.0)
        self._lock = threading.Lock()
        self.errors = 0
        self._codec = codec_for(TFMessage)
        self._encoding = zenoh.Encoding(self._codec.mime).with_schema(self._codec.type_name)
        key = ctx.keys.topic(self.topic)
        self._sub: Any
        if static:
            self._sub = zext.declare_advanced_subscriber(
                ctx.session, key, self._on_sample, allowed_origin=zenoh.Locality.REMOTE,
                history=zext.HistoryConfig(detect_late_publishers=True, max_samples=qos.depth),
                recovery=zext.RecoveryConfig(heartbeat=True, periodic_queries=None),
                subscriber_detection=True,
            )
        else:
            self._sub = ctx.session.declare_subscriber(
                key, self._on_sample, allowed_origin=zenoh.Locality.REMOTE
            )
        self._token = ctx.session.liveliness().declare_token(ctx.keys.entity_token(
            "sub", node.fqn, self.topic, self._codec.type_name, qos.tag, ctx.zid,
            ctx.next_eid(),
        ))  # fmt: skip
        ctx.add_local(self.topic, "subs", self)  # in-process publishers call _deliver_local

    def _deliver_local(self, msg: Any, pub: Any) -> None:
        if type(msg) is TFMessage:
            self._handle(msg, self._authorities.of(self._ctx.zid, self.topic))

    def _on_sample(self, sample: zenoh.Sample) -> None:
        sender = "unknown"
        try:
            ts = sample.timestamp
            sender = self._authorities.of(str(ts.get_id()), self.topic) if ts else "unknown"
            if sample.encoding != self._encoding:
                self._codec.check_encoding(str(sample.encoding))
            msg = self._codec.decode(sample.payload.to_bytes())
        except Exception as exc:  # noqa: BLE001 nothing raises into Zenoh's thread
            self._reject(str(exc) if isinstance(exc, CodecError)
                         else f"{type(exc).__name__}: {exc}", sender)
            return
        self._handle(msg, sender)

    def _handle(self, msg: TFMessage, authority: str) -> None:
        try:
            self._on_message(msg, self.static, authority)
        except Exception:  # a callback must never raise into Zenoh's thread
            self._logger.exception("handling %s from %s failed", self.topic, authority)

    def _reject(self, why: str, sender: str) -> None:
        with self._lock:
            self.errors += 1
            if not self._throttle.allow(sender):
                return
            extra = self._throttle.suppressed.pop(sender, 0)
        more = f" ({extra} more suppressed)" if extra else ""
        self._logger.error("cannot decode %s from %s: %s%s", self.topic, sender, why, more)

    def close(self) -> None:
        self._ctx.remove_local(self.topic, "subs", self)
        self._token.undeclare()  # type: ignore[no-untyped-call]
        self._sub.undeclare()


class TfTap:
    """Calls ``on_message(msg, is_static, authority)`` for every message on ``/tf`` and
    ``/tf_static`` (names resolved and remapped by ``node``), on Zenoh's threads.

    ``authority`` is the publishing node's name (several, comma separated, when one
    process publishes the topic from several nodes), or ``session <zid>`` when the graph
    does not know the publisher yet (see `resolve`).
    """

    def __init__(self, node: Node, on_message: OnMessage) -> None:
        authorities = self._authorities = _Authorities(node.graph)
        self._endpoints = [
            _Endpoint(node, "/tf", False, DYNAMIC_LISTENER_QOS, on_message, authorities),
            _Endpoint(node, "/tf_static", True, STATIC_LISTENER_QOS, on_message, authorities),
        ]

    def resolve(self, authority: str) -> str:
        """A ``session <zid>`` authority (recorded before the graph knew the publisher)
        as the names of that session's nodes, when they are known now."""
        return self._authorities.resolve(authority)

    @property
    def errors(self) -> int:
        """Samples that could not be decoded."""
        return sum(e.errors for e in self._endpoints)

    def close(self) -> None:
        for e in self._endpoints:
            e.close()
        self._endpoints = []

