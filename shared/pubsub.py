"""`Publisher` and `Subscription`: typed topics over Zenoh, with intra-process delivery."""

from __future__ import annotations

import functools
import inspect
import logging
import threading
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, Generic, TypeVar

import zenoh
from zenoh import ext as zext

from .callbacks import make_dispatch
from .codec import codec_for
from .context import is_session_failure
from .errors import CodecError, EncodeError, NodeClosedError
from .executor import CallbackGroup
from .gate import DeliveryGate, Held
from .keytag import key_tag, misrouted
from .log import ErrorLog, Throttle
from .message import Message
from .qos import QoSProfile, Reliability
from .qos_events import EntityEvents, PublisherEventCallbacks, SubscriptionEventCallbacks
from .receivers import receiver_for

if TYPE_CHECKING:
    from typing_extensions import TypeIs

    from .context import Context

__all__ = ["MessageInfo", "Publisher", "Subscription", "SubscriptionCallback"]

M = TypeVar("M", bound=Message)


def entity_token(ctx: Context, kind: str, node: str, topic: str, type_name: str,
                 qos: QoSProfile, eid: int | None = None) -> zenoh.LivelinessToken:
    """The liveliness token that shows a topic endpoint in the graph (docs/wire.md)."""
    return ctx.session.liveliness().declare_token(ctx.keys.entity_token(
        kind, node, topic, type_name, qos.tag, ctx.zid, ctx.next_eid() if eid is None else eid))


def _events(ctx: Context, kind: str, topic: str, qos: QoSProfile, eid: int,
            callbacks: PublisherEventCallbacks | SubscriptionEventCallbacks | None,
            logger: logging.Logger | None) -> EntityEvents | None:
    """The QoS events of an endpoint given ``event_callbacks`` (none: nothing to watch)."""
    if callbacks is None:
        return None
    return EntityEvents(kind, topic, qos, f"{ctx.zid}/{eid}", callbacks, ctx.graph,
                        logger or logging.getLogger("zenros"))


def _congestion(qos: QoSProfile) -> zenoh.CongestionControl:
    if qos.reliability == Reliability.RELIABLE:
        return zenoh.CongestionControl.BLOCK
    return zenoh.CongestionControl.DROP


