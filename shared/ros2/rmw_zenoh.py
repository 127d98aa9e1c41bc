"""rmw_zenoh's layout on Zenoh (rmw_zenoh_cpp 0.6 Kilted, 0.2 Jazzy): data keys, liveliness
tokens, the QoS string, and the attachment every sample, query and reply carries.

Pure functions and values: no session here (the bridge uses them).

- data key: ``<domain>/<name without leading slash>/<pkg>::msg::dds_::<Name>_/RIHS01_<hex>``;
  services use the service type (``pkg::srv::dds_::Name_``) and its hash
- token: ``@ros2_lv/<domain>/<zid>/<nid>/<eid>/<NN|MP|MS|SS|SC>/<enclave>/<namespace>/<node>``
  ``[/<topic>/<type>/<hash>/<qos>]``, every ``/`` inside a part written ``%``
- attachment: int64 sequence number, int64 source timestamp (ns), the 16-byte GID, as Zenoh's
  serializer writes them (little endian, the GID with a one-byte length 16): 33 bytes
"""

from __future__ import annotations

import hashlib
import struct
from dataclasses import dataclass, field
from enum import Enum

from ..errors import ZenrosError
from .registry import definition
from .typehash import type_hash
from .typenames import ros_to_dds, split_ros_name

__all__ = [
    "ADMIN_SPACE",
    "DEFAULT_QOS",
    "Attachment",
    "Entity",
    "EntityKind",
    "Qos",
    "RmwZenohError",
    "action_endpoints",
    "data_key",
    "demangle",
    "gid_of",
    "keyexpr_to_qos",
    "mangle",
    "qos_to_keyexpr",
    "type_part",
]

ADMIN_SPACE = "@ros2_lv"
_ATTACHMENT = struct.Struct("<qqB16s")


class RmwZenohError(ZenrosError, ValueError):
    """A malformed rmw_zenoh token, QoS string or attachment."""


def mangle(name: str) -> str:
    """``/robot1/chatter`` -> ``%robot1%chatter``; an empty name is ``%``."""
    return name.replace("/", "%") if name else "%"


def demangle(part: str) -> str:
    return part.replace("%", "/")


def type_part(ros_type: str) -> tuple[str, str]:
    """(DDS type name, RIHS01 hash) of a message or service type (``pkg/srv/Name``: the
    service type, as rmw_zenoh keys services)."""
    split_ros_name(ros_type)
    definition(ros_type)  # an unknown type fails here, with its name
    return ros_to_dds(ros_type), type_hash(ros_type)


def data_key(domain_id: int, name: str, ros_type: str) -> str:
    """The key of a topic or service: ``0/chatter/std_msgs::msg::dds_::String_/RIHS01_...``."""
    dds, h = type_part(ros_type)
    return f"{domain_id}/{name.strip('/')}/{dds}/{h}"


# ------------------------------------------------------------------ QoS


class Reliability(int, Enum):
    SYSTEM_DEFAULT = 0
    RELIABLE = 1
    BEST_EFFORT = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


class Durability(int, Enum):
    SYSTEM_DEFAULT = 0
    TRANSIENT_LOCAL = 1
    VOLATILE = 2
    UNKNOWN = 3
    BEST_AVAILABLE = 4


class History(int, Enum):
    SYSTEM_DEFAULT = 0
    KEEP_LAST = 1
    KEEP_ALL = 2
    UNKNOWN = 3


class Liveliness(int, Enum):
    SYSTEM_DEFAULT = 0
    AUTOMATIC = 1
    MANUAL_BY_TOPIC = 3
    UNKNOWN = 4
    BEST_AVAILABLE = 5


INFINITE = (9223372036, 854775807)  # RMW_DURATION_INFINITE


