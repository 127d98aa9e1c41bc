"""builtin_interfaces: `Time` and `Duration` (sec, nanosec), with arithmetic."""

from __future__ import annotations

import math
from typing import Any

from ..message import Message

_NS = 1_000_000_000


def _split(ns: int) -> tuple[int, int]:
    sec, nanosec = divmod(ns, _NS)
    return sec, nanosec


class Duration(Message, frozen=True, order=False):  # type: ignore[misc]
    """A signed span of time: ``sec`` (may be negative) plus ``nanosec`` in [0, 1e9)."""

    __msgtype__ = "builtin_interfaces/Duration"
    sec: int = 0
    nanosec: int = 0

    @classmethod
    def from_nanoseconds(cls, ns: int) -> Duration:
        sec, nanosec = _split(int(ns))
        return cls(sec=sec, nanosec=nanosec)

    @classmethod
    def from_seconds(cls, seconds: float) -> Duration:
        if not math.isfinite(seconds):
            raise ValueError(f"duration must be finite, got {seconds}")
        return cls.from_nanoseconds(round(seconds * _NS))

    @property
    def nanoseconds(self) -> int:
        return self.sec * _NS + self.nanosec

    def to_sec(self) -> float:
        return self.nanoseconds / _NS

    def __hash__(self) -> int:
        return hash((Duration, self.sec, self.nanosec))

    def __add__(self, other: Any) -> Any:
        if isinstance(other, Duration):
            return Duration.from_nanoseconds(self.nanoseconds + other.nanoseconds)
        if isinstance(other, Time):
            return Time.from_nanoseconds(self.nanoseconds + other.nanoseconds)
        return NotImplemented

    def __sub__(self, other: Any) -> Duration:
        if isinstance(other, Duration):
            return Duration.from_nanoseconds(self.nanoseconds - other.nanoseconds)
        return NotImplemented

    def __neg__(self) -> Duration:
        return Duration.from_nanoseconds(-self.nanoseconds)

    def __mul__(self, k: float) -> Duration:
        return Duration.from_nanoseconds(round(self.nanoseconds * k))

    def __lt__(self, o: object) -> bool:
        if not isinstance(o, Duration):
            return NotImplemented
        return self.nanoseconds < o.nanoseconds

    def __le__(self, o: object) -> bool:
        if not isinstance(o, Duration):
            return NotImplemented
        return self.nanoseconds <= o.nanoseconds

    def __gt__(self, o: object) -> bool:
        if not isinstance(o, Duration):
            return NotImplemented
        return self.nanoseconds > o.nanoseconds

    def __ge__(self, o: object) -> bool:
        if not isinstance(o, Duration):
            return NotImplemented
        return self.nanoseconds >= o.nanoseconds


class Time(Message, frozen=True, order=False):  # type: ignore[misc]
    """A point in time since an epoch (wall, steady or simulated): ``sec`` and ``nanosec``."""

    __msgtype__ = "builtin_interfaces/Time"
    sec: int = 0
    nanosec: int = 0

    @classmethod
    def from_nanoseconds(cls, ns: int) -> Time:
        sec, nanosec = _split(int(ns))
        return cls(sec=sec, nanosec=nanosec)

    @classmethod
    def from_seconds(cls, seconds: float) -> Time:
        if not math.isfinite(seconds):
            raise ValueError(f"time must be finite, got {seconds}")
        return cls.from_nanoseconds(round(seconds * _NS))

    @property
    def nanoseconds(self) -> int:
        return self.sec * _NS + self.nanosec

    def to_sec(self) -> float:
        return self.nanoseconds / _NS

    def __hash__(self) -> int:
        return hash((Time, self.sec, self.nanosec))

    def is_zero(self) -> bool:
        return self.sec == 0 and self.nanosec == 0

    def __add__(self, other: Any) -> Time:
        if isinstance(other, Duration):
            return Time.from_nanoseconds(self.nanoseconds + other.nanoseconds)
        return NotImplemented

    def __sub__(self, other: Any) -> Any:
        if isinstance(other, Time):
            return Duration.from_nanoseconds(self.nanoseconds - other.nanoseconds)
        if isinstance(other, Duration):
            return Time.from_nanoseconds(self.nanoseconds - other.nanoseconds)
        return NotImplemented

    def __lt__(self, o: object) -> bool:
        if not isinstance(o, Time):
            return NotImplemented
        return self.nanoseconds < o.nanoseconds

    def __le__(self, o: object) -> bool:
        if not isinstance(o, Time):
            return NotImplemented
        return self.nanoseconds <= o.nanoseconds

    def __gt__(self, o: object) -> bool:
        if not isinstance(o, Time):
            return NotImplemented
        return self.nanoseconds > o.nanoseconds

    def __ge__(self, o: object) -> bool:
        if not isinstance(o, Time):
            return NotImplemented
        return self.nanoseconds >= o.nanoseconds
