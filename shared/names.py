"""ROS names: validation, resolution, remapping, and the only place key expressions are built."""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field

from .errors import InvalidNameError

__all__ = [
    "DEFAULT_PREFIX",
    "MAX_NAME_LENGTH",
    "KeySpace",
    "Remapper",
    "Token",
    "basename",
    "chunk",
    "join",
    "namespace_of",
    "parse_token",
    "resolve",
    "unchunk",
    "validate_name",
    "validate_namespace",
    "validate_node_name",
]

DEFAULT_PREFIX = "zenros"
ENTITY_KINDS = ("node", "pub", "sub", "srv", "cli", "act", "actc")
"""Liveliness token kinds: nodes, publishers, subscribers, service servers and clients,
action servers and clients."""

MAX_NAME_LENGTH = 1000
"""The longest topic, service, action or parameter name (resolved), in characters.

ROS sets none, but a name becomes a Zenoh key expression, and Zenoh 1.10 cannot fragment a
key expression: one longer than a transport batch (64 KiB) makes the sender's transport
panic for good (see docs/wire.md). 1,000 leaves room for the prefix and the token fields."""

_NAME_CHARS = re.compile(r"[A-Za-z0-9_/~]")
_NODE_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


def _fail(kind: str, name: str, pos: int, why: str) -> InvalidNameError:
    pointer = " " * pos + "^"
    return InvalidNameError(f"invalid {kind} name {name!r}: {why}\n  {name}\n  {pointer}")


def _check_length(name: str, kind: str) -> None:
    if len(name) > MAX_NAME_LENGTH:
        raise InvalidNameError(f"invalid {kind} name {name[:40]!r}...: {len(name)} characters "
                               f"long; the limit is {MAX_NAME_LENGTH}")


def validate_name(name: str, kind: str = "topic") -> str:
    """Check a (possibly relative, global or private) topic/service name; return it unchanged."""
    if not name:
        raise InvalidNameError(f"invalid {kind} name '': a name may not be empty")
    _check_length(name, kind)
    for i, ch in enumerate(name):
        if not _NAME_CHARS.match(ch):
            raise _fail(kind, name, i, f"character {ch!r} is not allowed (use A-Z a-z 0-9 _ /)")
    if "~" in name[1:]:
        raise _fail(kind, name, name.index("~", 1), "'~' may only start a name")
    if name.endswith("/") and name not in ("/", "~/"):
        raise _fail(kind, name, len(name) - 1, "a name may not end with '/'")
    if "//" in name:
        raise _fail(kind, name, name.index("//") + 1, "empty segment")
    for m in re.finditer(r"[^/~]+", name):
        seg = m.group()
        if seg[0].isdigit():
            raise _fail(kind, name, m.start(), "a segment may not start with a digit")
        if "__" in seg:
            raise _fail(kind, name, m.start() + seg.index("__"), "'__' is reserved")
    return name


def validate_node_name(name: str) -> str:
    """A node's base name: a letter or '_' then letters, digits, '_'."""
    if not name:
        raise InvalidNameError("invalid node name '': a node name may not be empty")
    if not _NODE_NAME.match(name):
        bad = next(
            (i for i, ch in enumerate(name) if not re.match(r"[A-Za-z0-9_]", ch) or (i == 0 and ch.isdigit())),
            0,
        )
        raise _fail("node", name, bad, "use a letter or '_' followed by letters, digits or '_'")
    return name


def validate_namespace(ns: str) -> str:
    """Normalize a namespace to '/' or '/a/b' (a relative one is made absolute)."""
    if ns in ("", "/"):
        return "/"
    if not ns.startswith("/"):
        ns = "/" + ns
    validate_name(ns.rstrip("/") or ns, "namespace")
    if "~" in ns:
        raise _fail("namespace", ns, ns.index("~"), "'~' is not allowed in a namespace")
    return ns.rstrip("/")


def join(ns: str, name: str) -> str:
    """Join a namespace and a relative name."""
    return f"/{name}" if ns == "/" else f"{ns}/{name}"


def namespace_of(fqn: str) -> str:
    ns = fqn.rsplit("/", 1)[0]
    return ns or "/"


def basename(fqn: str) -> str:
    return fqn.rsplit("/", 1)[-1]


def resolve(name: str, namespace: str = "/", node: str | None = None, kind: str = "topic") -> str:
    """Resolve a name to its fully-qualified form, as ROS does.

    ``/x`` is global; ``~/x`` (or ``~x``) is private to ``node`` (its FQN); ``x`` is relative
    to ``namespace``.
    """
    validate_name(name, kind)
    if name.startswith("/"):
        return name if name == "/" else name.rstrip("/")
    if name.startswith("~"):
        if node is None:
            raise InvalidNameError(f"private {kind} name {name!r} needs a node")
        rest = name[1:].lstrip("/")
        full = node if not rest else f"{node}/{rest}"
    else:
        full = join(namespace, name)
    _check_length(full, kind)
    return full


