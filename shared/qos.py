"""Quality of service: reliability, durability (latched) and keep-last depth."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

__all__ = [
    "QOS_DEFAULT",
    "QOS_LATCHED",
    "QOS_SENSOR",
    "Durability",
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


@dataclass(frozen=True)
class QoSProfile:
    """How a topic's samples travel. ``depth`` is keep-last: the latched history and the
    backlog bound of `async def` callbacks."""

    depth: int = 10
    reliability: Reliability = Reliability.RELIABLE
    durability: Durability = Durability.VOLATILE

    def __post_init__(self) -> None:
        if isinstance(self.depth, bool) or not isinstance(self.depth, int):
            raise TypeError(f"QoS depth must be an int, got {type(self.depth).__name__}")
        if self.depth < 1:
            raise ValueError(f"QoS depth must be >= 1, got {self.depth}")

    @property
    def latched(self) -> bool:
        return self.durability == Durability.TRANSIENT_LOCAL

    @property
    def tag(self) -> str:
        """Short form carried in liveliness tokens: ``rel``/``be`` plus ``+tl`` when latched."""
        base = "rel" if self.reliability == Reliability.RELIABLE else "be"
        return base + ("+tl" if self.latched else "") + f"+{self.depth}"

    @classmethod
    def from_tag(cls, tag: str) -> QoSProfile:
        """The profile a `tag` stands for (``rel+tl+1``: reliable, latched, depth 1).

        Lenient, as tags come from other processes: a part it does not know is ignored, and a
        missing or bad depth is the default 10.
        """
        parts = tag.split("+")
        depth = int(parts[-1]) if parts[-1].isdigit() and int(parts[-1]) >= 1 else 10
        return cls(depth=depth,
                   reliability=Reliability.BEST_EFFORT if parts[0] == "be"
                   else Reliability.RELIABLE,
                   durability=Durability.TRANSIENT_LOCAL if "tl" in parts[1:]
                   else Durability.VOLATILE)


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
