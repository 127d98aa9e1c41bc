"""Time values for TF: `Time` ↔ integer nanoseconds, the LATEST sentinel, and formatting."""

from __future__ import annotations

from ..errors import InvalidArgumentException
from ..msgs.builtin_interfaces import Duration, Time

NS = 1_000_000_000

LATEST = Time()
"""Time 0: "the latest data available" (tf2's ``TimePointZero``)."""

TimeLike = Time | int
"""A stamp: a `Time` message, or integer nanoseconds (0 means latest)."""

__all__ = ["LATEST", "NS", "TimeLike", "format_ns", "from_ns", "seconds", "to_ns"]


def to_ns(t: TimeLike) -> int:
    """Integer nanoseconds of a stamp.

    Raises:
        InvalidArgumentException: ``t`` is neither a `Time` nor an int.
    """
    if isinstance(t, Time):
        return t.sec * NS + t.nanosec
    if isinstance(t, int) and not isinstance(t, bool):
        return t
    raise InvalidArgumentException(
        f"expected a Time or integer nanoseconds as a stamp, got {type(t).__name__} {t!r}"
    )


def from_ns(ns: int) -> Time:
    """The `Time` for integer nanoseconds."""
    sec, nanosec = divmod(ns, NS)
    return Time(sec=sec, nanosec=nanosec)


def seconds(d: float | Duration) -> float:
    """A timeout or window in float seconds, from seconds or a `Duration`.

    Raises:
        InvalidArgumentException: ``d`` is not a number or `Duration`, or is negative/NaN.
    """
    if isinstance(d, Duration):
        s = d.nanoseconds / NS
    elif isinstance(d, (int, float)) and not isinstance(d, bool):
        s = float(d)
    else:
        raise InvalidArgumentException(
            f"expected seconds (float) or a Duration, got {type(d).__name__} {d!r}"
        )
    if not s >= 0.0:
        raise InvalidArgumentException(f"expected a duration >= 0 s, got {s}")
    return s


def format_ns(ns: int) -> str:
    """Seconds with nine decimals, as tf2 (ROS 1) prints times: ``1.500000000``."""
    sign = "-" if ns < 0 else ""
    sec, nanosec = divmod(abs(ns), NS)
    return f"{sign}{sec}.{nanosec:09d}"
