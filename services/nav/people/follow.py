"""Person following: `follow_command`, the control law from a person's distance and bearing
to (v, ω); `Track`, the one person followed, kept from look to look; `Follow`, the nav
behaviour that ticks them on the leg detector's people (``legs``) or the UWB tag (``uwb``).

The robot keeps ``distance`` m from its person: it drives at up to ``max_linear`` m/s, the
speed the person walks away at (their track's velocity) plus some in proportion to the
distance beyond ``distance`` (never backwards: closer, it stops), slower the more
the person is off its heading, and turns to face them at up to ``max_angular`` rad/s. It
stops for anything in front of its body (`blocked`). A person not seen for ``lost_after`` s
is lost: the robot stops and says so, and takes the nearest person it sees next. A leg pair
on the static map's walls (a door jamb's two edges look like legs) is nobody (`off_walls`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from zenros.se2 import Pose2, wrap_angle

from ..motion.behavior import Behavior, Sense
from .legs import detect_people

__all__ = ["WALL_REACH", "Follow", "FollowParams", "Sighting", "Track", "Walls", "blocked",
           "follow_command", "off_walls"]


@dataclass(frozen=True)
class FollowParams:
    distance: float = 1.0  # m kept from the person
    max_linear: float = 0.5  # m/s
    max_angular: float = 1.2  # rad/s
    k_linear: float = 2.0  # (m/s) per m beyond ``distance``
    k_angular: float = 2.0  # (rad/s) per rad of bearing
    lost_after: float = 3.0  # s without a sighting
    acquire_range: float = 2.5  # m: a person farther is not taken up
    gate: float = 0.6  # m a person may move between two looks and stay the same one
    body_radius: float = 0.2  # m, for the stop on anything ahead
    margin: float = 0.1  # m kept clear in front of the body


def follow_command(distance: float, bearing: float, p: FollowParams,
                   away: float = 0.0) -> tuple[float, float]:
    """(v, ω) towards a person ``distance`` m away at ``bearing`` rad (left positive), who
    walks ``away`` m/s from the robot (fed forward, so a walking person is followed at
    ``distance``, not behind it by their speed over ``k_linear``)."""
    w = max(-p.max_angular, min(p.max_angular, p.k_angular * bearing))
    beyond = distance - p.distance
    if beyond <= 0:
        return 0.0, w
    facing = max(0.0, 1.0 - abs(bearing) / (math.pi / 2))
    return min(p.max_linear, max(0.0, away) + p.k_linear * beyond) * facing, w


def blocked(obstacles: np.ndarray, v: float, p: FollowParams) -> bool:
    """Whether a point of ``obstacles`` (``base_link``) lies in the body's corridor for the
    next half second at ``v`` (and ``margin``)."""
    if v <= 0 or not len(obstacles):
        return False
    reach = p.body_radius + p.margin + 0.5 * v
    x, y = obstacles[:, 0], obstacles[:, 1]
    return bool(np.any((x > 0) & (x < reach) & (np.abs(y) < p.body_radius + 0.02)))


@dataclass(frozen=True)
class Sighting:
    """Where the person is now, in ``base_link``: ``distance`` m at ``bearing`` rad."""

    distance: float
    bearing: float


class Track:
    """The person followed, in the odometry/map frame (so the robot's own motion does not
    move them), by position and the time last seen."""

    def __init__(self, p: FollowParams) -> None:
        self.p = p
        self.xy: tuple[float, float] | None = None
        self.seen_at = -math.inf
        self.velocity = (0.0, 0.0)  # m/s in the world, smoothed over the fixes
        self._fix: tuple[float, float, float] | None = None  # (time, x, y) of the last fix

    def moved(self, now: float) -> None:
        """Take the track's place at ``now`` as a new fix (a new scan or UWB reading) into
        its velocity; a fix after a loss starts it again."""
        if self.xy is None:
            self._fix, self.velocity = None, (0.0, 0.0)
            return
        x, y = self.xy
        if self._fix is not None and now - self._fix[0] > self.p.lost_after:
            self._fix, self.velocity = None, (0.0, 0.0)
        if self._fix is None:
            self._fix = (now, x, y)
            return
        dt = now - self._fix[0]
        if dt < 0.05:
            return
        vx, vy = (x - self._fix[1]) / dt, (y - self._fix[2]) / dt
        if math.hypot(vx, vy) <= 3.0:  # faster is a jump to someone else, not walking
            a = 0.3
            self.velocity = (self.velocity[0] + a * (vx - self.velocity[0]),
                             self.velocity[1] + a * (vy - self.velocity[1]))
        self._fix = (now, x, y)

    def away(self, pose: Pose2) -> float:
        """How fast the person walks away from the robot at ``pose`` (m/s; negative: nearer)."""
        if self.xy is None:
            return 0.0
        dx, dy = self.xy[0] - pose.x, self.xy[1] - pose.y
        d = math.hypot(dx, dy)
        return 0.0 if d < 1e-6 else (self.velocity[0] * dx + self.velocity[1] * dy) / d

    def update(self, pose: Pose2, candidates: np.ndarray, now: float, acquire: bool) -> bool:
        """Take the candidate (``base_link`` points, nearest first) that is the person:
        within ``gate`` of the track, or (no track, ``acquire``) the nearest within
        ``acquire_range``. Returns whether one was taken."""
        if self.xy is not None and now - self.seen_at > self.p.lost_after:
            self.xy = None
        if not len(candidates):
            return False
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        wx = pose.x + c * candidates[:, 0] - s * candidates[:, 1]
        wy = pose.y + s * candidates[:, 0] + c * candidates[:, 1]
        if self.xy is None:
            if not acquire:
                return False
            near = np.hypot(candidates[:, 0], candidates[:, 1])
            i = int(np.argmin(near))
            if near[i] > self.p.acquire_range:
                return False
            self.xy = (float(wx[i]), float(wy[i]))
        else:
            d = np.hypot(wx - self.xy[0], wy - self.xy[1])
            i = int(np.argmin(d))
            if d[i] > self.p.gate:
                return False
            self.xy = (float(wx[i]), float(wy[i]))
        self.seen_at = now
        return True

    def smooth(self, x: float, y: float, now: float, alpha: float = 0.5) -> None:
        """Move the track ``alpha`` of the way to (x, y) (there, when it has none): the tag
        is one person, so no gate; its noise is averaged out."""
        if self.xy is None or now - self.seen_at > self.p.lost_after:
            self.xy = (x, y)
        else:
            self.xy = (self.xy[0] + alpha * (x - self.xy[0]), self.xy[1] + alpha * (y - self.xy[1]))
        self.seen_at = now

    def seen_from(self, pose: Pose2) -> Sighting | None:
        if self.xy is None:
            return None
        dx, dy = self.xy[0] - pose.x, self.xy[1] - pose.y
        return Sighting(math.hypot(dx, dy), wrap_angle(math.atan2(dy, dx) - pose.theta))


Uwb = Callable[[], tuple[float, float, float] | None]
"""The latest UWB reading: (range m, bearing rad, when in node seconds), or None."""
Walls = Callable[[np.ndarray], np.ndarray]
"""Whether each (N, 2) map point is on the static map's walls (a door jamb, not a person)."""
WALL_REACH = 0.15  # m from a wall cell within which a leg pair is the wall's


