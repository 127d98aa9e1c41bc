"""`Outbox`: one client's outgoing frames, with per-topic throttling and keep-newest queues.

Replies (service responses, action results, ...) are never dropped. Topic frames wait in one
queue per subscribed topic: while the client keeps up they all go out; once its socket backs
up (``congested``), each topic keeps only its newest ``queue_length`` frames (at least one),
so a slow client sees fresh data late rather than stale data forever, and publishers are
never held up. ``throttle_rate`` (ms) spaces a topic's frames; with a throttle, frames that
arrive in between wait in the same bounded queue, as rosbridge does.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

__all__ = ["BURST_LIMIT", "Outbox", "TopicQueue"]

BURST_LIMIT = 1000
"""Frames a topic may hold for a client that is not (yet) congested: a hard memory bound."""

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
    dropped: int = 0

    @property
    def keep(self) -> int:
        """How many frames survive congestion (or wait out a throttle)."""
        return max(1, self.queue_length)

    def due(self, now: float) -> float:
        """When the next frame may go (``now`` or later)."""
        return max(now, self.last_sent + self.throttle)

    def push(self, frame: Frame, congested: bool) -> None:
        self.frames.append(frame)
        limit = self.keep if (congested or self.throttle > 0) else BURST_LIMIT
        while len(self.frames) > limit:
            self.frames.popleft()
            self.dropped += 1


class Outbox:
    """Orders what one client is sent next.

    Args:
        clock: monotonic seconds (``time.monotonic`` or a fake in tests).
    """

    def __init__(self, clock: Callable[[], float]) -> None:
        self._clock = clock
        self.replies: deque[Out] = deque()
        self.topics: dict[str, TopicQueue] = {}

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
        """Frames to send now, and when to look again for throttled ones (None: on push)."""
        now = self._clock()
        out = list(self.replies)
        self.replies.clear()
        wake: float | None = None
        for q in self.topics.values():
            if not q.frames:
                continue
            if q.throttle <= 0:
                out.extend((f, q.fragment_size) for f in q.frames)
                q.frames.clear()
                q.last_sent = now
                continue
            due = q.due(now)
            if due <= now:
                out.append((q.frames.popleft(), q.fragment_size))
                q.last_sent = now
                if q.frames:
                    due = now + q.throttle
            if q.frames:
                wake = due if wake is None else min(wake, due)
        return out, wake
