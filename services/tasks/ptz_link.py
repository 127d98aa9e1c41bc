"""`PtzLink`: PTZ camera moves for the tasks service (``onvif_camera_move_action``), over the
chassis's ``ptz_camera/move`` (zenros_msgs/MovePtz) and followed on its ``ptz_camera/state``.

A move is one service call that starts it; the camera's state then says where it points and
whether it still moves. Only states stamped after the call's answer count. Cancelling stops
the camera where it is (``ptz_camera/move_speed`` with all zeros).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from zenros.errors import ZenrosError
from zenros.msgs.zenros_msgs import (
    MovePtz,
    MovePtzRequest,
    MovePtzSpeed,
    MovePtzSpeedRequest,
    PtzState,
)
from zenros.node import Node

from .robot import Outcome
from .state_watch import Silent, StateWatch

__all__ = ["PtzLink"]


class PtzLink:
    """One camera move per call; ``silence`` wall seconds without a state from the chassis
    end it in error (the chassis is gone)."""

    def __init__(self, node: Node, call_timeout: float = 5.0, silence: float = 10.0) -> None:
        self.node = node
        self.call_timeout = call_timeout
        self.silence = silence
        self._move: Any = None  # made at the first move: most robots' tasks never move one
        self._stop: Any = None
        self._sub: Any = None
        self._watch: StateWatch[PtzState] = StateWatch(silence)

    def move(self, x: float, y: float, zoom: float, progress: Callable[[float], None],
             cancelled: Callable[[], bool]) -> Outcome:
        """`Robot.ptz_move`."""
        what = f"PTZ camera to x={x:g}, y={y:g}, zoom={zoom:g}"
        if self._sub is None:  # the state is published only while someone listens
            self._move = self.node.create_client(MovePtz, "ptz_camera/move")
            self._stop = self.node.create_client(MovePtzSpeed, "ptz_camera/move_speed")
            self._sub = self.node.create_subscription(PtzState, "ptz_camera/state",
                                                      self._watch)
        try:
            res = self._move.call(MovePtzRequest(x=x, y=y, zoom=zoom),
                                  timeout=self.call_timeout)
        except ZenrosError as exc:
            return Outcome("error", f"{what}: {exc}")
        if not res.success:
            return Outcome("error", f"{what}: {res.message}")
        start = res.state
        since = start.header.stamp
        span = math.dist((start.x, start.y, start.zoom_ratio), (x, y, zoom))
        while True:
            try:
                state = self._watch.next_after(since, cancelled)
            except Silent:
                return Outcome("error", f"{what}: no ptz_camera/state from the chassis for "
                                        f"{self.silence:g} s")
            if state is None:
                self._halt()
                return Outcome("preempted")
            since = state.header.stamp
            left = math.dist((state.x, state.y, state.zoom_ratio), (x, y, zoom))
            progress(1.0 - left / span if span > 1e-9 else 1.0)
            if not state.moving:
                progress(1.0)
                return Outcome("complete", f"PTZ camera at x={state.x:.3f}, "
                                           f"y={state.y:.3f}, zoom={state.zoom_ratio:.3f}")

    def _halt(self) -> None:
        try:
            self._stop.call(MovePtzSpeedRequest(), timeout=self.call_timeout)
        except ZenrosError as exc:
            self.node.logger.warning("could not stop the PTZ camera: %s", exc)
