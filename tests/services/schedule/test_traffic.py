"""The schedule manager's reservation table: segments, grants, passing places, leases,
queues, deadlocks, bad input, and its planning time at ten robots."""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest
from zenros.maps import GridMap, load_map
from zenros.services.schedule.segments import SegmentMap
from zenros.services.schedule.traffic import RoutePoint, TrafficError, TrafficTable

RES = 0.05
OFFICE = Path(__file__).resolve().parents[3] / "deploy" / "maps" / "office" / "office.yaml"


def world(w: float, h: float, free: Sequence[tuple[float, float, float, float]]) -> GridMap:
    """A w x h m map, occupied but for the ``free`` rectangles (x0, y0, x1, y1)."""
    g = np.full((round(h / RES), round(w / RES)), 100, np.int8)
    for x0, y0, x1, y1 in free:
        g[round(y0 / RES):round(y1 / RES), round(x0 / RES):round(x1 / RES)] = 0
    return GridMap(g, RES)


def dumbbell() -> SegmentMap:
    """Two 4 m rooms joined by a corridor 0.9 m wide and 6 m long, along y = 2."""
    return SegmentMap(world(14, 4, [(0, 0, 4, 4), (4, 1.55, 10, 2.45), (10, 0, 14, 4)]))


def ring() -> SegmentMap:
    """Rooms A (south-west), B (south-east), C (north), each pair joined by a corridor
    0.9 m wide: AB along y = 2, BC along x = 16, CA along x = 2."""
    return SegmentMap(world(18, 18, [
        (0, 0, 4, 4), (14, 0, 18, 4), (7, 14, 11, 18),     # A, B, C
        (4, 1.55, 14, 2.45),                              # AB
        (15.55, 4, 16.45, 16), (11, 15.55, 16.45, 16.45),  # BC: up, then west to C
        (1.55, 4, 2.45, 16), (1.55, 15.55, 7, 16.45)]))    # CA: up, then east to C


def polyline(points: Sequence[tuple[float, float]], step: float = 0.25) -> np.ndarray:
    out = [np.array(points[0], float)]
    for a, b in itertools.pairwise(points):
        a_, b_ = np.array(a, float), np.array(b, float)
        n = max(1, math.ceil(np.hypot(*(b_ - a_)) / step))
        out.extend(a_ + (b_ - a_) * k / n for k in range(1, n + 1))
    return np.array(out)


def route(path: np.ndarray, speed: float = 0.5) -> list[RoutePoint]:
    s = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(path, axis=0).T))))
    return [RoutePoint(float(x), float(y), float(d / speed)) for (x, y), d in zip(path, s,
                                                                                   strict=True)]


class Sim:
    """Robots driving their paths point by point, never past their grant, asking every tick;
    it records who stood in each narrow segment at once."""

    def __init__(self, table: TrafficTable, paths: dict[str, np.ndarray], speed: float = 0.5,
                 dt: float = 0.5) -> None:
        self.table, self.paths, self.speed, self.dt = table, paths, speed, dt
        self.at = {n: 0 for n in paths}
        self.now = 0.0
        self.crowded: list[tuple[float, int, list[str]]] = []
        self.waited: dict[str, list[tuple[float, float]]] = {n: [] for n in paths}
        self.alive = set(paths)

    def done(self, name: str) -> bool:
        return self.at[name] == len(self.paths[name]) - 1

    def step(self) -> None:
        for name in sorted(self.alive):
            if self.done(name):
                self.table.release(name)
                continue
            path = self.paths[name][self.at[name]:]
            g = self.table.request(name, route(path, self.speed), self.now, lease=2.0)
            limit = self.at[name] + (len(path) - 1 if g.granted else g.stop_index)
            nxt = min(self.at[name] + max(1, round(self.speed * self.dt / 0.25)), limit)
            if nxt <= self.at[name]:
                self.waited[name].append(tuple(self.paths[name][self.at[name]]))
            self.at[name] = max(self.at[name], nxt)
        inside: dict[int, list[str]] = {}
        for name in self.alive:
            x, y = self.paths[name][self.at[name]]
            seg = self.table.map.segment_at(x, y)
            if seg is not None and seg.narrow:
                inside.setdefault(seg.id, []).append(name)
        self.crowded += [(self.now, s, ns) for s, ns in inside.items() if len(ns) > 1]
        self.now += self.dt

    def run(self, limit: float = 300.0) -> bool:
        while self.now < limit:
            if all(self.done(n) for n in self.alive):
                return True
            self.step()
        return False


