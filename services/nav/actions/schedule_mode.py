"""ScheduleMode: nav's schedule mode, its switch and its talk with the schedule manager.

The node serves `handle_set` (``set_schedule_mode``) and `handle_get`
(``get_schedule_mode``), and while the mode is on it sends what `next_call` gives to the
schedule server's ``request_route`` or ``release_route`` and hands the answer to
`on_answer`. Leaving the mode (or a navigation ending) releases the robot's reservations.
docs/fleet.md, "Traffic schedule".
"""

from __future__ import annotations

import re
from collections.abc import Callable

from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.traffic import (
    GetScheduleModeRequest,
    GetScheduleModeResponse,
    ReleaseRouteRequest,
    RequestRouteRequest,
    RequestRouteResponse,
    RoutePose,
    ScheduleModeStatus,
    SetScheduleModeRequest,
    SetScheduleModeResponse,
)

from ..motion.traffic import Reply, ScheduleGate

__all__ = ["ScheduleMode"]

Call = RequestRouteRequest | ReleaseRouteRequest


class ScheduleMode:
    """``robot`` names the robot to the manager (its namespace); ``map_name`` gives the map
    in use; ``now`` the node clock's seconds; ``on_switch(on)`` runs when the mode changes."""

    def __init__(self, gate: ScheduleGate, robot: str, server_id: str, lease: float,
                 map_name: Callable[[], str], now: Callable[[], float],
                 on_switch: Callable[[bool], None] = lambda on: None) -> None:
        self.gate, self.robot, self.server_id, self.lease = gate, robot, server_id, lease
        self._map_name, self._now, self._on_switch = map_name, now, on_switch
        self.last_error = ""

    @property
    def enabled(self) -> bool:
        return self.gate.enabled

    def set(self, on: bool, server_id: str = "") -> None:
        if server_id and server_id != self.server_id:
            self.gate.set_enabled(False)  # released on the old server first
            self.server_id = server_id
        if on != self.gate.enabled:
            self.gate.set_enabled(on)
            self._on_switch(on)

    def status(self) -> ScheduleModeStatus:
        state, wait_for, segments = self.gate.status()
        return ScheduleModeStatus(enabled=self.gate.enabled, server_id=self.server_id,
                                  state=state, wait_for=wait_for, segments=list(segments))

    # ------------------------------------------------------------------ services

    def handle_set(self, req: SetScheduleModeRequest) -> SetScheduleModeResponse:
        if req.server_id and not re.fullmatch(r"[A-Za-z0-9_]{1,64}", req.server_id):
            return SetScheduleModeResponse(code=ResultCode.INVALID, message=(
                f"bad schedule server id {req.server_id!r} (letters, digits, _)"),
                status=self.status())
        self.set(req.enable, req.server_id)
        word = "in" if req.enable else "out of"
        return SetScheduleModeResponse(message=(
            f"{word} schedule mode (schedule server {self.server_id!r})"), status=self.status())

    def handle_get(self, req: GetScheduleModeRequest) -> GetScheduleModeResponse:
        return GetScheduleModeResponse(status=self.status())

    # ------------------------------------------------------------------ the manager

    def next_call(self) -> Call | None:
        """What to send to the manager now (None: nothing)."""
        ask = self.gate.take()
        if ask is None:
            return None
        if ask.release:
            return ReleaseRouteRequest(robot=self.robot)
        return RequestRouteRequest(
            robot=self.robot, map_name=self._map_name(), lease=self.lease,
            route=[RoutePose(x=x, y=y, t=t) for x, y, t in ask.route])

    def on_answer(self, res: RequestRouteResponse) -> None:
        if res.code != ResultCode.OK:
            self.last_error = res.message  # no grant: the gate keeps the robot stopped
            return
        self.last_error = ""
        stop = None if res.granted else (res.stop.x, res.stop.y)
        aside = ((res.yield_to.x, res.yield_to.y)
                 if res.step_aside or (res.must_yield and res.yield_to != RoutePose()) else None)
        self.gate.on_reply(Reply(self._now(), res.granted, stop, res.wait_for, res.must_yield,
                                 tuple(res.segments), aside))
