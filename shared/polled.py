"""`PolledSubscription`: a subscription that is read when its reader wants, not called.

A `Subscription` wakes a Python thread and decodes every sample; a reader that only needs
the newest message and how many arrived (a gateway's status at 10 Hz from odometry at
50 Hz, or whether a laser is alive) pays that for nothing. Here Zenoh keeps the last
``qos.depth`` samples in its ring channel without touching Python, and `take` drains
them when asked: it counts them, notes when each was published, and decodes only the
newest (only if ``decode``). Same key, encoding checks, liveliness token and in-process
delivery as a `Subscription`, so the graph and the publishers see an ordinary subscriber.
"""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Generic, TypeVar

import zenoh

from .codec import codec_for
from .errors import CodecError
from .keytag import key_tag, misrouted
from .log import Throttle
from .message import Message
from .pubsub import entity_token
from .qos import QoSProfile

if TYPE_CHECKING:
    from .context import Context
    from .pubsub import Publisher

__all__ = ["PolledSubscription", "Taken"]

M = TypeVar("M", bound=Message)


@dataclass
class Taken(Generic[M]):
    """What arrived since the last `PolledSubscription.take`.

    Attributes:
        count: samples that arrived (at most the subscription's ``qos.depth``: older ones
            were overwritten).
        arrivals: when each was published, oldest first, as ``time.monotonic()`` seconds
            (from the sample's timestamp; the take time for a sample without one).
        latest: the newest one decoded, or None (nothing arrived, ``decode=False``, or the
            newest could not be decoded: logged and counted in ``errors``).
    """

    count: int = 0
    arrivals: list[float] = field(default_factory=list)
    latest: M | None = None


class PolledSubscription(Generic[M]):
    """A subscription of ``msg_type`` on ``topic`` whose samples wait until `take`.

    Best effort in effect whatever ``qos``: the ring keeps the last ``qos.depth`` samples.
    Thread safe. Build it with `zenros.node.Node.create_polled_subscription`.
    """

    def __init__(self, ctx: Context, node: str, msg_type: type[M], topic: str,
                 qos: QoSProfile, logger: logging.Logger) -> None:
        self.msg_type = msg_type
        self.topic = topic
        self.qos = qos
        self.key = ctx.keys.topic(topic)
        self.errors = 0
        self.misrouted = 0
        self._ctx = ctx
        self._logger = logger
        self._throttle = Throttle(5.0)
        self._tag = key_tag(self.key)
        self._codec = codec_for(msg_type)
        self._encoding = zenoh.Encoding(self._codec.mime).with_schema(self._codec.type_name)
        self._lock = threading.Lock()
        self._local: deque[tuple[float, M]] = deque(maxlen=max(1, qos.depth))
        self._sub: Any = ctx.session.declare_subscriber(
            self.key, zenoh.handlers.RingChannel(max(1, qos.depth)),
            allowed_origin=zenoh.Locality.REMOTE)
        self._channel: Any = self._sub.handler
        ctx.add_local(topic, "subs", self)
        self._token = entity_token(ctx, "sub", node, topic, self._codec.type_name, qos)
        self.closed = False

    def take(self, decode: bool = True) -> Taken[M]:
        """Drain what arrived since the last call (see `Taken`)."""
        out: Taken[M] = Taken()
        newest: zenoh.Sample | None = None
        newest_at = -1.0
        local: M | None = None
        with self._lock:
            if self.closed:
                return out
            mono, wall = time.monotonic(), time.time_ns()
            # At most a ring's worth: what arrives while this drains is the next take's (a
            # publisher still sending had made this loop return depth + 1 under load).
            for _ in range(self._local.maxlen or 1):
                if (sample := self._channel.try_recv()) is None:
                    break
                if misrouted(sample.attachment, self._tag):
                    self.misrouted += 1
                    continue
                if sample.encoding != self._encoding and not self._encoding_ok(sample):
                    continue
                ts = sample.timestamp
                at = (mono if ts is None else
                      mono - max(0, wall - ts.get_time_as_ntp64().as_nanos()) / 1e9)
                out.arrivals.append(at)
                newest, newest_at = sample, at
            while self._local:
                at, msg = self._local.popleft()
                out.arrivals.append(at)
                if at >= newest_at:
                    local, newest_at, newest = msg, at, None
        out.arrivals.sort()
        del out.arrivals[:-(self._local.maxlen or 1)]  # remote and in-process: the newest
        out.count = len(out.arrivals)
        if decode:
            out.latest = local if newest is None else self._decode(newest)
        return out

    def _encoding_ok(self, sample: zenoh.Sample) -> bool:
        """A sample of another type or encoding is not counted (logged, in ``errors``)."""
        try:
            self._codec.check_encoding(str(sample.encoding))
        except CodecError as exc:
            self._error(str(exc))
            return False
        return True

    def _decode(self, sample: zenoh.Sample) -> M | None:
        try:
            msg: M = self._codec.decode(sample.payload.to_bytes())
        except Exception as exc:  # noqa: BLE001 msgspec's errors, RecursionError
            self._error(f"expected {self._codec.type_name}: {exc}")
            return None
        return msg

    def _error(self, why: str) -> None:
        self.errors += 1
        if self._throttle.allow("error"):
            self._logger.error("cannot take %s: %s", self.key, why)

    def _deliver_local(self, msg: Any, pub: Publisher[Any]) -> None:
        """An in-process publisher's message (kept as is, no serialization)."""
        if type(msg) is not self.msg_type:
            self._error(f"expected {self._codec.type_name}, got {pub.type_name}")
            return
        with self._lock:
            self._local.append((time.monotonic(), msg))

    def close(self) -> None:
        with self._lock:
            if self.closed:
                return
            self.closed = True
        self._ctx.remove_local(self.topic, "subs", self)
        self._token.undeclare()  # type: ignore[no-untyped-call]
        self._sub.undeclare()