# ------------------------------------------------------------------ segments


def test_the_dumbbell_corridor_is_one_narrow_segment_and_the_rooms_are_wide() -> None:
    m = dumbbell()
    assert len(m.narrow) == 1
    corridor = m.narrow[0]
    assert corridor.width == pytest.approx(0.9)
    assert m.segment_at(7.0, 2.0) == corridor
    for x, y in ((2.0, 2.0), (12.0, 2.0), (1.0, 3.5)):
        seg = m.segment_at(x, y)
        assert seg is not None and not seg.narrow
    assert m.segment_at(7.0, 0.5) is None  # a wall


def test_office_doors_are_narrow_the_corridor_is_wide_unless_passing_needs_more() -> None:
    office = load_map(OFFICE)
    m = SegmentMap(office, "office", passing_width=1.3)
    corridor = m.segment_at(5.0, 0.0)
    assert corridor is not None and not corridor.narrow
    door = m.segment_at(-1.1, 1.25)  # the first north office's door, 1 m wide
    assert door is not None and door.narrow and door.width == pytest.approx(1.0)
    strict = SegmentMap(office, "office", passing_width=3.0)
    corridor = strict.segment_at(5.0, 0.0)
    assert corridor is not None and corridor.narrow


def test_bad_segment_parameters_are_refused() -> None:
    g = world(4, 4, [(0, 0, 4, 4)])
    with pytest.raises(ValueError, match="cell_size"):
        SegmentMap(g, cell_size=0.01)
    with pytest.raises(ValueError, match="passing_width"):
        SegmentMap(g, passing_width=-1)


# ------------------------------------------------------------------ head-on


def test_head_on_in_a_one_robot_corridor_one_waits_at_the_passing_place_both_reach() -> None:
    table = TrafficTable(dumbbell(), stand_off=0.9)
    west, east = polyline([(1.0, 2.0), (13.0, 2.0)]), polyline([(13.0, 2.0), (1.0, 2.0)])
    sim = Sim(table, {"a": west, "b": east})
    assert sim.run()
    assert sim.crowded == []
    # b asked second: it waited in its room, 0.9 m of route before the corridor (x = 10)
    assert sim.waited["a"] == []
    spots = {p for p in sim.waited["b"]}
    assert spots and all(10.0 < x <= 11.0 for x, _ in spots), spots


def test_the_refused_robot_is_told_where_to_stop_and_whom_it_waits_for() -> None:
    table = TrafficTable(dumbbell(), stand_off=0.9)
    a = table.request("a", route(polyline([(1.0, 2.0), (13.0, 2.0)])), 0.0, 2.0)
    assert a.granted and [h.segment for h in a.holds] == [table.map.narrow[0].id]
    b = table.request("b", route(polyline([(13.0, 2.0), (1.0, 2.0)])), 0.0, 2.0)
    assert not b.granted and b.wait_for == "a" and b.holds == ()
    assert b.stop is not None and b.stop[0] == pytest.approx(10.75, abs=0.26)
    assert table.waits() == {"b": "a"}


def test_a_waiter_in_the_lane_of_the_robot_coming_out_is_sent_aside() -> None:
    table = TrafficTable(dumbbell(), stand_off=0.9)
    a = table.request("a", route(polyline([(1.0, 2.0), (13.0, 2.0)])), 0.0, 2.0)
    assert a.granted
    # b stands on a's way out of the corridor: it waits off a's lane, in a wall-free cell
    b = table.request("b", route(polyline([(11.5, 2.0), (1.0, 2.0)])), 0.0, 2.0)
    assert not b.granted and b.wait_for == "a" and b.step_aside and b.yield_to is not None
    m = table.map
    lane = {m.cell_at(x, y) for x, y in polyline([(1.0, 2.0), (13.0, 2.0)])}
    row, col = m.cell_at(*b.yield_to)
    assert all(abs(row - r) > 1 or abs(col - c) > 1 for r, c in lane), (b.yield_to, lane)
    assert m.clear_cells[row, col] and math.dist(b.yield_to, (11.5, 2.0)) < 3.0
    # asking again from there keeps it there; once a has gone, b is granted
    b2 = table.request("b", route(np.vstack([b.yield_to, polyline([(11.5, 2.0), (1.0, 2.0)])])),
                       1.0, 2.0)
    assert b2.step_aside and b2.yield_to == b.yield_to
    table.release("a")
    b3 = table.request("b", route(polyline([b.yield_to, (11.5, 2.0), (1.0, 2.0)])), 2.0, 2.0)
    assert b3.granted and not b3.step_aside
    # a waiter whose stop is off the lane (it comes from the side) stays on its route
    table = TrafficTable(dumbbell(), stand_off=0.9)
    table.request("a", route(polyline([(1.0, 2.0), (11.0, 2.0), (11.0, 0.5)])), 0.0, 2.0)
    c = table.request("c", route(polyline([(13.0, 3.5), (10.5, 3.5), (10.0, 2.0),
                                           (1.0, 2.0)])), 0.0, 2.0)
    assert not c.granted and c.wait_for == "a"


