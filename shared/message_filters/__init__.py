"""Message filters as ROS's `message_filters`: Subscriber, Cache and the time synchronizers.

Same names, arguments and callbacks as rclpy's message_filters, with the algorithms of ROS's
C++ policies (docs/message_filters.md): `TimeSynchronizer` is ExactTime, and
`ApproximateTimeSynchronizer` is ApproximateTime (the set of smallest spread, each topic's
queue, inter-message lower bounds, age penalty), ``slop`` its largest span.
"""

from __future__ import annotations

from .approximate import ApproximateTimeSynchronizer
from .cache import Cache
from .exact import TimeSynchronizer
from .filter import SimpleFilter, Subscriber, stamp_ns

__all__ = [
    "ApproximateTimeSynchronizer",
    "Cache",
    "SimpleFilter",
    "Subscriber",
    "TimeSynchronizer",
    "stamp_ns",
]
