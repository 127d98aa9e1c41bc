"""`FollowControl`: ``follow/set`` and ``follow/status`` over nav's motion: person following
starts as the active behaviour (`Follow`), one mode at a time, never over a running goal.

Enabling a mode while a navigation goal (or docking, a local move) runs is refused with the
goal's name: a user who asked the robot to go somewhere did not ask it to stop going there.
Enabling one mode replaces the other; a goal sent while following takes over (following
stops, its status says so).
"""

from __future__ import annotations

import threading
from collections.abc import Callable

from zenros.msgs.zenros_msgs import (
    FollowStatus,
    GetFollowStatusResponse,
    SetFollowRequest,
    SetFollowResponse,
)

from ..motion.active import Motion
from .follow import Follow, FollowParams, Uwb, Walls

__all__ = ["FollowControl"]


class FollowControl:
    """Starts and stops `Follow` on ``motion``; ``active()`` says whether nav takes goals."""

    def __init__(self, motion: Motion, params: FollowParams, uwb: Uwb,
                 active: Callable[[], str] | None = None, walls: Walls | None = None) -> None:
        self.motion, self.params, self.uwb, self.walls = motion, params, uwb, walls
        self.active = active
        self._lock = threading.Lock()
        self._last: Follow | None = None

    def status(self) -> FollowStatus:
        f = self._last
        if f is None:
            return FollowStatus()
        running = self.motion.active is f
        if not running:  # turned off, or a goal took over: the reason
            return FollowStatus(mode=f.mode, state="off", message=f.error_msg)
        seen = f.sighting
        return FollowStatus(enabled=True, mode=f.mode, following=f.state == "following",
                            state=f.state, distance=round(seen.distance, 3) if seen else 0.0,
                            bearing=round(seen.bearing, 3) if seen else 0.0, message=f.message)

    def handle_status(self, _req: object) -> GetFollowStatusResponse:
        return GetFollowStatusResponse(status=self.status())

    def handle_set(self, req: SetFollowRequest) -> SetFollowResponse:
        with self._lock:
            why = self._enable(req.mode) if req.enable else self._disable(req.mode)
        return SetFollowResponse(success=not why, message=why or "ok", status=self.status())

    def _enable(self, mode: str) -> str:
        if mode not in ("legs", "uwb"):
            return f"follow mode must be legs or uwb, got {mode!r}"
        why = self.active() if self.active is not None else ""
        if why:
            return why
        cur = self.motion.active
        if isinstance(cur, Follow) and cur.mode == mode:
            return ""
        if cur is not None and not isinstance(cur, Follow):
            return (f"a {cur.name} goal is running: cancel it before following a person "
                    "(tracking_mode and uwb_track never take over a goal)")
        follow = Follow(mode, self.params, self.uwb, self.walls)
        self._last = follow
        self.motion.start(follow, reason=f"following in mode {mode} instead")
        return ""

    def _disable(self, mode: str) -> str:
        cur = self.motion.active
        if isinstance(cur, Follow) and cur.mode == mode:
            self.motion.halt(cur, reason=f"following ({mode}) turned off")
        return ""
