"""Schedule mode's wiring on the nav node: the ``set_schedule_mode`` and
``get_schedule_mode`` services, the schedule server's clients, and the timer that sends the
gate's routes while the mode is on (docs/fleet.md, "Traffic schedule")."""

from __future__ import annotations

from typing import Any

from zenros.errors import ZenrosError
from zenros.msgs.zenros_msgs.schedule import schedule_service
from zenros.msgs.zenros_msgs.traffic import (
    GetScheduleMode,
    ReleaseRoute,
    ReleaseRouteRequest,
    RequestRoute,
    SetScheduleMode,
)

from .actions.schedule_mode import ScheduleMode
from .motion.traffic import ScheduleGate
from .params import NavParameters

__all__ = ["ScheduleLink"]

SEND_PERIOD = 0.1
"""Seconds of the node's clock between looks at the gate's outbox while the mode is on."""


class ScheduleLink:
    """Built by the node in ``setup``; ``mode`` is its `ScheduleMode`."""

    def __init__(self, node: Any, p: NavParameters) -> None:
        self.node = node
        gate = ScheduleGate(speed=p.max_linear_vel, lease=p.schedule_lease)
        robot = node.namespace.strip("/") or node.fqn
        self.mode = ScheduleMode(gate, robot, p.schedule_server, p.schedule_lease,
                                 lambda: node.core.maps.current,
                                 lambda: node.now().nanoseconds * 1e-9, self._on_switch)
        self._clients: dict[str, tuple[Any, Any]] = {}
        node.core.traffic = gate
        node.create_service(SetScheduleMode, "set_schedule_mode", self.mode.handle_set)
        node.create_service(GetScheduleMode, "get_schedule_mode", self.mode.handle_get)
        self.timer = node.create_timer(SEND_PERIOD, self.on_timer)
        self.timer.cancel()  # no wake-ups while the mode is off
        self._failures = 0
        if p.schedule_mode:
            self.mode.set(True)

    def _on_switch(self, on: bool) -> None:
        self.node.logger.info("schedule mode %s (schedule server %r)", "on" if on else "off",
                              self.mode.server_id)
        if on:
            self.timer.reset()
        # off: the timer sends the release, then stops (on_timer)

    def _clients_for(self, sid: str) -> tuple[Any, Any]:
        if sid not in self._clients:
            self._clients[sid] = (
                self.node.create_client(RequestRoute, schedule_service(sid, "request_route")),
                self.node.create_client(ReleaseRoute, schedule_service(sid, "release_route")))
        return self._clients[sid]

    async def on_timer(self) -> None:
        call = self.mode.next_call()
        if call is None:
            if not self.mode.enabled:
                self.timer.cancel()
            return
        ask, release = self._clients_for(self.mode.server_id)
        try:
            if isinstance(call, ReleaseRouteRequest):
                await release.call_async(call, timeout=1.0)
            else:
                self.mode.on_answer(await ask.call_async(call, timeout=1.0))
            self._failures = 0
        except ZenrosError as exc:  # no manager: the gate keeps the robot stopped
            self._failures += 1
            if self._failures in (1, 10) or self._failures % 100 == 0:
                self.node.logger.warning("schedule server %r: %s (%d in a row)",
                                         self.mode.server_id, exc, self._failures)
