"""The registry: the system state (ROS master's getSystemState) folded from liveliness tokens.

Pure: the master feeds it the graph's token events with the time they arrived. A DELETE is
applied only after ``grace`` seconds, and a PUT of the same token within that time cancels
it, so a liveliness flap (a router restart deletes and re-puts every token, see
specs/zenoh-ops.md) leaves the registry unchanged. Node instances are told apart by session
and start time, which travel in their tokens, so "newer" never depends on arrival order.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from zenros.names import Token

__all__ = ["Endpoints", "Eviction", "Notice", "Registry", "TopicView", "TypeConflict"]


@dataclass(frozen=True)
class Eviction:
    """Two live nodes share a name: ``older`` must shut down, ``newer`` keeps it."""

    older: Token
    newer: Token


@dataclass(frozen=True)
class TypeConflict:
    """Endpoints on one topic declare different types."""

    topic: str
    types: tuple[str, ...]


Notice = Eviction | TypeConflict


@dataclass
class TopicView:
    """One topic: its types, and the nodes publishing and subscribing to it."""

    name: str
    types: list[str] = field(default_factory=list)
    publishers: list[str] = field(default_factory=list)
    subscribers: list[str] = field(default_factory=list)


@dataclass
class Endpoints:
    """One service or action: its types and the nodes serving it."""

    name: str
    types: list[str] = field(default_factory=list)
    servers: list[str] = field(default_factory=list)


def _age(tok: Token) -> tuple[int, str]:
    return tok.start_ns, tok.zid


class Registry:
    """Live tokens with debounced deletions; answers the ROS master's graph queries.

    Not thread-safe: the master serializes calls. ``now`` is any monotonic time in seconds.
    """

    def __init__(self, grace: float = 2.0) -> None:
        self.grace = grace
        self._tokens: dict[Token, None] = {}
        self._gone: dict[Token, float] = {}
        self._evicted: dict[Token, Eviction] = {}
        self._conflicts: dict[str, tuple[str, ...]] = {}

    # ------------------------------------------------------------------ events

    def put(self, tok: Token, now: float) -> list[Notice]:
        """A token appeared (or came back). Returns what the master must act on."""
        self.expire(now)
        self._gone.pop(tok, None)
        if tok in self._tokens:
            return []
        self._tokens[tok] = None
        if tok.kind == "node":
            return list(self._duplicates(tok.node))
        if tok.kind in ("pub", "sub"):
            return list(self._conflict(tok.name))
        return []

    def delete(self, tok: Token, now: float) -> None:
        """A token disappeared; it leaves after ``grace`` seconds unless it comes back."""
        self.expire(now)
        if tok in self._tokens:
            self._gone.setdefault(tok, now)

    def expire(self, now: float) -> list[Token]:
        """Drop the tokens deleted at least ``grace`` seconds ago; returns them."""
        out = [t for t, at in self._gone.items() if now - at >= self.grace]
        for tok in out:
            del self._gone[tok]
            del self._tokens[tok]
            self._evicted.pop(tok, None)
            if tok.kind in ("pub", "sub"):
                self._conflict(tok.name)
        return out

    def _live(self, kind: str) -> list[Token]:
        return [t for t in self._tokens if t.kind == kind and t not in self._gone]

    def _duplicates(self, name: str) -> list[Eviction]:
        same = sorted((t for t in self._live("node") if t.node == name), key=_age)
        if len(same) < 2:
            return []
        newest = same[-1]
        out = []
        for older in same[:-1]:
            if older not in self._evicted:
                self._evicted[older] = Eviction(older, newest)
                out.append(self._evicted[older])
        return out

    def _conflict(self, topic: str) -> list[TypeConflict]:
        types = tuple(sorted({t.type for k in ("pub", "sub") for t in self._live(k)
                              if t.name == topic}))
        if len(types) < 2:
            self._conflicts.pop(topic, None)
            return []
        if self._conflicts.get(topic) == types:
            return []
        self._conflicts[topic] = types
        return [TypeConflict(topic, types)]

    # ------------------------------------------------------------------ queries

    def tokens(self, kind: str | None = None) -> list[Token]:
        """Every token (those within their grace period included)."""
        return [t for t in self._tokens if kind is None or t.kind == kind]

    def nodes(self) -> list[Token]:
        """Node instances, by name then age."""
        return sorted(self.tokens("node"), key=lambda t: (t.node, *_age(t)))

    def lookup_node(self, name: str) -> Token | None:
        """The newest instance of a node name (ROS ``lookupNode``), or None."""
        same = [t for t in self.tokens("node") if t.node == name]
        return max(same, key=_age) if same else None

    def topics(self) -> list[TopicView]:
        """Topics with their types, publishers and subscribers (ROS ``getSystemState``)."""
        views: dict[str, TopicView] = {}
        for tok in self.tokens():
            if tok.kind not in ("pub", "sub"):
                continue
            view = views.setdefault(tok.name, TopicView(tok.name))
            if tok.type and tok.type not in view.types:
                view.types.append(tok.type)
            nodes = view.publishers if tok.kind == "pub" else view.subscribers
            if tok.node not in nodes:
                nodes.append(tok.node)
        return [_sorted_topic(views[k]) for k in sorted(views)]

    def services(self) -> list[Endpoints]:
        return self._endpoints("srv")

    def actions(self) -> list[Endpoints]:
        return self._endpoints("act")

    def _endpoints(self, kind: str) -> list[Endpoints]:
        views: dict[str, Endpoints] = {}
        for tok in self.tokens(kind):
            view = views.setdefault(tok.name, Endpoints(tok.name))
            if tok.type and tok.type not in view.types:
                view.types.append(tok.type)
            if tok.node not in view.servers:
                view.servers.append(tok.node)
        return [Endpoints(v.name, sorted(v.types), sorted(v.servers))
                for _, v in sorted(views.items())]

    def topic_types(self) -> dict[str, list[str]]:
        """Topic name to its types (ROS ``getTopicTypes``; several types mean a conflict)."""
        return {t.name: t.types for t in self.topics()}

    def published_topics(self, subgraph: str = "/") -> dict[str, list[str]]:
        """Topics with a publisher, within a namespace (ROS ``getPublishedTopics``)."""
        ns = subgraph.rstrip("/") or "/"
        return {t.name: t.types for t in self.topics() if t.publishers
                and (ns == "/" or t.name == ns or t.name.startswith(ns + "/"))}

    def type_conflicts(self) -> dict[str, list[str]]:
        return {t.name: t.types for t in self.topics() if len(t.types) > 1}

    def evictions(self) -> list[Eviction]:
        """Evicted nodes whose token is still live (the master repeats its request)."""
        return [e for t, e in self._evicted.items() if t in self._tokens and t not in self._gone]


def _sorted_topic(v: TopicView) -> TopicView:
    return TopicView(v.name, sorted(v.types), sorted(v.publishers), sorted(v.subscribers))
