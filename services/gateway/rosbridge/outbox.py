"""`Outbox`: one client's outgoing scheduler: per-topic throttling and keep-newest queues,
and a lane of its own for large frames so they never hold up the small ones.

Replies (service responses, action results, ...) are never dropped. Topic frames wait in one
queue per subscribed topic: while the client keeps up they all go out; once its socket backs
up (``congested``), each topic keeps only its newest ``queue_length`` frames (at least one),
so a slow client sees fresh data late rather than stale data forever, and publishers are
never held up. ``throttle_rate`` (ms) spaces a topic's frames; with a throttle, frames that
arrive in between wait in the same bounded queue, as rosbridge does. A queue also holds at
most `QUEUE_BYTES` (beyond its newest ``queue_length`` frames).

Frames larger than `BIG` (a map, a cloud) are not sent with the others (`take`): the writer
takes them one piece at a time (`take_bulk`), after every small frame that is waiting, and
waits for the socket to drain after each piece. A piece is the whole frame, or, for a
client that subscribed with ``fragment_size``, one ``fragment`` frame: small frames then go
out between the fragments of a large message. Topics with large frames take turns.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field

__all__ = ["BIG", "BURST_LIMIT", "QUEUE_BYTES", "Outbox", "TopicQueue", "Turnstile"]

BURST_LIMIT = 1000
"""Frames a topic may hold for a client that is not (yet) congested: a hard memory bound."""
BIG = 64 * 1024
"""Frames longer than this (bytes) go out through the large-frame lane (`Outbox.take_bulk`)."""
QUEUE_BYTES = 32 * 1024 * 1024
"""Bytes a topic's queue may hold beyond its newest ``queue_length`` frames."""
GAP = 0.002
"""A whole large frame goes out within this many seconds after a small topic frame went out:
into the gap before the next one of a periodic stream (`Outbox.take_bulk`)."""
QUIET = 0.1
"""... or when no small topic frame went out for this long (no stream to leave a gap in)."""
HOLD = 0.25
"""... or when it has waited this long for a gap (and its turn)."""
READ_RATE = 200e6
"""Bytes a second a client is taken to read a whole large frame at (`Turnstile`): a Python
client reads the 5 MB of a map's JSON in about 10-20 ms on a small machine."""


class Turnstile:
    """Shared by the clients of one server: whole large frames start one at a time, each once
    the last is read (at `READ_RATE`). Five clients reading 5 MB each at once on a small
    machine all finish late, past the next small frame; one at a time, each reads its copy
    in the gap after a small frame."""

    def __init__(self) -> None:
        self._free_at = float("-inf")

    def free(self, now: float) -> bool:
        return now >= self._free_at

    def take(self, now: float, size: int) -> None:
        self._free_at = now + size / READ_RATE


Frame = bytes
Out = tuple[bytes, int]
"""A frame to send and the fragment size to split it with (0: whole)."""


@dataclass
class TopicQueue:
    """The frames of one subscribed topic waiting for one client."""

    throttle: float = 0.0  # seconds between frames
    queue_length: int = 0
    fragment_size: int = 0  # 0: never fragment
    frames: deque[Frame] = field(default_factory=deque)
    last_sent: float = float("-inf")
    held_since: float | None = None  # when its large head frame began waiting for a gap
    dropped: int = 0
    size: int = 0  # bytes in frames

    @property
    def keep(self) -> int:
        """How many frames survive congestion (or wait out a throttle)."""
        return max(1, self.queue_length)

    def due(self, now: float) -> float:
        """When the next frame may go (``now`` or later)."""
        return max(now, self.last_sent + self.throttle)

    def push(self, frame: Frame, congested: bool) -> None:
        self.frames.append(frame)
        self.size += len(frame)
        limit = self.keep if (congested or self.throttle > 0) else BURST_LIMIT
        while len(self.frames) > limit or (self.size > QUEUE_BYTES and
                                           len(self.frames) > self.keep):
            self.size -= len(self.frames.popleft())
            self.dropped += 1

    def pop(self, now: float) -> Frame:
        frame = self.frames.popleft()
        self.size -= len(frame)
        self.last_sent = now
        self.held_since = None
        return frame

    @property
    def big_next(self) -> bool:
        """Whether the next frame goes through the large-frame lane."""
        return bool(self.frames) and len(self.frames[0]) > BIG


