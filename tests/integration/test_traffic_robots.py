"""Two simulated robots in schedule mode meet head-on in a corridor one robot wide
(docs/fleet.md, "Traffic schedule"): a generated world of two halls joined by a 0.8 m
corridor 3 m long (tests/worlds.py, `crossing_world`), a chassis and nav per robot sharing
one world (each sees the other), the schedule server on the same map. Both get goals across
the corridor at once: both reach, the manager never let both hold the corridor, their true
poses were never both in it, and they never touched (bumpers released, centres always
more than two radii apart).

The same without schedule mode is not asserted on: two robots meeting in the corridor stand
each other off until nav's recoveries give up, which says nothing the schedule needs and
costs minutes (bench/traffic.py counts those meetings).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from traffic_robots import Rect, traffic_robots
from worlds import crossing_world, lane_y
from zenros.testing import wait_for

pytestmark = [pytest.mark.timeout(180), pytest.mark.xdist_group("sim")]

HALL, LENGTH, WIDTH = 3.0, 3.0, 0.8
EAST = 2 * HALL + LENGTH - 1.0  # x of the east robots' start and the west robots' goal
RADIUS = 0.2  # the chassis' robot_radius


def test_two_robots_in_schedule_mode_cross_a_one_robot_corridor(tmp_path: Path) -> None:
    world = crossing_world(tmp_path / "world", 1, width=WIDTH, length=LENGTH, hall=HALL)
    y = lane_y(0)
    corridor = Rect(HALL, y - WIDTH / 2, HALL + LENGTH, y + WIDTH / 2)
    starts = [(1.0, y - 0.5, 0.0), (EAST, y - 0.5, math.pi)]
    goals = [(EAST, y + 0.5, 0.0), (1.0, y + 0.5, math.pi)]
    with traffic_robots(tmp_path, world, starts, speed=5.0, corridors=[corridor]) as fleet:
        server = fleet.server
        assert server is not None
        assert [s.width for s in server.traffic.table.map.narrow] == [pytest.approx(WIDTH)]
        handles = [fleet.navigate[n].send_goal_async(fleet.goal(*g))
                   for n, g in zip(fleet.names, goals, strict=True)]
        # one of them is granted the corridor, the other waits before it
        assert wait_for(lambda: bool(server.traffic.table.waits()), 30), \
            server.traffic.table.robots
        # the one waiting stands where the other comes out: it waits aside
        assert wait_for(lambda: any((g := server.traffic.table.grant_of(n)) is not None
                                    and g.step_aside for n in fleet.names), 30), \
            [server.traffic.table.grant_of(n) for n in fleet.names]
        results = [h.result(120) for h in handles]
        assert all(r.succeeded for r in results), [r.status for r in results]
        for (gx, gy, _), name in zip(goals, fleet.names, strict=True):
            assert wait_for(lambda n=name, gx=gx, gy=gy: math.hypot(
                fleet.watch.truth[n][0] - gx, fleet.watch.truth[n][1] - gy) < 0.3, 5), \
                (name, fleet.watch.truth[name])
        watch = fleet.watch
        assert watch.reservations > 0
        assert watch.shared_holds == []  # never both in the narrow segment, per the manager
        assert watch.together == set()  # nor by their true poses
        assert watch.bumped == set()
        assert watch.closest > 2 * RADIUS, watch.closest
        # navigations ended: nav released what it held
        assert wait_for(lambda: all(not server.traffic.table.holds(n) for n in fleet.names), 10)