class Publisher(Generic[M]):
    """Publishes messages of one type on one topic.

    Subscriptions in the same context get the message object itself (no serialization);
    other sessions get it over Zenoh, encoded once, only when someone remote is listening
    (latched topics always encode, since their cache serves late joiners).
    """

    def __init__(
        self, ctx: Context, node: str, msg_type: type[M], topic: str, qos: QoSProfile,
        event_callbacks: PublisherEventCallbacks | None = None,
        logger: logging.Logger | None = None,
    ) -> None:
        self.msg_type = msg_type
        self.topic = topic
        self.qos = qos
        self.key = ctx.keys.topic(topic)
        self._ctx = ctx
        codec = codec_for(msg_type)
        # Bulk types go through Codec.encode, which gives arrays their declared dtype.
        self._encode = codec.encode if codec.bulk else codec._encode
        self.type_name = codec.type_name
        encoding = zenoh.Encoding(codec.mime).with_schema(codec.type_name)
        self._match_cond = threading.Condition()
        self._latched = qos.latched  # before the matching listener, whose events may come first
        self._pub: Any
        if qos.latched:
            self._pub = zext.declare_advanced_publisher(
                ctx.session, self.key, encoding=encoding,
                congestion_control=_congestion(qos),
                allowed_destination=zenoh.Locality.REMOTE,
                cache=zext.CacheConfig(max_samples=qos.depth),
                sample_miss_detection=zext.MissDetectionConfig(heartbeat=0.5,
                                                                sporadic_heartbeat=None),
                publisher_detection=True,
            )
            self._remote = True
            self._matching = None
        else:
            self._pub = ctx.session.declare_publisher(
                self.key, encoding=encoding, congestion_control=_congestion(qos),
                express=qos.reliability == Reliability.BEST_EFFORT,
                allowed_destination=zenoh.Locality.REMOTE,
            )
            self._remote = bool(self._pub.matching_status.matching)
            self._matching = self._pub.declare_matching_listener(self._on_matching)
        # The typed tag: subscriptions of this type skip the encoding comparison (keytag).
        self._put = functools.partial(
            self._pub.put, attachment=zenoh.ZBytes(key_tag(self.key, codec.encoding)))
        self._local = ctx.local_topic(topic)
        eid = ctx.next_eid()
        self.events = _events(ctx, "pub", topic, qos, eid, event_callbacks, logger)
        """The QoS events (`zenros.qos_events`) when created with ``event_callbacks``."""
        self._token = entity_token(ctx, "pub", node, topic, self.type_name, qos, eid)
        self.closed = False

    def _on_matching(self, status: Any) -> None:
        # Read the current status rather than trust the event's: events arrive late, and a
        # stale "no longer matching" (an old subscriber leaving) must not switch off puts to
        # a subscriber that has joined since.
        try:
            self._refresh_remote()
        except zenoh.ZError:
            if not self.closed:  # else an event in flight while close() undeclared the publisher
                raise

    def _refresh_remote(self) -> bool:
        if self._latched:  # always puts; late joiners query the cache
            return True
        with self._match_cond:
            self._remote = bool(self._pub.matching_status.matching)
            self._match_cond.notify_all()
            return self._remote

    def wait_for_subscribers(self, n: int = 1, timeout: float | None = None) -> bool:
        """Block until ``n`` subscriptions (any process) exist and Zenoh routes to the remote
        ones; False on timeout."""
        deadline = None if timeout is None else time.monotonic() + timeout
        graph = self._ctx.graph
        if not graph.wait_for(lambda: len(graph.subscribers(self.topic)) >= n, timeout):
            return False
        local = {id(s) for s in self._local.subs}
        if len(graph.subscribers(self.topic)) <= len(local):
            return True
        while not self._refresh_remote():  # the current status, not a possibly stale event
            left = None if deadline is None else deadline - time.monotonic()
            if left is not None and left <= 0:
                return False
            with self._match_cond:
                self._match_cond.wait(0.01 if left is None else min(left, 0.01))
        return True

    def publish(self, msg: M) -> None:
        """Send ``msg`` to every subscriber; raises `EncodeError` for a message of another type,
        `NodeClosedError` once the publisher is closed."""
        if self.closed:
            raise NodeClosedError(f"the publisher on {self.topic} is closed")
        if type(msg) is not self.msg_type:
            raise EncodeError(
                f"{self.topic} carries {self.type_name}, got {type(msg).__name__}"
            )
        if self.events is not None:
            self.events.sample()
        for sub in self._local.subs:
            sub._deliver_local(msg, self)
        if self._remote:
            try:
                data = self._encode(msg)
            except (TypeError, ValueError, NotImplementedError) as exc:
                raise EncodeError(f"cannot encode {self.type_name} on {self.topic}: {exc}") from exc
            try:
                self._put(data)
            except (zenoh.ZError, RuntimeError):  # undeclared, or "Already mutably borrowed"
                if self.closed:  # close() came between the check above and the put
                    raise NodeClosedError(f"the publisher on {self.topic} is closed") from None
                raise

    @property
    def subscription_count(self) -> int:
        """In-process subscriptions plus whether any remote one matches (0 or 1)."""
        return len(self._local.subs) + int(bool(self._remote))

    def assert_liveliness(self) -> None:
        """Show this MANUAL_BY_TOPIC publisher alive without publishing (rclpy's): its lease
        starts again. Other processes' subscriptions see samples only (`zenros.qos_events`)."""
        if self.events is not None:
            self.events.assert_liveliness()

    def close(self) -> None:
        """Undeclare the publisher; `publish` refuses from now on. Safe while another thread
        is in `publish`: its put ends first."""
        if self.closed:
            return
        self.closed = True
        if self.events is not None:
            self.events.close()
        if self._matching is not None:
            self._matching.undeclare()
        self._token.undeclare()  # type: ignore[no-untyped-call]
        undeclare_when_free(self._pub)


def undeclare_when_free(entity: Any, timeout: float = 5.0) -> None:
    """Undeclare a Zenoh entity that another thread may be using. zenoh-python refuses
    (RuntimeError "Already borrowed") while a call on it is in progress in another thread (a
    ``put``, a matching status read), and such a call ends within milliseconds: try again
    until it has, for at most ``timeout`` seconds."""
    deadline = time.monotonic() + timeout
    while True:
        try:
            entity.undeclare()
            return
        except RuntimeError as exc:
            if "borrowed" not in str(exc) or time.monotonic() >= deadline:
                raise
            time.sleep(0.0005)


