"""The registry on Zenoh: feeds graph events to `Registry`, serves its queries, evicts duplicates."""

from __future__ import annotations

import threading
import time

from zenros.msgs.builtin_interfaces import Time
from zenros.names import Token
from zenros.node import Node
from zenros.shutdown import SHUTDOWN_TOPIC, Shutdown, send_shutdown

from .messages import (
    GET_PUBLISHED_TOPICS,
    GET_SYSTEM_STATE,
    GET_TOPIC_TYPES,
    LOOKUP_NODE,
    EndpointState,
    GetPublishedTopics,
    GetPublishedTopicsRequest,
    GetPublishedTopicsResponse,
    GetSystemState,
    GetSystemStateRequest,
    GetSystemStateResponse,
    GetTopicTypes,
    GetTopicTypesRequest,
    GetTopicTypesResponse,
    LookupNode,
    LookupNodeRequest,
    LookupNodeResponse,
    NodeState,
    TopicState,
    TopicType,
)
from .registry import Endpoints, Eviction, Notice, Registry, TypeConflict

__all__ = ["RegistryServer"]

MAX_REQUESTS = 5
"""How many times an evicted node is told to shut down (once per tick) before giving up."""


def node_state(tok: Token) -> NodeState:
    return NodeState(name=tok.node, host=tok.host, pid=tok.pid, zid=tok.zid,
                     start=Time.from_nanoseconds(tok.start_ns))


def _endpoints(views: list[Endpoints]) -> list[EndpointState]:
    return [EndpointState(name=v.name, types=v.types, servers=v.servers) for v in views]


def _describe(tok: Token) -> str:
    started = time.strftime("%H:%M:%S", time.localtime(tok.start_ns / 1e9))
    return f"pid {tok.pid} on {tok.host}, session {tok.zid[:8]}, started {started}"


class RegistryServer:
    """The ROS master's graph API, built from liveliness (right for nodes started earlier).

    Args:
        node: the master node.
        grace: seconds a deleted token stays (a liveliness flap must not change the state).
    """

    def __init__(self, node: Node, grace: float = 2.0) -> None:
        self._node = node
        self._registry = Registry(grace)
        self._lock = threading.Lock()
        self._sent: dict[Token, int] = {}
        self._shutdown_key = node.context.keys.topic(SHUTDOWN_TOPIC)
        self.closed = False
        graph = node.graph
        graph.add_listener(self._on_graph)
        for tok in graph.tokens():
            self._on_graph("put", tok)
        node.create_service(GetSystemState, GET_SYSTEM_STATE, self.handle_get_system_state)
        node.create_service(LookupNode, LOOKUP_NODE, self.handle_lookup_node)
        node.create_service(GetTopicTypes, GET_TOPIC_TYPES, self.handle_get_topic_types)
        node.create_service(GetPublishedTopics, GET_PUBLISHED_TOPICS,
                            self.handle_get_published_topics)
        node.create_timer(max(0.1, min(1.0, grace / 2)), self.on_tick)

    @property
    def registry(self) -> Registry:
        return self._registry

    def _on_graph(self, event: str, tok: Token) -> None:
        if self.closed:
            return
        with self._lock:
            if event == "put":
                notices = self._registry.put(tok, time.monotonic())
            else:
                self._registry.delete(tok, time.monotonic())
                notices = []
        for notice in notices:
            self._act(notice)

    def _act(self, notice: Notice) -> None:
        log = self._node.logger
        if isinstance(notice, TypeConflict):
            log.warning("type conflict on %s: endpoints declare %s", notice.topic,
                        ", ".join(notice.types))
        elif isinstance(notice, Eviction):
            old, new = notice.older, notice.newer
            log.warning("duplicate node name %s: the newer instance (%s) replaces the older"
                        " (%s), which is told to shut down", old.node, _describe(new),
                        _describe(old))
            self._evict(notice)

    def _evict(self, e: Eviction) -> None:
        old = e.older
        self._sent[old] = self._sent.get(old, 0) + 1
        send_shutdown(self._node.context.session, self._shutdown_key, Shutdown(
            node=old.node, zid=old.zid, start_ns=old.start_ns, by=self._node.fqn,
            reason=f"a newer node took the name {old.node} ({_describe(e.newer)})",
        ))

    def on_tick(self) -> None:
        """Apply expired deletions; repeat shutdown requests to evicted nodes still alive."""
        with self._lock:
            self._registry.expire(time.monotonic())
            pending = [e for e in self._registry.evictions()
                       if self._sent.get(e.older, 0) < MAX_REQUESTS]
            live = set(self._registry.tokens("node"))
            self._sent = {t: n for t, n in self._sent.items() if t in live}
        for e in pending:
            self._evict(e)

    # ------------------------------------------------------------------ services

    def handle_get_system_state(self, req: GetSystemStateRequest) -> GetSystemStateResponse:
        with self._lock:
            reg = self._registry
            reg.expire(time.monotonic())
            nodes = reg.nodes()
            names = [t.node for t in nodes]
            return GetSystemStateResponse(
                nodes=[node_state(t) for t in nodes],
                topics=[TopicState(name=t.name, types=t.types, publishers=t.publishers,
                                   subscribers=t.subscribers) for t in reg.topics()],
                services=_endpoints(reg.services()),
                actions=_endpoints(reg.actions()),
                type_conflicts=[TopicType(name=k, types=v)
                                for k, v in reg.type_conflicts().items()],
                duplicate_nodes=sorted({n for n in names if names.count(n) > 1}),
            )

    def handle_lookup_node(self, req: LookupNodeRequest) -> LookupNodeResponse:
        with self._lock:
            self._registry.expire(time.monotonic())
            tok = self._registry.lookup_node(req.name)
        if tok is None:
            return LookupNodeResponse(found=False, node=NodeState(name=req.name))
        return LookupNodeResponse(found=True, node=node_state(tok))

    def handle_get_topic_types(self, req: GetTopicTypesRequest) -> GetTopicTypesResponse:
        with self._lock:
            self._registry.expire(time.monotonic())
            types = self._registry.topic_types()
        return GetTopicTypesResponse(topics=[TopicType(name=k, types=v) for k, v in types.items()])

    def handle_get_published_topics(
        self, req: GetPublishedTopicsRequest
    ) -> GetPublishedTopicsResponse:
        with self._lock:
            self._registry.expire(time.monotonic())
            types = self._registry.published_topics(req.subgraph or "/")
        return GetPublishedTopicsResponse(
            topics=[TopicType(name=k, types=v) for k, v in types.items()]
        )

    def close(self) -> None:
        self.closed = True
