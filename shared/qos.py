"""Quality of service: reliability, durability (latched), keep-last depth, and ROS 2's
deadline, lifespan and liveliness policies (their events: `zenros.qos_events`)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum
from typing import Any

__all__ = [
    "QOS_DEFAULT",
    "QOS_LATCHED",
    "QOS_SENSOR",
    "Durability",
    "Liveliness",
    "QoSProfile",
    "Reliability",
    "as_profile",
]


class Reliability(str, Enum):
    """RELIABLE blocks the publisher rather than drop (Zenoh congestion control BLOCK);
    BEST_EFFORT drops under congestion (DROP), for high-rate sensor data."""

    RELIABLE = "reliable"
    BEST_EFFORT = "best_effort"


class Durability(str, Enum):
    """VOLATILE delivers only what is published after a subscriber joins; TRANSIENT_LOCAL
    ("latched") also delivers the publisher's last ``depth`` samples to late joiners."""

    VOLATILE = "volatile"
    TRANSIENT_LOCAL = "transient_local"


class Liveliness(str, Enum):
    """How a publisher shows it is alive (ROS 2's policy). AUTOMATIC: while its process
    runs (its Zenoh session's lease); MANUAL_BY_TOPIC: by publishing or
    ``Publisher.assert_liveliness()`` at least once per ``liveliness_lease_duration``."""

    AUTOMATIC = "automatic"
    MANUAL_BY_TOPIC = "manual_by_topic"


def _seconds(name: str, value: Any) -> float:
    """A policy's duration in seconds: a number, or anything with ``nanoseconds`` (a
    `Duration`, as rclpy takes); 0 is ROS 2's "infinite" (no deadline, no lifespan...)."""
    if hasattr(value, "nanoseconds"):
        ns = value.nanoseconds
        value = (ns() if callable(ns) else ns) / 1e9
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise TypeError(f"QoS {name} must be seconds or a Duration, got "
                        f"{type(value).__name__}")
    if not math.isfinite(value) or value < 0:
        raise ValueError(f"QoS {name} must be finite and >= 0 (0: none), got {value!r}")
    return float(value)


@dataclass(frozen=True)
class QoSProfile:
    """How a topic's samples travel. ``depth`` is keep-last: the latched history and the
    backlog bound of `async def` callbacks. ``deadline``, ``lifespan`` and
    ``liveliness_lease_duration`` are seconds (or a `Duration`), 0 for none, as ROS 2's
    policies of those names (docs/runtime.md, "QoS events")."""

    depth: int = 10
    reliability: Reliability = Reliability.RELIABLE
    durability: Durability = Durability.VOLATILE
    deadline: float = 0.0
    lifespan: float = 0.0
    liveliness: Liveliness = Liveliness.AUTOMATIC
    liveliness_lease_duration: float = 0.0

    def __post_init__(self) -> None:
        if isinstance(self.depth, bool) or not isinstance(self.depth, int):
            raise TypeError(f"QoS depth must be an int, got {type(self.depth).__name__}")
        if self.depth < 1:
            raise ValueError(f"QoS depth must be >= 1, got {self.depth}")
        for name in ("deadline", "lifespan", "liveliness_lease_duration"):
            object.__setattr__(self, name, _seconds(name, getattr(self, name)))
        object.__setattr__(self, "liveliness", Liveliness(self.liveliness))

    @property
    def latched(self) -> bool:
        return self.durability == Durability.TRANSIENT_LOCAL

    @property
    def tag(self) -> str:
        """Short form carried in liveliness tokens: ``rel``/``be``, ``+tl`` when latched, the
        depth, then the policies that are set: ``+d<s>`` deadline, ``+ls<s>`` lifespan,
        ``+m`` manual-by-topic liveliness, ``+lease<s>`` its lease (seconds, ``g`` format)."""
        base = "rel" if self.reliability == Reliability.RELIABLE else "be"
        out = base + ("+tl" if self.latched else "") + f"+{self.depth}"
        if self.deadline:
            out += f"+d{self.deadline:g}"
        if self.lifespan:
            out += f"+ls{self.lifespan:g}"
        if self.liveliness == Liveliness.MANUAL_BY_TOPIC:
            out += "+m"
        if self.liveliness_lease_duration:
            out += f"+lease{self.liveliness_lease_duration:g}"
        return out

    @classmethod
    def from_tag(cls, tag: str) -> QoSProfile:
        """The profile a `tag` stands for (``rel+tl+1``: reliable, latched, depth 1).

        Lenient, as tags come from other processes: a part it does not know is ignored, and a
        missing or bad depth is the default 10.
        """
        parts = tag.split("+")
        depth = next((int(p) for p in parts[1:] if p.isdigit() and int(p) >= 1), 10)
        policies = {"deadline": 0.0, "lifespan": 0.0, "liveliness_lease_duration": 0.0}
        for p in parts[1:]:
            for prefix, name in (("lease", "liveliness_lease_duration"), ("ls", "lifespan"),
                                 ("d", "deadline")):
                if p.startswith(prefix):
                    try:
                        v = float(p[len(prefix):])
                    except ValueError:
                        break
                    if math.isfinite(v) and v >= 0:
                        policies[name] = v
                    break
        return cls(depth=depth,
                   reliability=Reliability.BEST_EFFORT if parts[0] == "be"
                   else Reliability.RELIABLE,
                   durability=Durability.TRANSIENT_LOCAL if "tl" in parts[1:]
                   else Durability.VOLATILE,
                   liveliness=Liveliness.MANUAL_BY_TOPIC if "m" in parts[1:]
                   else Liveliness.AUTOMATIC, **policies)


QOS_DEFAULT = QoSProfile()
QOS_SENSOR = QoSProfile(depth=5, reliability=Reliability.BEST_EFFORT)
QOS_LATCHED = QoSProfile(depth=1, durability=Durability.TRANSIENT_LOCAL)


def as_profile(qos: QoSProfile | int) -> QoSProfile:
    """Accept rclpy's shorthand: an int is a default profile with that depth."""
    if isinstance(qos, QoSProfile):
        return qos
    if isinstance(qos, bool) or not isinstance(qos, int):
        raise TypeError(f"qos must be a QoSProfile or an int depth, got {type(qos).__name__}")
    return QoSProfile(depth=qos)