class MessageInfo:
    """How one message arrived (rclpy's ``MessageInfo``), for callbacks that take it.

    A subscription callback with two parameters, ``callback(msg, info)``, gets one with each
    message. Built only for such callbacks; the source timestamp is converted on first use.

    Attributes:
        publisher_gid: the publishing Zenoh session's id (``Graph.nodes_of_zid`` names its
            nodes); empty when the sample carried no timestamp.
        received_timestamp: wall-clock nanoseconds (Unix epoch) when it was received.
        from_intra_process: True when a publisher in this process handed it over directly.
    """

    __slots__ = ("_ts", "from_intra_process", "publisher_gid", "received_timestamp")

    def __init__(self, ts: zenoh.Timestamp | None, publisher_gid: str,
                 from_intra_process: bool = False) -> None:
        self._ts = ts
        self.publisher_gid = publisher_gid
        self.received_timestamp = time.time_ns()
        self.from_intra_process = from_intra_process

    @classmethod
    def of(cls, sample: zenoh.Sample) -> MessageInfo:
        ts = sample.timestamp
        return cls(ts, str(ts.get_id()) if ts is not None else "")

    @property
    def source_timestamp(self) -> int:
        """Publication time, nanoseconds since the Unix epoch (the publisher session's
        hybrid clock); the receive time for an in-process message, 0 when unknown."""
        if self.from_intra_process:
            return self.received_timestamp
        return int(self._ts.get_time_as_ntp64().as_nanos()) if self._ts is not None else 0

    def __repr__(self) -> str:
        return (f"MessageInfo(publisher_gid={self.publisher_gid!r}, source_timestamp="
                f"{self.source_timestamp}, received_timestamp={self.received_timestamp}, "
                f"from_intra_process={self.from_intra_process})")


SubscriptionCallback = Callable[[M], Any] | Callable[[M, MessageInfo], Any]
"""``callback(msg)``, or ``callback(msg, info)`` to get each message's `MessageInfo` too."""


