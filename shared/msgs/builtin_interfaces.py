"""builtin_interfaces: `Time` and `Duration` (sec, nanosec), with arithmetic."""

from __future__ import annotations

import math
from typing import Any, Self

from ..message import Message

_NS = 1_000_000_000


class _SecNsec(Message, frozen=True, order=False):  # type: ignore[misc]
    """``sec`` plus ``nanosec`` in [0, 1e9): construction, conversion, ordering, hashing.

    Ordering compares only values of the same class (a `Time` is not less than a
    `Duration`); the arithmetic that mixes them lives in the subclasses.
    """

    sec: int = 0
    nanosec: int = 0

    @classmethod
    def from_nanoseconds(cls, ns: int) -> Self:
        sec, nanosec = divmod(int(ns), _NS)
        return cls(sec=sec, nanosec=nanosec)

    @classmethod
    def from_seconds(cls, seconds: float) -> Self:
        if not math.isfinite(seconds):
            raise ValueError(f"{cls.__name__.lower()} must be finite, got {seconds}")
        return cls.from_nanoseconds(round(seconds * _NS))

    @property
    def nanoseconds(self) -> int:
        return self.sec * _NS + self.nanosec

    def to_sec(self) -> float:
        return self.nanoseconds / _NS

    def __hash__(self) -> int:
        return hash((type(self), self.sec, self.nanosec))

    def _key(self, o: object) -> int | None:
        return o.nanoseconds if type(o) is type(self) else None

    def __lt__(self, o: object) -> bool:
        k = self._key(o)
        return NotImplemented if k is None else self.nanoseconds < k

    def __le__(self, o: object) -> bool:
        k = self._key(o)
        return NotImplemented if k is None else self.nanoseconds <= k

    def __gt__(self, o: object) -> bool:
        k = self._key(o)
        return NotImplemented if k is None else self.nanoseconds > k

    def __ge__(self, o: object) -> bool:
        k = self._key(o)
        return NotImplemented if k is None else self.nanoseconds >= k


class Duration(_SecNsec, frozen=True, order=False):  # type: ignore[misc]
    """A signed span of time: ``sec`` (may be negative) plus ``nanosec`` in [0, 1e9)."""

    __msgtype__ = "builtin_interfaces/Duration"

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


class Time(_SecNsec, frozen=True, order=False):  # type: ignore[misc]
    """A point in time since an epoch (wall, steady or simulated): ``sec`` and ``nanosec``."""

    __msgtype__ = "builtin_interfaces/Time"

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