def test_same_segment_asked_at_once_goes_by_arrival_then_name() -> None:
    t1 = TrafficTable(dumbbell())
    r_a = route(polyline([(1.0, 2.0), (13.0, 2.0)]))
    r_b = route(polyline([(13.0, 2.0), (1.0, 2.0)]))
    assert t1.request("b", r_b, 0.0, 2.0).granted
    assert not t1.request("a", r_a, 0.0, 2.0).granted
    t2 = TrafficTable(dumbbell())
    assert t2.request("a", r_a, 0.0, 2.0).granted
    assert not t2.request("b", r_b, 0.0, 2.0).granted


def test_a_freed_segment_goes_to_the_first_in_its_queue() -> None:
    table = TrafficTable(dumbbell())
    east = route(polyline([(13.0, 2.0), (1.0, 2.0)]))
    assert table.request("a", route(polyline([(1.0, 2.0), (13.0, 2.0)])), 0.0, 5.0).granted
    assert table.request("b", east, 0.5, 5.0).wait_for == "a"
    east_c = route(polyline([(13.0, 3.0), (12.0, 2.0), (1.0, 2.0)]))
    assert table.request("c", east_c, 1.0, 5.0).wait_for == "a"
    table.request("a", route(polyline([(12.0, 2.0), (13.0, 2.0)])), 2.0, 5.0)  # a is out
    late = table.request("c", east_c, 2.1, 5.0)
    assert not late.granted and late.wait_for == "b"
    assert table.request("b", east, 2.2, 5.0).granted


def test_following_robots_do_not_take_the_corridor_beyond_the_horizon() -> None:
    table = TrafficTable(dumbbell(), horizon=8.0)
    far = route(polyline([(0.5, 0.5), (0.5, 3.5), (3.5, 3.5), (3.5, 0.5), (1.0, 2.0),
                          (13.0, 2.0)]), speed=0.5)  # about 12 s of room first
    g = table.request("slow", far, 0.0, 2.0)
    assert not g.granted and g.wait_for == "" and g.holds == ()
    assert table.request("b", route(polyline([(13.0, 2.0), (1.0, 2.0)])), 0.0, 2.0).granted


# ------------------------------------------------------------------ leases


def test_a_dead_robots_lease_expires_and_the_corridor_is_free_again() -> None:
    table = TrafficTable(dumbbell())
    assert table.request("dead", route(polyline([(1.0, 2.0), (13.0, 2.0)])), 0.0, 3.0).granted
    east = route(polyline([(13.0, 2.0), (1.0, 2.0)]))
    assert table.request("b", east, 1.0, 3.0).wait_for == "dead"
    assert table.request("b", east, 2.9, 3.0).wait_for == "dead"
    g = table.request("b", east, 3.0, 3.0)
    assert g.granted and "dead" not in table.robots
    assert table.expire(100.0) == ["b"]


def test_release_frees_at_once_and_an_unknown_robot_is_said() -> None:
    table = TrafficTable(dumbbell())
    table.request("a", route(polyline([(1.0, 2.0), (13.0, 2.0)])), 0.0, 10.0)
    assert table.release("a") and not table.release("a")
    assert table.request("b", route(polyline([(13.0, 2.0), (1.0, 2.0)])), 0.1, 2.0).granted


# ------------------------------------------------------------------ deadlocks


def test_three_robots_round_a_ring_of_corridors_all_reach() -> None:
    m = ring()
    a, b, c = (2.0, 2.0), (16.0, 2.0), (9.0, 16.0)
    ab = [a, (16.0, 2.0)]
    bc = [b, (16.0, 16.0), (11.0, 16.0), c]
    ca = [c, (7.0, 16.0), (2.0, 16.0), a]
    paths = {"r1": polyline(ab + bc[1:]), "r2": polyline(bc + ca[1:]),
             "r3": polyline(ca + ab[1:])}
    sim = Sim(TrafficTable(m), paths)
    assert sim.run(600.0)
    assert sim.crowded == []