@dataclass
class Remapper:
    """Name remappings (``from:=to``) and the special ``__ns``/``__node`` rules."""

    rules: dict[str, str] = field(default_factory=dict)
    node_name: str | None = None
    namespace: str | None = None

    @classmethod
    def parse(cls, args: list[str]) -> Remapper:
        """Parse ``from:=to`` strings, as given to ``-r``/``--remap``."""
        r = cls()
        for arg in args:
            src, sep, dst = arg.partition(":=")
            if not sep or not src or not dst:
                raise InvalidNameError(f"invalid remapping {arg!r}: expected from:=to")
            if src in ("__ns", "__namespace"):
                r.namespace = validate_namespace(dst)
            elif src in ("__node", "__name"):
                r.node_name = validate_node_name(dst)
            else:
                validate_name(src, "remap source")
                validate_name(dst, "remap target")
                r.rules[src] = dst
        return r

    def apply(self, resolved: str, namespace: str, node: str, kind: str = "topic") -> str:
        """Map an already-resolved name through the rules (rules are resolved in the node's context)."""
        for src, dst in self.rules.items():
            if resolve(src, namespace, node, kind) == resolved:
                return resolve(dst, namespace, node, kind)
        return resolved


def chunk(name: str) -> str:
    """One key-expression chunk for a name: '/' written as '%' (rmw_zenoh's convention)."""
    return name.replace("/", "%") or "%"


def unchunk(part: str) -> str:
    return part.replace("%", "/")


_SAFE = re.compile(r"[^A-Za-z0-9_.\-]")


def safe_chunk(text: str) -> str:
    """A free-text value (host name) made safe for one key-expression chunk."""
    return _SAFE.sub("_", text) or "_"


@dataclass(frozen=True)
class Token:
    """A parsed liveliness token: what kind of entity, which node, which name and type."""

    kind: str
    node: str
    name: str = ""
    type: str = ""
    qos: str = ""
    zid: str = ""
    eid: str = ""
    host: str = ""
    pid: int = 0
    start_ns: int = 0


@dataclass(frozen=True)
class KeySpace:
    """Builds every key expression under one prefix (default ``zenros``)."""

    prefix: str = DEFAULT_PREFIX

    @classmethod
    def from_env(cls, prefix: str | None = None) -> KeySpace:
        p = prefix or os.environ.get("ZENROS_PREFIX") or DEFAULT_PREFIX
        p = p.strip("/")
        if not p or any(c in p for c in "*$?#") or "//" in p:
            raise InvalidNameError(f"invalid key prefix {p!r}")
        return cls(p)

    def topic(self, fqn: str) -> str:
        return f"{self.prefix}/topic{fqn}"

    def service(self, fqn: str) -> str:
        return f"{self.prefix}/service{fqn}"

    def action(self, fqn: str, part: str) -> str:
        return f"{self.prefix}/action{fqn}/{part}"

    def param(self, fqn: str) -> str:
        return f"{self.prefix}/param{fqn}"

    def param_describe(self, node: str) -> str:
        """Where a node answers its parameter declarations (`zenros.param_describe`)."""
        return f"{self.prefix}/paramdesc{node}"

    def all_topics(self) -> str:
        return f"{self.prefix}/topic/**"

    def topic_name(self, key: str) -> str:
        """The topic FQN of a topic key expression."""
        head = f"{self.prefix}/topic"
        return key.removeprefix(head)

    def alive_all(self) -> str:
        return f"{self.prefix}/alive/**"

    def node_token(self, node: str, zid: str, host: str, pid: int, start_ns: int) -> str:
        return (
            f"{self.prefix}/alive/node/{chunk(node)}/{zid}/{safe_chunk(host)}/{pid}/{start_ns}"
        )

    def entity_token(
        self, kind: str, node: str, name: str, type_name: str, qos: str, zid: str, eid: int
    ) -> str:
        return (
            f"{self.prefix}/alive/{kind}/{chunk(node)}/{chunk(name)}/{chunk(type_name)}/"
            f"{qos or '_'}/{zid}/{eid}"
        )

    def parse_token(self, key: str) -> Token | None:
        """Parse a liveliness key back into a `Token` (None if it is not ours)."""
        head = f"{self.prefix}/alive/"
        if not key.startswith(head):
            return None
        parts = key[len(head):].split("/")
        try:
            if parts[0] == "node" and len(parts) == 6:
                return Token(
                    "node", unchunk(parts[1]), zid=parts[2], host=parts[3], pid=int(parts[4]),
                    start_ns=int(parts[5]),
                )
            if parts[0] in ENTITY_KINDS and parts[0] != "node" and len(parts) == 7:
                return Token(
                    parts[0], unchunk(parts[1]), unchunk(parts[2]), unchunk(parts[3]),
                    "" if parts[4] == "_" else parts[4], parts[5], parts[6],
                )
        except ValueError:
            return None
        return None


def parse_token(keys: KeySpace, key: str) -> Token | None:
    return keys.parse_token(key)