def off_walls(people: np.ndarray, pose: Pose2 | None, walls: Walls | None) -> np.ndarray:
    """``people`` (``base_link``) less those the map has as walls (all of them without a
    pose or a map)."""
    if walls is None or pose is None or not len(people):
        return people
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    world = np.column_stack([pose.x + c * people[:, 0] - s * people[:, 1],
                             pose.y + s * people[:, 0] + c * people[:, 1]])
    return people[~walls(world)]


class Follow(Behavior):
    """Follow a person on the leg detector (``mode`` ``legs``) or the UWB tag (``uwb``);
    runs until halted. ``state``: ``searching``, ``following``, ``lost``."""

    name = "follow"

    def __init__(self, mode: str, p: FollowParams, uwb: Uwb | None = None,
                 walls: Walls | None = None) -> None:
        super().__init__()
        self.walls = walls
        if mode not in ("legs", "uwb"):
            raise ValueError(f"follow mode must be legs or uwb, got {mode!r}")
        self.mode, self.p, self.uwb = mode, p, uwb
        self.track = Track(p)
        self.state = "searching"
        self.message = "looking for a person" if mode == "legs" else "waiting for the UWB tag"
        self.sighting: Sighting | None = None
        self._points: np.ndarray | None = None
        self._people = np.zeros((0, 2))
        self._fresh = False  # a new scan or UWB reading since the last velocity fix
        self._reading_at = -math.inf

    def _candidates(self, sense: Sense) -> np.ndarray:
        """The leg detector's people and single legs (``base_link``), from the latest scan."""
        if sense.obstacles is not self._points:
            self._points = sense.obstacles
            self._people = off_walls(
                detect_people(sense.obstacles, singles=self.track.xy is not None),
                sense.pose, self.walls)
            self._fresh = True
        return self._people

    def _look(self, sense: Sense, pose: Pose2) -> Sighting | None:
        if self.mode == "uwb":
            reading = self.uwb() if self.uwb is not None else None
            if reading is None or sense.now - reading[2] > self.p.lost_after:
                return None
            r, b, when = reading
            if when != self._reading_at:
                self._reading_at, self._fresh = when, True
                self.track.smooth(pose.x + r * math.cos(pose.theta + b),
                                  pose.y + r * math.sin(pose.theta + b), when)
            return self.track.seen_from(pose)
        if self.track.update(pose, self._candidates(sense), sense.now, acquire=True):
            return self.track.seen_from(pose)
        if sense.now - self.track.seen_at <= self.p.lost_after:
            return self.track.seen_from(pose)  # hidden a moment: where last seen
        return None

    def tick(self, sense: Sense) -> tuple[float, float]:
        pose = sense.pose or Pose2()
        self.sighting = seen = self._look(sense, pose)
        if self._fresh:
            self._fresh = False
            self.track.moved(sense.now)
        if seen is None:
            if self.state == "following":
                self.state = "lost"
                self.message = f"lost the person for {self.p.lost_after:g} s: stopped"
            return 0.0, 0.0
        self.state, self.message = "following", ""
        v, w = follow_command(seen.distance, seen.bearing, self.p, self.track.away(pose))
        if blocked(sense.obstacles, v, self.p):
            self.message = "something in front of the robot: stopped"
            v = 0.0
        return v, w
