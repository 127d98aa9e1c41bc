"""`Player`: publishes a bag's messages on their original schedule, with pause and step."""

from __future__ import annotations

import queue
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import zenoh
from zenoh import ext as zext

from ..clock import Time
from ..context import Context
from ..msgs.rosgraph_msgs import Clock as ClockMsg
from ..node import Node
from ..qos import QoSProfile, Reliability
from .reader import BagMessage, bag_span, iter_messages
from .transcode import TRANSCODED, from_json

__all__ = ["PlayOptions", "Player"]

BATCH = 256  # messages per hand-over from the reader thread
READ_AHEAD = 32  # batches the reader thread may be ahead
SPIN = 0.0002  # s before a deadline where sleeping turns into spinning (kept short: under
#               load a process that spins loses its turn to ones that slept)
CLOCK_PERIOD = 0.01  # /clock at 100 Hz with --clock
MATCH_TIMEOUT = 2.0  # seconds to wait for Zenoh to route to known subscribers before playing

_MIMES = {"json": "application/json", "msgpack": "application/msgpack"}


@dataclass
class PlayOptions:
    """How to play: speed, looping, where to start, which topics, /clock."""

    rate: float = 1.0
    loop: bool = False
    start: float = 0.0
    topics: list[str] = field(default_factory=list)
    clock: bool = False


class _Out:
    """The Zenoh publisher of one recorded channel (latched topics get a cache again)."""

    def __init__(self, ctx: Context, node: str, topic: str, encoding: str, type_name: str,
                 qos: str) -> None:
        profile = QoSProfile.from_tag(qos)
        reliable, latched, depth = (profile.reliability == Reliability.RELIABLE,
                                    profile.latched, profile.depth)
        key = ctx.keys.topic(topic)
        enc = zenoh.Encoding(encoding)
        cc = zenoh.CongestionControl.BLOCK if reliable else zenoh.CongestionControl.DROP
        self.pub: Any
        if latched:
            self.pub = zext.declare_advanced_publisher(
                ctx.session, key, encoding=enc, congestion_control=cc,
                cache=zext.CacheConfig(max_samples=depth), publisher_detection=True)
        else:
            self.pub = ctx.session.declare_publisher(key, encoding=enc, congestion_control=cc)
        self.put = self.pub.put
        self.topic = topic
        self.latched = latched
        self.token = ctx.session.liveliness().declare_token(
            ctx.keys.entity_token("pub", node, topic, type_name or "unknown", qos, ctx.zid,
                                  ctx.next_eid()))

    def matching(self) -> bool:
        return self.latched or bool(self.pub.matching_status.matching)

    def close(self) -> None:
        self.token.undeclare()  # type: ignore[no-untyped-call]  # zenoh stub: unannotated
        self.pub.undeclare()


