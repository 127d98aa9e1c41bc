"""The schedule server's traffic schedule over real Zenoh: two robots' routes through one
door of the demo office, the latched reservations, release, and bad requests answered
with their reason (the server keeps serving)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from zenros.errors import ServiceError
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.traffic import (
    ReleaseRoute,
    ReleaseRouteRequest,
    RequestRoute,
    RequestRouteRequest,
    RoutePose,
    TrafficReservations,
)
from zenros.qos import QOS_LATCHED
from zenros.services.schedule.node import ScheduleServerNode
from zenros.testing import wait_for


def through_door(x0: float, y0: float, x1: float, y1: float) -> list[RoutePose]:
    """Straight from (x0, y0) to (x1, y1) in 0.25 m steps at 0.5 m/s."""
    n = round(max(abs(x1 - x0), abs(y1 - y0)) / 0.25)
    return [RoutePose(x=x0 + (x1 - x0) * k / n, y=y0 + (y1 - y0) * k / n, t=k * 0.5)
            for k in range(n + 1)]


def test_two_robots_through_one_door(make_node: Any, tmp_path: Path) -> None:
    server = make_node("schedule_server", 0, ScheduleServerNode, parameter_overrides={
        "data_dir": str(tmp_path)})
    user = make_node("user", 1)
    got: list[TrafficReservations] = []
    user.create_subscription(TrafficReservations, "/schedule/local/reservations", got.append,
                             QOS_LATCHED)
    ask = user.create_client(RequestRoute, "/schedule/local/request_route")
    release = user.create_client(ReleaseRoute, "/schedule/local/release_route")
    assert ask.wait_for_service(10)
    # the first north office's door (1 m wide) at x = -1.1: one robot in, one out
    a = ask.call(RequestRouteRequest(robot="robot1", map_name="office",
                                     route=through_door(-1.1, -0.5, -1.1, 3.0)))
    assert a.code == 0 and a.granted and len(a.segments) == 1, a
    b = ask.call(RequestRouteRequest(robot="robot2", route=through_door(-1.1, 3.5, -1.1, -0.5)))
    assert not b.granted and b.wait_for == "robot1" and b.stop.y > 1.25 + 0.5, b
    assert wait_for(lambda: bool(got) and {r.robot for r in got[-1].robots}
                    == {"robot1", "robot2"}, 5)
    held = {r.robot: r for r in got[-1].robots}
    assert [h.segment for h in held["robot1"].holds] == a.segments
    assert held["robot2"].wait_for == "robot1" and held["robot2"].stop
    assert release.call(ReleaseRouteRequest(robot="robot1")).released
    assert not release.call(ReleaseRouteRequest(robot="robot1")).released
    assert ask.call(RequestRouteRequest(robot="robot2",
                                        route=through_door(-1.1, 3.5, -1.1, -0.5))).granted
    assert server.traffic.table.holds("robot2") == tuple(a.segments)


def test_bad_requests_get_their_reason_and_the_server_keeps_serving(make_node: Any,
                                                                     tmp_path: Path) -> None:
    make_node("schedule_server", 0, ScheduleServerNode, parameter_overrides={
        "data_dir": str(tmp_path)})
    user = make_node("user", 1)
    ask = user.create_client(RequestRoute, "/schedule/local/request_route")
    assert ask.wait_for_service(10)
    r = ask.call(RequestRouteRequest(robot="robot1", map_name="lobby",
                                     route=[RoutePose(x=0.0, y=0.0)]))
    assert r.code == ResultCode.INVALID and "'office', not 'lobby'" in r.message
    r = ask.call(RequestRouteRequest(robot="robot1", route=[]))
    assert r.code == ResultCode.INVALID and "empty route" in r.message
    r = ask.call(RequestRouteRequest(robot="robot1", route=[RoutePose(x=0.0)], lease=-1.0))
    assert r.code == ResultCode.INVALID or r.granted  # a negative lease is the default one
    raw = user.create_client(ReleaseRoute, "/schedule/local/request_route")
    try:  # a payload of another type: refused, and the server answers the next one
        raw.call(ReleaseRouteRequest(robot="x"), timeout=5)
    except ServiceError:
        pass
    assert ask.call(RequestRouteRequest(robot="robot1", route=[RoutePose(x=0.0)])).granted
