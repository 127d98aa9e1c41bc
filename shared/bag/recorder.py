"""`Recorder`: subscribes to topics (raw samples, any type) and writes them to a bag."""

from __future__ import annotations

import re
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import zenoh
from zenoh import ext as zext

from ..codec import MSGPACK, split_encoding
from ..context import Context
from ..names import Token, resolve
from ..registry import lookup_type
from .schema import message_encoding, schema_for, schema_of_type
from .sink import CHUNK_SIZE, FLUSH_INTERVAL, BagSink, SplitPolicy
from .stamp import stamp_reader
from .transcode import TRANSCODED, to_json
from .writer import MESSAGE_HEAD

__all__ = ["RecordOptions", "Recorder"]

FIFO_CAPACITY = 256  # samples buffered per subscriber before Zenoh pushes back (reliable)
QOS_UNKNOWN = "rel+10"
TOKEN_WAIT = 2.0  # s a new topic's first sample waits for its publisher's token (its QoS)
BATCH = 64  # samples a pump hands to the sink at once at most (fewer when it catches up)


@dataclass
class RecordOptions:
    """What to record and how.

    Attributes:
        directory: the bag directory (created); files are ``<name>_<i>.mcap`` inside it.
        topics: topic names to record; empty with ``all_topics`` for everything.
        all_topics: record every topic, including those that appear later.
        exclude: a regular expression; matching topic names are not recorded.
        compression: ``zstd``, ``lz4`` or ``none``.
        split: when to start the next file.
        chunk_size, flush_interval: see `BagSink`.
        bulk_json: store bulk (MessagePack) types as JSON, so that JSON-only viewers
            (Foxglove) decode them; costs a decode and an encode per bulk message.
    """

    directory: Path
    topics: list[str] = field(default_factory=list)
    all_topics: bool = False
    exclude: str | None = None
    compression: str = "zstd"
    split: SplitPolicy = field(default_factory=SplitPolicy)
    chunk_size: int = CHUNK_SIZE
    flush_interval: float = FLUSH_INTERVAL
    bulk_json: bool = False


class _Route:
    """Where samples of one key and encoding go: a channel, and how to read their stamp."""

    __slots__ = ("channel", "encoding", "plain", "seq", "stamp", "transcode")

    def __init__(self, channel: int, encoding: str, stamp: Callable[[bytes], int] | None,
                 transcode: Callable[[bytes], bytes | None] | None = None) -> None:
        self.channel = channel
        self.seq = 0  # the channel's last message number (only its key's pump counts)
        self.encoding = zenoh.Encoding(encoding)  # compared with samples' as is (no str())
        self.stamp = stamp
        self.transcode = transcode
        self.plain = stamp is None and transcode is None  # the source timestamp, bytes as is


