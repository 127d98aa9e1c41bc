"""What bag readers hand out: `BagMessage`, and `BagError` for a bag that cannot be read
(zenros's own bags, `zenros.bag.reader`; bags recorded with ROS, `zenros.bag.foreign`)."""

from __future__ import annotations

from dataclasses import dataclass

from mcap.records import Channel, Schema

from ..errors import ZenrosError

__all__ = ["BagError", "BagMessage"]


class BagError(ZenrosError, ValueError):
    """A bag that cannot be read: missing, not MCAP, truncated or corrupt."""


@dataclass(frozen=True)
class BagMessage:
    """One recorded message with its channel."""

    log_time: int
    publish_time: int
    sequence: int
    channel: Channel
    schema: Schema | None
    data: bytes