class Outbox:
    """Orders what one client is sent next.

    Args:
        clock: monotonic seconds (``time.monotonic`` or a fake in tests).
    """

    def __init__(self, clock: Callable[[], float], turnstile: Turnstile | None = None) -> None:
        self._clock = clock
        self._turnstile = turnstile or Turnstile()
        self.replies: deque[Out] = deque()
        self.topics: dict[str, TopicQueue] = {}
        self._pieces: Iterator[bytes] = iter(())  # the rest of the large frame being sent
        self._turn = 0  # the topic whose large frame goes next (round robin)
        self._last_small = float("-inf")  # when `take` last gave out a small topic frame
        self.bulk_wake: float | None = None  # when a large frame held for a gap must go

    def configure(self, topic: str, throttle_ms: float, queue_length: int,
                  fragment_size: int = 0) -> None:
        """Set (or change) a topic's throttle, queue length and fragment size; keeps waiting
        frames."""
        q = self.topics.get(topic)
        if q is None:
            q = self.topics[topic] = TopicQueue()
        q.throttle = max(0.0, throttle_ms) / 1000.0
        q.queue_length = max(0, queue_length)
        q.fragment_size = max(0, fragment_size)

    def remove(self, topic: str) -> None:
        self.topics.pop(topic, None)

    def reply(self, frame: Frame, fragment_size: int = 0) -> None:
        """Queue a frame that must arrive (never dropped)."""
        self.replies.append((frame, fragment_size))

    def publish(self, topic: str, frame: Frame, congested: bool) -> bool:
        """Queue a topic frame; False if the client is not subscribed to ``topic``."""
        q = self.topics.get(topic)
        if q is None:
            return False
        q.push(frame, congested)
        return True

    @property
    def dropped(self) -> int:
        return sum(q.dropped for q in self.topics.values())

    def take(self) -> tuple[list[Out], float | None]:
        """Frames to send now, and when to look again for throttled ones (None: on push).

        A topic's large frames stay queued (in order with its small ones) for `take_bulk`.
        """
        now = self._clock()
        out = list(self.replies)
        self.replies.clear()
        replies = len(out)
        wake: float | None = None
        for q in self.topics.values():
            if not q.frames:
                continue
            if q.throttle <= 0:
                while q.frames and not q.big_next:
                    out.append((q.pop(now), q.fragment_size))
                continue
            due = q.due(now)
            if due <= now and not q.big_next:
                out.append((q.pop(now), q.fragment_size))
                due = now + q.throttle
            if q.frames:
                wake = due if wake is None else min(wake, due)
        if len(out) > replies:
            self._last_small = now
        return out, wake

    def take_bulk(self, split: Callable[[bytes, int], Iterable[bytes]]) -> bytes | None:
        """The next piece of a large frame, or None: the rest of the frame being sent, else
        the first piece (``split(frame, fragment_size)``, made as they are taken) of the next
        topic's due one.

        A frame that goes whole (no ``fragment_size``) holds up every small frame behind it
        on the WebSocket until the client has read it all, so it waits for a gap: it goes
        within `GAP` of a small topic frame (a periodic stream's next one is then as far
        off as it can be), when no small frame went out for `QUIET`, or after `HOLD`;
        meanwhile `bulk_wake` says when it must go.
        """
        piece = next(self._pieces, None)
        if piece is not None:
            return piece
        now = self._clock()
        self.bulk_wake = None
        queues = list(self.topics.values())
        for i in range(len(queues)):
            q = queues[(self._turn + i) % len(queues)]
            if not q.big_next or q.due(now) > now:
                continue
            if not q.fragment_size and not self._gap(q, now):
                assert q.held_since is not None
                wake = q.held_since + HOLD
                self.bulk_wake = wake if self.bulk_wake is None else min(self.bulk_wake, wake)
                continue
            frame = q.pop(now)
            if not q.fragment_size:
                self._turnstile.take(now, len(frame))
            self._turn = (self._turn + i + 1) % len(queues)
            self._pieces = iter(split(frame, q.fragment_size))
            return next(self._pieces, None)
        return None

    def _gap(self, q: TopicQueue, now: float) -> bool:
        """Whether ``q``'s whole large frame may go now (see `take_bulk`)."""
        if q.held_since is None:
            q.held_since = now
        if now - q.held_since >= HOLD:
            return True
        since = now - self._last_small
        return (since <= GAP or since >= QUIET) and self._turnstile.free(now)