class Recorder:
    """Records topics of one context's network into a bag until `close`.

    Samples are taken raw from Zenoh (``application/json`` or MessagePack bytes, the type
    named in the encoding's schema) and written as they arrived: nothing is decoded or
    re-encoded. Subscribers are Zenoh advanced subscribers with history, so latched topics'
    cached samples (tf_static, map) are recorded at start and when a latched publisher
    appears later. Reliable publishers are never dropped: a full FIFO pushes back.
    The recorder must have its own session (publishers skip Zenoh for subscribers in their
    own context).
    """

    def __init__(self, ctx: Context, options: RecordOptions, node: str = "/zenros_bag_recorder",
                 on_channel: Callable[[str, str], None] | None = None) -> None:
        if not options.all_topics and not options.topics:
            raise ValueError("give topics to record, or all topics (-a)")
        self.ctx = ctx
        self.options = options
        self.node = node
        self._on_channel = on_channel
        self._exclude = re.compile(options.exclude) if options.exclude else None
        self._topics = {resolve(t) for t in options.topics}
        self.sink = BagSink(options.directory, options.directory.name,
                            compression=options.compression, chunk_size=options.chunk_size,
                            flush_interval=options.flush_interval, split=options.split)
        self._routes: dict[str, _Route | None] = {}  # key -> its latest route (None: excluded)
        self._by_encoding: dict[tuple[str, str], _Route] = {}
        self._route_lock = threading.Lock()
        self._tokens: dict[tuple[str, str], Any] = {}
        self._token_lock = threading.Lock()
        self._closed = False
        self.dropped = 0  # bulk payloads that could not be transcoded (bulk_json only)
        self._subs: list[Any] = []
        self._pumps: list[threading.Thread] = []
        graph = ctx.graph
        self._remove_listener = graph.add_listener(self._on_graph)
        for tok in graph.tokens("pub"):
            self._on_graph("put", tok)
        keys = ([ctx.keys.all_topics()] if options.all_topics
                else [ctx.keys.topic(t) for t in sorted(self._topics)])
        for key in keys:
            self._subscribe(key)

    # ------------------------------------------------------------------ subscribing

    def _subscribe(self, key: str) -> None:
        sub = zext.declare_advanced_subscriber(
            self.ctx.session, key, zenoh.handlers.FifoChannel(FIFO_CAPACITY),
            history=zext.HistoryConfig(detect_late_publishers=True),
            recovery=zext.RecoveryConfig(heartbeat=True, periodic_queries=None),
            subscriber_detection=True,
        )
        fixed = None if key == self.ctx.keys.all_topics() else key
        # the channel is taken here: `.handler` read in the pump while stop() undeclares
        # raises pyo3's "Already mutably borrowed"
        pump = threading.Thread(target=self._pump, args=(sub.handler, fixed),
                                name=f"zenros-bag:{key}", daemon=True)
        self._subs.append(sub)
        self._pumps.append(pump)
        pump.start()

    def wanted(self, topic: str) -> bool:
        """Whether ``topic`` is recorded (the topic list or -a, minus --exclude)."""
        if not self.options.all_topics and topic not in self._topics:
            return False
        return not (self._exclude is not None and self._exclude.search(topic))

    def _on_graph(self, event: str, tok: Token) -> None:
        """Show the recorder as a subscriber of every recorded topic that has a publisher, so
        `topic info` lists it and publishers' ``wait_for_subscribers`` see it."""
        if event != "put" or tok.kind != "pub" or not self.wanted(tok.name):
            return
        with self._token_lock:
            if self._closed or (tok.name, tok.type) in self._tokens:
                return
            ctx = self.ctx
            self._tokens[(tok.name, tok.type)] = ctx.session.liveliness().declare_token(
                ctx.keys.entity_token("sub", self.node, tok.name, tok.type, tok.qos or "_",
                                      ctx.zid, ctx.next_eid()))

    # ------------------------------------------------------------------ hot path

    def _pump(self, channel: Any, fixed_key: str | None) -> None:
        """Drain one subscriber (``fixed_key``: the key of a one-topic subscriber, whose
        samples need no key lookup).

        Each sample becomes a packed Message record head and its payload as received, in a
        local batch; the batch goes to the sink (one lock) when it is full or when Zenoh has
        no further sample ready, so nothing waits in it while the pump sleeps. A channel
        belongs to one key, so to one pump, which numbers its messages.
        """
        routes, now, hand_off = self._routes, time.time_ns, self.sink.add_batch
        head = MESSAGE_HEAD.pack
        try_recv, recv = channel.try_recv, channel.recv
        batch: list[bytes] = []
        append = batch.append
        size = 0  # bytes of the batch's records, less 9 (opcode and length) each
        full = 2 * BATCH  # a head and a payload per message
        try:
            while True:
                sample = try_recv()
                if sample is None:  # caught up: hand over, then sleep until the next one
                    if batch:
                        hand_off(batch, size + 9 * (len(batch) // 2))
                        batch, size = [], 0
                        append = batch.append
                    sample = recv()  # raises ZError once the subscriber is undeclared
                log_time = now()
                key = fixed_key if fixed_key is not None else str(sample.key_expr)
                route = routes.get(key)
                if route is None or sample.encoding != route.encoding:
                    if route is None and key in routes:
                        continue  # excluded
                    route = self._route(key, str(sample.encoding))
                    if route is None:
                        continue
                data = sample.payload.to_bytes()
                if route.plain:  # no header stamp to read, nothing to transcode
                    ts = sample.timestamp
                    publish = ts.get_time_as_ntp64().as_nanos() if ts is not None else log_time
                else:
                    publish = route.stamp(data) if route.stamp is not None else 0
                    if not publish:
                        ts = sample.timestamp
                        publish = (ts.get_time_as_ntp64().as_nanos() if ts is not None
                                   else log_time)
                    if route.transcode is not None:  # only with bulk_json
                        converted = route.transcode(data)
                        if converted is None:
                            self.dropped += 1
                            continue
                        data = converted
                seq = route.seq = route.seq + 1
                length = 22 + len(data)
                size += length
                append(head(5, length, route.channel, seq & 0xFFFFFFFF, log_time, publish))
                append(data)
                if len(batch) >= full:
                    hand_off(batch, size + 9 * BATCH)
                    batch, size = [], 0
                    append = batch.append
        except zenoh.ZError:  # the channel closed under us at shutdown
            pass
        finally:
            if batch:
                hand_off(batch)

    def _route(self, key: str, enc: str) -> _Route | None:
        """The slow path for a key (or encoding) not seen before: make its channel."""
        with self._route_lock:
            route = self._by_encoding.get((key, enc))
            if route is not None:
                self._routes[key] = route
                return route
            topic = self.ctx.keys.topic_name(key)
            if not self.wanted(topic):
                self._routes[key] = None
                return None
            mime, type_name = split_encoding(enc)
            schema_encoding, schema = schema_for(type_name) if type_name else ("", b"")
            def publishers() -> list[Token]:
                return [t for t in self.ctx.graph.publishers(topic)
                        if not type_name or t.type == type_name]

            pubs = publishers()
            if not pubs:  # a sample came (a latched cache's, say) before its publisher's
                # token: it is on its way, and its QoS is the channel's (once a topic)
                self.ctx.graph.wait_for(lambda: bool(publishers()), TOKEN_WAIT)
                pubs = publishers()
            # a latched publisher's QoS when there is one: a replay must latch what it latched
            latched = [t for t in pubs if "+tl" in (t.qos or "")]
            qos = (latched or pubs)[0].qos if pubs else QOS_UNKNOWN
            metadata = {"zenoh_encoding": enc, "qos": qos}
            encoding = message_encoding(mime) if mime else ""
            transcode = (to_json(type_name) if self.options.bulk_json and mime == MSGPACK
                         and type_name else None)
            if transcode is not None:
                encoding, schema = "json", schema_of_type(lookup_type(type_name), False)
                metadata[TRANSCODED] = "msgpack"
            channel = self.sink.add_channel(topic, encoding, type_name, schema_encoding, schema,
                                            metadata)
            route = _Route(channel, enc, stamp_reader(type_name, mime == MSGPACK) if type_name
                           else None, transcode)
            self._routes[key] = self._by_encoding[(key, enc)] = route
        if self._on_channel is not None:
            self._on_channel(topic, type_name or mime)
        return route

    # ------------------------------------------------------------------ end

    @property
    def files(self) -> list[Path]:
        return list(self.sink.files)

    def counts(self) -> dict[str, int]:
        """Messages recorded so far per topic (those already written to disk)."""
        out: dict[str, int] = {}
        for cid, info in self.sink.channels.items():
            out[info.topic] = out.get(info.topic, 0) + self.sink.counts.get(cid, 0)
        return out

    def close(self) -> None:
        """Stop subscribing, write what is buffered and finish the bag."""
        with self._token_lock:
            if self._closed:
                return
            self._closed = True
            tokens = list(self._tokens.values())
        self._remove_listener()
        for sub in self._subs:
            sub.undeclare()
        for pump in self._pumps:
            pump.join(5.0)
        for tok in tokens:
            tok.undeclare()
        self.sink.close()