@dataclass(frozen=True)
class Qos:
    """An rmw QoS profile as rmw_zenoh keys it (durations as (sec, nsec))."""

    reliability: Reliability = Reliability.RELIABLE
    durability: Durability = Durability.VOLATILE
    history: History = History.KEEP_LAST
    depth: int = 42
    deadline: tuple[int, int] = INFINITE
    lifespan: tuple[int, int] = INFINITE
    liveliness: Liveliness = Liveliness.AUTOMATIC
    lease: tuple[int, int] = INFINITE

    def normalized(self) -> Qos:
        """System defaults (0, and zero durations) replaced by rmw_zenoh's defaults."""
        d = DEFAULT_QOS
        return Qos(
            reliability=self.reliability or d.reliability,
            durability=self.durability or d.durability,
            history=self.history or d.history,
            depth=self.depth or d.depth,
            deadline=self.deadline if self.deadline != (0, 0) else d.deadline,
            lifespan=self.lifespan if self.lifespan != (0, 0) else d.lifespan,
            liveliness=self.liveliness or d.liveliness,
            lease=self.lease if self.lease != (0, 0) else d.lease,
        )


DEFAULT_QOS = Qos()


def qos_to_keyexpr(qos: Qos) -> str:
    """rmw_zenoh's compact QoS string: each value left empty where it is the default."""
    q, d = qos.normalized(), DEFAULT_QOS

    def v(a: object, b: object, text: str) -> str:
        return "" if a == b else text

    return (
        v(q.reliability, d.reliability, str(int(q.reliability))) + ":"
        + v(q.durability, d.durability, str(int(q.durability))) + ":"
        + v(q.history, d.history, str(int(q.history))) + ","
        + v(q.depth, d.depth, str(q.depth)) + ":"
        + v(q.deadline[0], d.deadline[0], str(q.deadline[0])) + ","
        + v(q.deadline[1], d.deadline[1], str(q.deadline[1])) + ":"
        + v(q.lifespan[0], d.lifespan[0], str(q.lifespan[0])) + ","
        + v(q.lifespan[1], d.lifespan[1], str(q.lifespan[1])) + ":"
        + v(q.liveliness, d.liveliness, str(int(q.liveliness))) + ","
        + v(q.lease[0], d.lease[0], str(q.lease[0])) + ","
        + v(q.lease[1], d.lease[1], str(q.lease[1]))
    )


def _num(text: str, default: int, what: str) -> int:
    if not text:
        return default
    if not text.isdigit():
        raise RmwZenohError(f"QoS {what}: not a non-negative number: {text!r}")
    return int(text)


def keyexpr_to_qos(text: str) -> Qos:
    """Parse rmw_zenoh's QoS string; raises `RmwZenohError` on a malformed one."""
    parts = text.split(":")
    if len(parts) < 6:
        raise RmwZenohError(f"QoS string needs 6 ':'-separated parts: {text!r}")
    hist, dl, ls, lv = (p.split(",") for p in parts[2:6])
    if len(hist) < 2 or len(dl) < 2 or len(ls) < 2 or len(lv) < 3:
        raise RmwZenohError(f"QoS string has too few ',' components: {text!r}")
    d = DEFAULT_QOS
    try:
        return Qos(
            reliability=Reliability(_num(parts[0], d.reliability, "reliability")),
            durability=Durability(_num(parts[1], d.durability, "durability")),
            history=History(_num(hist[0], d.history, "history")),
            depth=_num(hist[1], d.depth, "depth"),
            deadline=(_num(dl[0], d.deadline[0], "deadline"), _num(dl[1], d.deadline[1], "deadline")),
            lifespan=(_num(ls[0], d.lifespan[0], "lifespan"), _num(ls[1], d.lifespan[1], "lifespan")),
            liveliness=Liveliness(_num(lv[0], d.liveliness, "liveliness")),
            lease=(_num(lv[1], d.lease[0], "lease"), _num(lv[2], d.lease[1], "lease")),
        )
    except ValueError as exc:
        raise RmwZenohError(f"QoS string {text!r}: {exc}") from None


# ------------------------------------------------------------------ liveliness tokens


class EntityKind(str, Enum):
    NODE = "NN"
    PUBLISHER = "MP"
    SUBSCRIPTION = "MS"
    SERVICE = "SS"
    CLIENT = "SC"