def _takes_info(callback: SubscriptionCallback[M]) -> TypeIs[Callable[[M, MessageInfo], Any]]:
    """True for ``callback(msg, info)``: two or more positional parameters."""
    try:
        params = inspect.signature(callback).parameters.values()
    except (TypeError, ValueError):
        return False
    positional = [p for p in params if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
    return len(positional) >= 2


def _with_info(callback: Callable[..., Any]) -> Callable[[Any], Any]:
    """``callback(msg, info)`` as a one-argument callback of ``(msg, info)`` pairs."""
    if inspect.iscoroutinefunction(callback):
        async def call_async(pair: tuple[Any, MessageInfo]) -> Any:
            return await callback(pair[0], pair[1])

        return call_async

    def call(pair: tuple[Any, MessageInfo]) -> Any:
        return callback(pair[0], pair[1])

    return call


class Subscription(Generic[M]):
    """Receives messages of one type from one topic and hands them to a callback.

    A sample that fails to decode, or carries another type, is logged (rate-limited per
    sender) and counted in ``errors``; the callback never sees it and the node keeps running.
    A callback with two parameters, ``callback(msg, info)``, also gets a `MessageInfo`.
    With a closed ``gate`` (its node's setup() is running), messages are held, the last
    ``qos.depth``, and delivered in order when the gate opens.
    """

    def __init__(
        self,
        ctx: Context,
        node: str,
        msg_type: type[M],
        topic: str,
        callback: SubscriptionCallback[M],
        qos: QoSProfile,
        logger: logging.Logger,
        group: CallbackGroup | None = None,
        gate: DeliveryGate | None = None,
        event_callbacks: SubscriptionEventCallbacks | None = None,
    ) -> None:
        self.msg_type = msg_type
        self.topic = topic
        self.qos = qos
        self.key = ctx.keys.topic(topic)
        self._eid = ctx.next_eid()
        self.events = _events(ctx, "sub", topic, qos, self._eid, event_callbacks, logger)
        """The QoS events (`zenros.qos_events`) when created with ``event_callbacks``."""
        self.errors = 0
        self.misrouted = 0
        """Samples dropped because they were published on another key (`zenros.keytag`)."""
        self._ctx = ctx
        self._logger = logger
        self._throttle = Throttle(5.0)
        self._codec = codec_for(msg_type)
        self._decode = self._codec._fast_decode  # a refused sample retries `_decode_slow`
        self._encoding = zenoh.Encoding(self._codec.mime).with_schema(self._codec.type_name)
        self._tag = key_tag(self.key, self._codec.encoding)  # what our publishers attach
        call: Callable[[Any], Any]  # of a message, or of a (message, info) pair
        if _takes_info(callback):
            self._info = True
            call = _with_info(callback)
        else:
            self._info = False
            call = callback
        # A plain sync callback with no group is called straight from the receive loop.
        self._direct = (call if group is None and not inspect.iscoroutinefunction(call)
                        else None)
        self._callback_errors = ErrorLog(logger)
        self._dispatch = make_dispatch(
            call, executor=ctx.executor, logger=logger, what=f"subscription {topic}",
            group=group, depth=qos.depth, errors=self._callback_errors,
        )
        if gate is not None and not gate.is_open:
            self._dispatch = Held(gate, self._dispatch, qos.depth)
            self._direct = None
        self._receiver = receiver_for(ctx.session, self.key, qos, self._codec.bulk,
                                      self._on_sample, self._sample_path,
                                      f"zenros-sub:{topic}")
        # Live in-process samples come from the context's bus, joined before the token is
        # declared: once the graph shows this subscription, an in-process publisher reaches it.
        ctx.add_local(topic, "subs", self)
        self._token = entity_token(ctx, "sub", node, topic, self._codec.type_name, qos,
                                   self._eid)
        self.closed = False

    def _sample_path(self, first: Callable[[threading.Thread], None]
                     ) -> Callable[[zenoh.Sample], None]:
        """The per-sample path of a queue-drained receiver, on the thread that drains Zenoh's
        queue (``first(thread)`` on its first sample): decode, hand to the callback (called
        right there when it needs no executor). What it reads is bound as locals: the hot
        path of a subscription."""
        admit, decode, dispatch = self._admit, self._decode, self._dispatch
        direct, info, tag, events = self._direct, self._info, self._tag, self.events
        named = False

        def take(sample: zenoh.Sample) -> None:
            nonlocal named
            if not named:
                named = True
                first(threading.current_thread())
            try:
                att = sample.attachment
                if (att is None or att.to_bytes() != tag) and not admit(sample):
                    return
                if events is not None and not self._event_sample(sample):
                    return
                data = sample.payload.to_bytes()
                try:
                    msg: Any = decode(data)  # or (msg, info) below
                except Exception:  # noqa: BLE001 msgspec's errors, RecursionError
                    msg = self._decode_slow(data, sample)
                    if msg is None:
                        return
                if info:
                    msg = (msg, MessageInfo.of(sample))
                if direct is None:
                    dispatch(msg)
                    return
                try:
                    direct(msg)
                except Exception as exc:  # noqa: BLE001 user code never stops the subscription
                    self._callback_raised(exc)
            except Exception as exc:  # noqa: BLE001 no sample stops the subscription
                self._reject(f"{type(exc).__name__}: {exc}", ("an unknown sender", ""))
            except BaseException as exc:
                if not is_session_failure(exc):
                    raise
                self._ctx.fail(exc)  # the process exits (runtime) so supervision can restart it

        return take

    @property
    def callback_errors(self) -> int:
        """Messages whose callback raised (logged with the traceback, rate-limited)."""
        return self._callback_errors.count

    def _callback_raised(self, exc: Exception) -> None:
        self._callback_errors.report(type(exc).__name__, logging.ERROR,
                                     "subscription %s callback raised %s: %s", self.topic,
                                     type(exc).__name__, exc, exc_info=exc)

    def _decode_slow(self, data: bytes, sample: zenoh.Sample) -> Any:
        """A sample the fast decoder refused: decoded with the codec's retries (``null`` in
        a float field as NaN), else rejected (None)."""
        try:
            return self._codec._decode(data)
        except Exception as exc:  # noqa: BLE001 msgspec's errors, RecursionError
            self._reject(f"expected {self._codec.type_name}: {exc}", self._sender(sample))
            return None

    def _event_sample(self, sample: zenoh.Sample) -> bool:
        """The sample for the QoS events: False to drop it (past its lifespan)."""
        assert self.events is not None
        ts = sample.timestamp
        if ts is None:
            return self.events.sample()
        return self.events.sample(str(ts.get_id()),
                                  lambda: int(ts.get_time_as_ntp64().as_nanos()))

    def _deliver_local(self, msg: Any, pub: Publisher[Any]) -> None:
        if type(msg) is not self.msg_type:
            self._reject(f"type mismatch: expected {self._codec.type_name}, got {pub.type_name}",
                         ("this process", "local"))
            return
        if self.events is not None:
            self.events.sample(self._ctx.zid)
        if self._info:
            msg = (msg, MessageInfo(None, self._ctx.zid, from_intra_process=True))
        self._dispatch(msg)

    def _on_sample(self, sample: zenoh.Sample) -> None:
        # The hot path: one tag comparison, one decode, one call. Anything unusual (another
        # type, a bad payload) takes the slow path in _admit and _check.
        try:
            att = sample.attachment
            if (att is None or att.to_bytes() != self._tag) and not self._admit(sample):
                return
            if self.events is not None and not self._event_sample(sample):
                return
            data = sample.payload.to_bytes()
            try:
                msg = self._decode(data)
            except Exception:  # noqa: BLE001 msgspec's errors, RecursionError
                msg = self._decode_slow(data, sample)
                if msg is None:
                    return
            self._dispatch((msg, MessageInfo.of(sample)) if self._info else msg)
        except Exception as exc:  # noqa: BLE001 nothing raises into Zenoh's thread
            self._reject(f"{type(exc).__name__}: {exc}", ("an unknown sender", ""))
        except BaseException as exc:
            if not is_session_failure(exc):
                raise
            self._ctx.fail(exc)

    def _admit(self, sample: zenoh.Sample) -> bool:
        """The checks of a sample without this subscription's own typed tag (untagged, an older
        publisher's tag, another type's): False when it was published on another key (dropped
        and counted) or names another encoding (`_check` decides)."""
        if misrouted(sample.attachment, self._tag):
            self._misrouted(sample)
            return False
        if sample.encoding != self._encoding:
            self._check(sample)
            return False
        return True

    def _misrouted(self, sample: zenoh.Sample) -> None:
        """A sample published on another key that Zenoh delivered here: dropped, counted, and
        logged once per sender every 5 s (`zenros.keytag`)."""
        self.misrouted += 1
        who, key = self._sender(sample)
        if self._throttle.allow("misrouted" + key):
            self._logger.error("dropped a sample on %s from %s that was published on another "
                               "key (Zenoh misrouted it; docs/wire.md); %d so far",
                               self.key, who, self.misrouted)

    def _check(self, sample: zenoh.Sample) -> None:
        try:
            self._codec.check_encoding(str(sample.encoding))
            msg = self._codec.decode(sample.payload.to_bytes())
        except CodecError as exc:
            self._reject(str(exc), self._sender(sample))
            return
        self._dispatch((msg, MessageInfo.of(sample)) if self._info else msg)

    def _sender(self, sample: zenoh.Sample) -> tuple[str, str]:
        """(who, throttle key): node names behind the sample's session, and the session id."""
        ts = sample.timestamp
        if ts is None:
            return "an unknown sender", ""
        zid = str(ts.get_id())
        nodes = self._ctx.graph.nodes_of_zid(zid, self.topic)
        return (", ".join(nodes) if nodes else f"session {zid}"), zid

    def _reject(self, why: str, sender: tuple[str, str]) -> None:
        who, key = sender
        if self._throttle.allow(key):
            extra = self._throttle.suppressed.pop(key, 0)
            more = f" ({extra} more suppressed)" if extra else ""
            self._logger.error("cannot decode %s from %s: %s%s", self.key, who, why, more)
        self.errors += 1

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        if self.events is not None:
            self.events.close()
        self._ctx.remove_local(self.topic, "subs", self)
        self._token.undeclare()  # type: ignore[no-untyped-call]
        self._receiver.close()  # a sample being handled finishes first