class Player:
    """Plays bag files into one context's network.

    Deadlines are absolute (first message's wall time plus the recorded offset divided by the
    rate), so waiting errors never accumulate; the last stretch before a deadline is spun
    rather than slept. A reader thread decodes chunks ahead of the schedule.
    """

    def __init__(self, ctx: Context, files: list[Path], options: PlayOptions | None = None,
                 node: Node | None = None) -> None:
        self.ctx = ctx
        self.files = files
        self.options = options or PlayOptions()
        if not self.options.rate > 0:
            raise ValueError(f"rate must be > 0, got {self.options.rate}")
        self.bag_start, self.bag_end, channels = bag_span(files)
        self.node = node
        self._node_name = node.fqn if node is not None else "/zenros_bag_player"
        self._outs: dict[tuple[str, str], _Out] = {}
        wanted = set(self.options.topics)
        for ch, schema in channels:
            if wanted and ch.topic not in wanted:
                continue
            self._out_for(ch.topic, ch.message_encoding, ch.metadata,
                          schema.name if schema else "")
        self._cond = threading.Condition()
        self._paused = False
        self._steps = 0
        self._stopped = False
        self._base = 0.0  # wall (perf_counter) time of bag time `_origin`
        self._origin = self.bag_start
        self._pause_at = 0.0
        self.position = 0  # log time of the last published message
        self.published = 0
        self.lateness: list[float] = []  # seconds each message went out after its deadline
        self._clock_pub = (node.create_publisher(ClockMsg, "/clock")
                           if self.options.clock and node is not None else None)
        self._playing = threading.Event()  # the schedule is set: bag_now() means something

    def _out_for(self, topic: str, message_encoding: str, metadata: dict[str, str],
                 type_name: str) -> _Out:
        encoding = metadata.get("zenoh_encoding") or (
            f"{_MIMES.get(message_encoding, message_encoding)}"
            + (f";{type_name}" if type_name else ""))
        key = (topic, encoding)
        out = self._outs.get(key)
        if out is None:
            out = self._outs[key] = _Out(self.ctx, self._node_name, topic, encoding, type_name,
                                         metadata.get("qos", "rel+10"))
        return out

    @property
    def duration(self) -> float:
        return (self.bag_end - self.bag_start) / 1e9

    # ------------------------------------------------------------------ controls

    @property
    def paused(self) -> bool:
        return self._paused

    def pause(self) -> None:
        with self._cond:
            if not self._paused:
                self._paused = True
                self._pause_at = time.perf_counter()
                self._cond.notify_all()

    def resume(self) -> None:
        with self._cond:
            if self._paused:
                self._paused = False
                self._base += time.perf_counter() - self._pause_at
                self._cond.notify_all()

    def toggle_pause(self) -> None:
        if self._paused:
            self.resume()
        else:
            self.pause()

    def step(self) -> None:
        """While paused: publish the next message now."""
        with self._cond:
            if self._paused:
                self._steps += 1
                self._cond.notify_all()

    def stop(self) -> None:
        with self._cond:
            self._stopped = True
            self._cond.notify_all()

    def bag_now(self) -> int:
        """The bag time that corresponds to now (frozen while paused)."""
        with self._cond:
            wall = self._pause_at if self._paused else time.perf_counter()
            return self._origin + int((wall - self._base) * self.options.rate * 1e9)

    # ------------------------------------------------------------------ playing

    def wait_for_matching(self, timeout: float = MATCH_TIMEOUT) -> None:
        """Give Zenoh time to route to the subscribers the graph already knows."""
        graph = self.ctx.graph
        pending = [o for o in self._outs.values() if graph.subscribers(o.topic)]
        deadline = time.monotonic() + timeout
        while pending and time.monotonic() < deadline:
            pending = [o for o in pending if not o.matching()]
            if pending:
                time.sleep(0.005)

    def _read(self, out: queue.Queue[list[BagMessage] | None], start: int,
              stop: threading.Event) -> None:
        batch: list[BagMessage] = []
        back: dict[int, Any] = {}  # channel id -> JSON-to-MessagePack (bulk_json bags)
        try:
            for m in iter_messages(self.files, self.options.topics or None, start):
                cid = m.channel.id
                if cid not in back:
                    back[cid] = (from_json(m.schema.name) if m.schema is not None
                                 and m.channel.metadata.get(TRANSCODED) == "msgpack" else None)
                if back[cid] is not None:
                    data = back[cid](m.data)
                    if data is None:
                        continue
                    m = replace(m, data=data)
                batch.append(m)
                if len(batch) >= BATCH:
                    out.put(batch)
                    batch = []
                if stop.is_set():
                    return
            if batch:
                out.put(batch)
        finally:
            out.put(None)

    def _wait(self, deadline_of: Callable[[], float]) -> bool:
        """Wait for a deadline (recomputed after a pause); False when stopped."""
        cond = self._cond
        while True:
            with cond:
                while self._paused and not self._steps and not self._stopped:
                    cond.wait(0.1)
                if self._stopped:
                    return False
                if self._paused:  # a step: go now, and continue the schedule from here
                    self._steps -= 1
                    return True
                deadline = deadline_of()
                left = deadline - time.perf_counter()
                if left > SPIN:
                    cond.wait(left - SPIN)
                    continue
            while time.perf_counter() < deadline:
                pass
            return True

    def play(self, on_progress: Callable[[Player], None] | None = None) -> int:
        """Play to the end (or `stop`); with ``loop``, again until stopped. Returns the number
        of messages published."""
        self.wait_for_matching()
        clock_stop = threading.Event()
        clock = None
        if self._clock_pub is not None:
            clock = threading.Thread(target=self._clock_loop, args=(clock_stop,), daemon=True,
                                     name="zenros-bag-clock")
            clock.start()
        try:
            while True:
                self._play_once(on_progress)
                if not self.options.loop or self._stopped:
                    break
        finally:
            clock_stop.set()
            if clock is not None:
                clock.join()
        return self.published

    def _play_once(self, on_progress: Callable[[Player], None] | None) -> None:
        start = self.bag_start + int(self.options.start * 1e9)
        batches: queue.Queue[list[BagMessage] | None] = queue.Queue(READ_AHEAD)
        stop_reading = threading.Event()
        reader = threading.Thread(target=self._read, args=(batches, start, stop_reading),
                                  daemon=True, name="zenros-bag-reader")
        reader.start()
        rate = self.options.rate
        first = batches.get()  # the clock starts once the first chunk is decoded
        with self._cond:
            self._origin = first[0].log_time if first else start
            self._base = time.perf_counter()
            if self._paused:
                self._pause_at = self._base
        self._playing.set()
        by_channel: dict[int, _Out | None] = {}
        now = time.perf_counter
        batch = first
        try:
            while batch is not None:
                for m in batch:
                    cid = m.channel.id
                    if cid in by_channel:
                        out = by_channel[cid]
                    else:
                        out = by_channel[cid] = self._outs.get((m.channel.topic,
                                                                self._encoding(m)))
                    if out is None:
                        continue

                    def deadline(t: int = m.log_time) -> float:
                        return self._base + (t - self._origin) / 1e9 / rate

                    was_paused = self._paused
                    if not self._wait(deadline):
                        return
                    sent = now()
                    out.put(m.data)
                    if was_paused and self._paused:  # stepped: the schedule restarts here
                        with self._cond:
                            self._origin, self._base = m.log_time, sent
                            self._pause_at = sent
                    else:
                        self.lateness.append(sent - deadline())
                    self.position = m.log_time
                    self.published += 1
                    if on_progress is not None:
                        on_progress(self)
                batch = batches.get()
        finally:
            stop_reading.set()
            while reader.is_alive():  # unblock a reader waiting on a full queue
                try:
                    batches.get_nowait()
                except queue.Empty:
                    reader.join(0.01)

    @staticmethod
    def _encoding(m: BagMessage) -> str:
        enc: str = m.channel.metadata.get("zenoh_encoding", "")
        if enc:
            return enc
        mime: str = _MIMES.get(m.channel.message_encoding, m.channel.message_encoding)
        return mime + (f";{m.schema.name}" if m.schema is not None and m.schema.name else "")

    def _clock_loop(self, stop: threading.Event) -> None:
        """/clock from the start of play (the first message's time, at once), every
        CLOCK_PERIOD, and once more at the end: a play shorter than a period still tells the
        clock's subscribers where the bag's time went."""
        assert self._clock_pub is not None
        while not self._playing.wait(CLOCK_PERIOD):
            if stop.is_set():
                return
        self._clock_pub.publish(ClockMsg(clock=Time.from_nanoseconds(self.bag_now())))
        while not stop.wait(CLOCK_PERIOD):
            self._clock_pub.publish(ClockMsg(clock=Time.from_nanoseconds(self.bag_now())))
        self._clock_pub.publish(ClockMsg(clock=Time.from_nanoseconds(self.bag_now())))

    def close(self) -> None:
        self.stop()
        for out in self._outs.values():
            out.close()
        self._outs.clear()