@dataclass(frozen=True)
class Entity:
    """One graph entity as its liveliness token spells it. ``namespace`` and ``enclave`` are
    ``/`` when not set; ``topic`` is the fully qualified name (``/chatter``)."""

    domain_id: int
    zid: str
    node_id: int
    entity_id: int
    kind: EntityKind
    namespace: str
    node: str
    enclave: str = "/"
    topic: str = ""
    dds_type: str = ""
    type_hash: str = ""
    qos: Qos = field(default_factory=Qos)

    def token(self) -> str:
        parts = [ADMIN_SPACE, str(self.domain_id), self.zid, str(self.node_id),
                 str(self.entity_id), self.kind.value, mangle(self.enclave),
                 mangle(self.namespace), mangle(self.node)]
        if self.kind is not EntityKind.NODE:
            if not (self.topic and self.dds_type and self.type_hash):
                raise RmwZenohError(f"a {self.kind.name} token needs a topic, type and hash")
            parts += [mangle(self.topic), mangle(self.dds_type), mangle(self.type_hash),
                      qos_to_keyexpr(self.qos)]
        return "/".join(parts)

    @property
    def gid(self) -> bytes:
        return gid_of(self.token())

    @classmethod
    def parse(cls, keyexpr: str) -> Entity:
        """Read a liveliness token; raises `RmwZenohError` on a malformed one."""
        parts = keyexpr.split("/")
        if len(parts) < 9 or parts[0] != ADMIN_SPACE or any(not p for p in parts):
            raise RmwZenohError(f"not an rmw_zenoh liveliness token: {keyexpr!r}")
        try:
            kind = EntityKind(parts[5])
        except ValueError:
            raise RmwZenohError(f"unknown entity kind {parts[5]!r} in {keyexpr!r}") from None
        if not parts[1].isdigit():
            raise RmwZenohError(f"bad domain id in {keyexpr!r}")
        topic = dds = h = ""
        qos = DEFAULT_QOS
        if kind is not EntityKind.NODE:
            if len(parts) < 13:
                raise RmwZenohError(f"{kind.name} token without topic, type, hash, QoS: "
                                    f"{keyexpr!r}")
            topic, dds, h = demangle(parts[9]), demangle(parts[10]), demangle(parts[11])
            qos = keyexpr_to_qos(parts[12])
        return cls(domain_id=int(parts[1]), zid=parts[2], node_id=_num(parts[3], 0, "node id"),
                   entity_id=_num(parts[4], 0, "entity id"), kind=kind,
                   enclave=demangle(parts[6]), namespace=demangle(parts[7]),
                   node=demangle(parts[8]), topic=topic, dds_type=dds, type_hash=h, qos=qos)


def gid_of(token: str) -> bytes:
    """A 16-byte GID for an entity, from its token (rmw_zenoh_cpp uses XXH3-128 of the same
    string; peers only compare GIDs, they never recompute them)."""
    return hashlib.blake2b(token.encode(), digest_size=16).digest()


# ------------------------------------------------------------------ attachment


@dataclass(frozen=True)
class Attachment:
    sequence_number: int
    source_timestamp: int  # ns since the Unix epoch
    gid: bytes  # 16 bytes

    def encode(self) -> bytes:
        if len(self.gid) != 16:
            raise RmwZenohError(f"a GID is 16 bytes, got {len(self.gid)}")
        return _ATTACHMENT.pack(self.sequence_number, self.source_timestamp, 16, self.gid)

    @classmethod
    def decode(cls, data: bytes | bytearray | memoryview) -> Attachment:
        if len(data) != _ATTACHMENT.size:
            raise RmwZenohError(f"an rmw_zenoh attachment is 33 bytes, got {len(data)}")
        seq, ts, n, gid = _ATTACHMENT.unpack(data)
        if n != 16:
            raise RmwZenohError(f"attachment GID length {n}, expected 16")
        return cls(seq, ts, bytes(gid))


# ------------------------------------------------------------------ actions


def action_endpoints(name: str, action_type: str) -> dict[str, tuple[str, str]]:
    """The services and topics of an action (``/fibonacci``, ``pkg/action/Fibonacci``):
    part -> (name, ROS type), as rcl_action names them under ``<name>/_action/``."""
    base = name.rstrip("/") + "/_action/"
    return {
        "send_goal": (base + "send_goal", f"{action_type}_SendGoal"),
        "cancel_goal": (base + "cancel_goal", "action_msgs/srv/CancelGoal"),
        "get_result": (base + "get_result", f"{action_type}_GetResult"),
        "feedback": (base + "feedback", f"{action_type}_FeedbackMessage"),
        "status": (base + "status", "action_msgs/msg/GoalStatusArray"),
    }