def test_a_cycle_of_waiters_is_broken_by_the_latest_robot_yielding() -> None:
    table = TrafficTable(dumbbell())
    # both stand inside the corridor facing each other (entered without a grant)
    g1 = table.request("first", route(polyline([(6.0, 2.0), (13.0, 2.0)])), 0.0, 5.0)
    assert g1.granted
    g2 = table.request("second", route(polyline([(8.0, 2.0), (1.0, 2.0)])), 0.1, 5.0)
    assert g2.must_yield and g2.yield_to is not None and g2.holds == ()
    seg = table.map.segment_at(*g2.yield_to)
    assert seg is not None and not seg.narrow
    x, y = g2.yield_to  # the east room, behind it (it faces west), aside of first's route
    assert x > 10.0 and abs(y - 2.0) >= 0.7, g2.yield_to
    assert table.holds("second") == () and table.holds("first") == (table.map.narrow[0].id,)


def test_waiting_robots_never_form_a_cycle_in_a_busy_corridor() -> None:
    table = TrafficTable(dumbbell())
    paths = {f"w{k}": polyline([(1.0, 0.5 + k * 0.5), (13.0, 2.0)]) for k in range(3)}
    paths |= {f"e{k}": polyline([(13.0, 0.5 + k * 0.5), (1.0, 2.0)]) for k in range(3)}
    sim = Sim(table, paths)
    seen_cycles = []
    while sim.now < 600 and not all(sim.done(n) for n in paths):
        sim.step()
        w = table.waits()
        for start in w:
            cur, hops = start, 0
            while cur in w and hops <= len(w):
                cur, hops = w[cur], hops + 1
            if hops > len(w):
                seen_cycles.append(sim.now)
    assert all(sim.done(n) for n in paths)
    assert sim.crowded == [] and seen_cycles == []


# ------------------------------------------------------------------ bad input


@pytest.mark.parametrize(("robot", "points", "lease", "match"), [
    ("", [RoutePoint(1, 2)], 1.0, "name"),
    ("a", [], 1.0, "empty route"),
    ("a", [RoutePoint(1, 2), RoutePoint(math.nan, 2)], 1.0, "point 1 is not finite"),
    ("a", [RoutePoint(1, 2)], 0.0, "lease"),
    ("a", [RoutePoint(1, 2)], math.inf, "lease"),
    ("a", [RoutePoint(1, 2)] * 6000, 1.0, "at most"),
])
def test_bad_requests_are_refused_with_the_reason(robot: str, points: list[RoutePoint],
                                                  lease: float, match: str) -> None:
    table = TrafficTable(dumbbell())
    with pytest.raises(TrafficError, match=match):
        table.request(robot, points, 0.0, lease)
    assert table.robots == {}


def test_a_route_off_the_map_holds_nothing() -> None:
    table = TrafficTable(dumbbell())
    g = table.request("lost", [RoutePoint(-50, -50), RoutePoint(99, 99, 1.0)], 0.0, 1.0)
    assert g.granted and g.holds == ()


# ------------------------------------------------------------------ planning time


def test_planning_time_at_ten_robots_is_under_ten_ms_p99() -> None:
    office = SegmentMap(load_map(OFFICE), "office", passing_width=1.3)
    table = TrafficTable(office)
    rng = np.random.default_rng(1)
    spots = [(x, 0.0) for x in np.arange(-2.0, 24.0, 2.0)] + [
        (0.4, 3.0), (6.2, 3.0), (12.0, 3.0), (17.8, 3.0), (1.5, -3.0), (8.0, -3.0)]
    times = []
    for i in range(500):
        name = f"robot{i % 10}"
        a, b = rng.choice(len(spots), 2, replace=False)
        path = polyline([spots[a], (spots[a][0], 0.0), (spots[b][0], 0.0), spots[b]])
        points = route(path)
        t0 = time.thread_time()  # CPU time: the box is shared; bench/traffic.py gives wall time
        table.request(name, points, i * 0.05, 2.0)
        times.append(time.thread_time() - t0)
    p99 = float(np.percentile(times, 99)) * 1000
    assert p99 <= 10.0, p99
