"""`TfTap`: subscriptions to ``/tf`` and ``/tf_static`` that also say who sent each message.

A `TFMessage` carries no sender; the buffer server wants the authority of every link
(tf_monitor shows it). Its subscriptions take a `MessageInfo` with each message, whose
``publisher_gid`` is the publishing session: the graph knows which nodes of that session
publish the topic. Everything else (graph token, latched history on ``/tf_static``,
in-process delivery, logging and counting undecodable samples) is the plain `Subscription`.
"""

from __future__ import annotations

from collections.abc import Callable

from zenros.graph import Graph
from zenros.msgs.tf2_msgs import TFMessage
from zenros.names import Token
from zenros.node import Node
from zenros.pubsub import MessageInfo, Subscription
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


class TfTap:
    """Calls ``on_message(msg, is_static, authority)`` for every message on ``/tf`` and
    ``/tf_static`` (names resolved and remapped by ``node``), on Zenoh's threads.

    ``authority`` is the publishing node's name (several, comma separated, when one
    process publishes the topic from several nodes), or ``session <zid>`` when the graph
    does not know the publisher yet (see `resolve`).
    """

    def __init__(self, node: Node, on_message: OnMessage) -> None:
        authorities = self._authorities = _Authorities(node.graph)

        def tap(static: bool) -> Callable[[TFMessage, MessageInfo], None]:
            topic = node.resolve_name("/tf_static" if static else "/tf")

            def on_sample(msg: TFMessage, info: MessageInfo) -> None:
                who = info.publisher_gid
                on_message(msg, static, authorities.of(who, topic) if who else "unknown")

            return on_sample

        self._subs: list[Subscription[TFMessage]] = [
            node.create_subscription(TFMessage, "/tf", tap(False), DYNAMIC_LISTENER_QOS),
            node.create_subscription(TFMessage, "/tf_static", tap(True), STATIC_LISTENER_QOS),
        ]

    def resolve(self, authority: str) -> str:
        """A ``session <zid>`` authority (recorded before the graph knew the publisher)
        as the names of that session's nodes, when they are known now."""
        return self._authorities.resolve(authority)

    @property
    def errors(self) -> int:
        """Samples that could not be decoded."""
        return sum(s.errors for s in self._subs)

    @property
    def callback_errors(self) -> int:
        """Messages whose handling raised (logged, rate-limited)."""
        return sum(s.callback_errors for s in self._subs)

    def close(self) -> None:
        """Nothing to do: the subscriptions are the node's and close with it."""
