"""The traffic gate: how far along its path a navigating robot may drive, in schedule mode.

`Navigate` asks its gate every tick (`TrafficGate.limit`) and drives no further along the
path than the arc length it answers (None: no limit); it tells the gate when it ends. The
`ScheduleGate` is the schedule manager's (docs/fleet.md, "Traffic schedule"): it turns the
path into a route (a point every ``spacing`` metres, timed at ``speed``), leaves it in an
outbox that the node sends to the manager (`take`), at once for a new path and every
``renew_period`` seconds while driving, which also renews the lease; the answer (`on_reply`)
says where to stop. No answer for ``lease`` seconds: the robot stops. Off (``enabled``
false), it answers None and sends nothing: the robot drives as without it. An answer with a
place to wait at off the route (a robot coming out of a narrow segment will pass where this
one would stop, or a deadlock's yield) is `aside`: `Navigate` drives there and waits, asking
with its path as before, and goes back to its path once the answer no longer says so.
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass
from typing import Protocol

import numpy as np
from zenros.se2 import Pose2

__all__ = ["Ask", "Reply", "ScheduleGate", "TrafficGate"]


class TrafficGate(Protocol):
    def limit(self, now: float, pose: Pose2, path: np.ndarray, s: float) -> float | None:
        """The furthest arc length along ``path`` the robot (at ``pose``, ``s`` along it)
        may reach now; None: anywhere."""
        ...

    def end(self) -> None:
        """The behaviour ended: give back what it held."""
        ...

    def aside(self, now: float) -> tuple[float, float] | None:
        """A place off the path to wait at now (None: wait on the path, if at all)."""
        ...


@dataclass(frozen=True)
class Ask:
    """What the node sends: a route (``(x, y, t)`` points) or, with ``release``, an end."""

    route: tuple[tuple[float, float, float], ...] = ()
    release: bool = False


@dataclass(frozen=True)
class Reply:
    """The manager's answer, as the gate needs it (``at``: when it came, node clock)."""

    at: float
    granted: bool
    stop: tuple[float, float] | None = None
    wait_for: str = ""
    must_yield: bool = False
    segments: tuple[int, ...] = ()
    aside: tuple[float, float] | None = None  # wait there, off the route


class ScheduleGate:
    """The schedule manager's gate; thread-safe (ticks on the control thread, replies on
    Zenoh's)."""

    def __init__(self, *, speed: float = 0.5, renew_period: float = 0.5, lease: float = 3.0,
                 spacing: float = 0.25) -> None:
        self.speed, self.renew_period, self.lease, self.spacing = (
            speed, renew_period, lease, spacing)
        self.enabled = False
        self.state = "off"
        self._lock = threading.Lock()
        self._outbox: Ask | None = None
        self._reply: Reply | None = None
        self._path: np.ndarray | None = None
        self._cum = np.zeros(0)
        self._sent_at = -math.inf

    # ------------------------------------------------------------------ the switch

    def set_enabled(self, on: bool) -> None:
        """Schedule mode on or off; off gives back what the robot held."""
        with self._lock:
            was, self.enabled = self.enabled, on
            self.state = "idle" if on else "off"
            if was and not on:
                self._end_locked()

    # ------------------------------------------------------------------ TrafficGate

    def limit(self, now: float, pose: Pose2, path: np.ndarray, s: float) -> float | None:
        if not self.enabled:
            return None
        with self._lock:
            if path is not self._path:
                self._path = path
                seg = np.hypot(*np.diff(path, axis=0).T) if len(path) > 1 else np.zeros(0)
                self._cum = np.concatenate(([0.0], np.cumsum(seg)))
                self._sent_at = -math.inf
            if now - self._sent_at >= self.renew_period:
                self._outbox = Ask(self._route(pose, path, s))
                self._sent_at = now
            reply = self._reply
            if reply is None or now - reply.at > self.lease:
                self.state = "no_answer"
                return s
            if reply.must_yield:
                self.state = "yielding"
                return s
            if reply.granted or reply.stop is None:
                self.state = "driving"
                return None
            cap = self._project(reply.stop, s)
            self.state = "waiting" if cap - s < 0.1 else "driving"
            return cap

    def aside(self, now: float) -> tuple[float, float] | None:
        """Where the last (fresh) answer says to wait off the route (None: on it)."""
        with self._lock:
            reply = self._reply
            if (not self.enabled or reply is None or now - reply.at > self.lease
                    or reply.granted):
                return None
            if reply.aside is not None:
                self.state = "yielding" if reply.must_yield else "waiting"
            return reply.aside

    def end(self) -> None:
        with self._lock:
            self._end_locked()
            if self.enabled:
                self.state = "idle"

    def _end_locked(self) -> None:
        self._outbox = Ask(release=True)
        self._reply, self._path, self._sent_at = None, None, -math.inf

    # ------------------------------------------------------------------ the node's side

    def take(self) -> Ask | None:
        """The next thing to send (None: nothing)."""
        with self._lock:
            ask, self._outbox = self._outbox, None
            return ask

    def on_reply(self, reply: Reply) -> None:
        """The manager's answer to the last route sent (dropped once the behaviour ended)."""
        with self._lock:
            if self._path is not None:
                self._reply = reply

    def status(self) -> tuple[str, str, tuple[int, ...]]:
        """(state, whom it waits for, the segments it holds)."""
        with self._lock:
            r = self._reply
            return self.state, (r.wait_for if r else ""), (r.segments if r else ())

    # ------------------------------------------------------------------ geometry

    def _route(self, pose: Pose2, path: np.ndarray, s: float
               ) -> tuple[tuple[float, float, float], ...]:
        """The path from ``s`` on, a point every ``spacing`` metres, timed at ``speed``;
        its first point is the robot's pose."""
        cum = self._cum
        if len(path) < 2:
            return ((pose.x, pose.y, 0.0),)
        targets = np.arange(s + self.spacing, cum[-1], self.spacing)
        xs = np.interp(targets, cum, path[:, 0])
        ys = np.interp(targets, cum, path[:, 1])
        out = [(pose.x, pose.y, 0.0)]
        out += [(float(x), float(y), float((d - s) / self.speed))
                for x, y, d in zip(xs, ys, targets, strict=True)]
        out.append((float(path[-1, 0]), float(path[-1, 1]), float((cum[-1] - s) / self.speed)))
        return tuple(out)

    def _project(self, stop: tuple[float, float], s: float) -> float:
        """The arc length of the path's point nearest ``stop``, from 0.5 m behind ``s`` on."""
        path, cum = self._path, self._cum
        assert path is not None
        ahead = np.flatnonzero(cum >= s - 0.5)
        if len(ahead) == 0:
            return s
        d = np.hypot(path[ahead, 0] - stop[0], path[ahead, 1] - stop[1])
        return float(cum[ahead[int(np.argmin(d))]])
