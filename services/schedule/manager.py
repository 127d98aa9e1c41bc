"""TrafficManager: the schedule manager's requests and answers, as messages, over a
`TrafficTable` (plain Python; the node serves it under ``/schedule/<server_id>/...``).

Every call holds one lock: the table is a single ledger, and requests come on Zenoh's
threads. A malformed request is answered INVALID with the table's reason, and changes
nothing.
"""

from __future__ import annotations

import threading

from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.traffic import (
    ReleaseRouteRequest,
    ReleaseRouteResponse,
    RequestRouteRequest,
    RequestRouteResponse,
    RoutePose,
    SegmentReservation,
    TrafficReservations,
    TrafficRobot,
)

from .traffic import Grant, RoutePoint, TrafficError, TrafficTable

__all__ = ["TrafficManager"]


class TrafficManager:
    """The table of map ``map_name``; leases default to ``lease`` seconds."""

    def __init__(self, table: TrafficTable, server_id: str, map_name: str,
                 lease: float = 3.0) -> None:
        self.table, self.server_id, self.map_name, self.lease = table, server_id, map_name, lease
        self._lock = threading.Lock()
        self._published = -1

    def request(self, req: RequestRouteRequest, now: float) -> RequestRouteResponse:
        """Answer ``req`` at ``now`` (seconds of the manager's clock)."""
        if req.map_name and req.map_name != self.map_name:
            return RequestRouteResponse(code=ResultCode.INVALID, message=(
                f"schedule server {self.server_id!r} schedules map {self.map_name!r}, "
                f"not {req.map_name!r}"))
        route = [RoutePoint(p.x, p.y, p.t) for p in req.route]
        lease = req.lease if req.lease > 0 else self.lease
        try:
            with self._lock:
                grant = self.table.request(req.robot, route, now, lease)
        except TrafficError as exc:
            return RequestRouteResponse(code=ResultCode.INVALID, message=str(exc))
        return _response(grant, lease)

    def release(self, req: ReleaseRouteRequest) -> ReleaseRouteResponse:
        with self._lock:
            released = self.table.release(req.robot)
        return ReleaseRouteResponse(released=released, message="" if released else (
            f"robot {req.robot!r} held nothing on schedule server {self.server_id!r}"))

    def expire(self, now: float) -> list[str]:
        with self._lock:
            return self.table.expire(now)

    def changed(self) -> bool:
        """True once after each change of the reservations (for the latched topic)."""
        with self._lock:
            if self.table.version == self._published:
                return False
            self._published = self.table.version
            return True

    def reservations(self, now: float, stamp: Time) -> TrafficReservations:
        """Who holds what, for the ``reservations`` topic and the fleet dashboard."""
        m = self.table.map
        robots = []
        with self._lock:
            for name in sorted(self.table.robots):
                r = self.table.robots[name]
                last = r.last
                holds = [SegmentReservation(
                    segment=h.segment, width=m.segments[h.segment].width,
                    t_enter=h.t_enter - now, t_exit=h.t_exit - now,
                    cells=[RoutePose(*m.cell_centre(c)) for c in m.segments[h.segment].cells])
                    for h in (r.holds[s] for s in sorted(r.holds))]
                at = last and (last.yield_to if last.step_aside else last.stop)
                stop = [RoutePose(*at)] if at else []
                robots.append(TrafficRobot(
                    robot=name, holds=holds, wait_for=r.wait_for, stop=stop,
                    must_yield=bool(last and last.must_yield), expires_in=r.expires - now))
        return TrafficReservations(server_id=self.server_id, map_name=self.map_name,
                                   stamp=stamp, cell_size=m.cell_size,
                                   passing_width=m.passing_width, robots=robots)


def _response(g: Grant, lease: float) -> RequestRouteResponse:
    stop = RoutePose(*g.stop) if g.stop else RoutePose()
    place = RoutePose(*g.yield_to) if g.yield_to else RoutePose()
    message = ("" if g.granted else "yield: back off to the passing place" if g.must_yield
               else f"waiting for {g.wait_for}, aside" if g.step_aside
               else f"waiting for {g.wait_for}" if g.wait_for
               else "beyond the horizon: ask again")
    return RequestRouteResponse(
        granted=g.granted, stop_index=g.stop_index, stop=stop, wait_for=g.wait_for,
        must_yield=g.must_yield, yield_to=place, segments=[h.segment for h in g.holds],
        lease=lease, message=message, step_aside=g.step_aside)
