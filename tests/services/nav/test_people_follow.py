"""The leg detector on synthetic scans, the follower's control law and track, and the
following's control over nav's motion (one mode at a time, never over a goal)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from zenros.msgs.zenros_msgs import SetFollowRequest
from zenros.se2 import Pose2
from zenros.services.nav.costmap.costmap import Costmap2D
from zenros.services.nav.motion.active import Motion
from zenros.services.nav.motion.behavior import Behavior, Sense
from zenros.services.nav.people.control import FollowControl
from zenros.services.nav.people.follow import (
    Follow,
    FollowParams,
    Track,
    blocked,
    follow_command,
    off_walls,
)
from zenros.services.nav.people.legs import detect_legs, detect_people

BEAMS = 360


def scan(circles: list[tuple[float, float, float]], wall: float = 8.0,
         noise: float = 0.0, seed: int = 0) -> np.ndarray:
    """A 360-beam scan's points (x, y) from the origin: circles (x, y, r), walls a circle of
    radius ``wall`` round the robot (too big to be a leg)."""
    a = np.linspace(-math.pi, math.pi, BEAMS, endpoint=False)
    dx, dy = np.cos(a), np.sin(a)
    r = np.full(BEAMS, wall)
    for cx, cy, cr in circles:
        b = -(cx * dx + cy * dy)
        c = cx * cx + cy * cy - cr * cr
        disc = b * b - c
        with np.errstate(invalid="ignore"):
            t = -b - np.sqrt(disc)
        r = np.where((disc >= 0) & (t > 0) & (t < r), t, r)
    r = r + np.random.default_rng(seed).normal(0, noise, BEAMS) if noise else r
    return np.column_stack([r * dx, r * dy])


def person(x: float, y: float, spread: float = 0.2) -> list[tuple[float, float, float]]:
    """Two legs of 0.06 m either side of (x, y), ``spread`` apart across the line of sight."""
    n = np.array([-y, x]) / math.hypot(x, y)
    return [(x + n[0] * spread / 2, y + n[1] * spread / 2, 0.06),
            (x - n[0] * spread / 2, y - n[1] * spread / 2, 0.06)]


def test_legs_are_found_and_paired_into_people_nearest_first() -> None:
    pts = scan(person(2.0, 0.5) + person(1.0, -1.0))
    assert len(detect_legs(pts)) == 4
    found = detect_people(pts)
    assert found.shape == (2, 2)
    assert found[0] == pytest.approx([1.0, -1.0], abs=0.06)  # nearest first
    assert found[1] == pytest.approx([2.0, 0.5], abs=0.06)


def test_things_not_of_leg_size_or_single_legs_are_not_people() -> None:
    pts = scan([(1.5, 0.0, 0.4), (0.0, 2.0, 0.06)])  # a bin, one lone leg
    assert len(detect_people(pts)) == 0
    assert len(detect_people(pts, singles=True)) == 1  # the lone leg, when tracking
    far_apart = scan([(1.5, 0.5, 0.06), (1.5, -0.5, 0.06)])  # 1 m apart: two people's legs
    assert len(detect_people(far_apart)) == 0


def wall_scan(y: float, x0: float, x1: float) -> np.ndarray:
    """A 1-degree scan's points on a wall along x (from ``x0`` to ``x1``) at ``y``."""
    a = np.linspace(-math.pi, math.pi, BEAMS, endpoint=False)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = y / np.sin(a)
    x = t * np.cos(a)
    keep = (t > 0) & (x >= x0) & (x <= x1)
    return np.column_stack([x[keep], np.full(keep.sum(), y)])


def test_a_wall_seen_at_a_grazing_angle_is_no_one() -> None:
    for y in (1.2, -1.0, 0.8):
        assert len(detect_legs(wall_scan(y, 0.5, 6.0))) == 0, y


def test_people_on_the_maps_walls_are_dropped() -> None:
    occ = np.zeros((40, 40), np.int8)
    occ[:, 30] = 100  # a wall at x = 1.5 .. 1.55
    cm = Costmap2D(occ, 0.05)
    near = cm.near_static(np.array([[1.4, 1.0], [1.0, 1.0], [5.0, 5.0]]), 0.15)
    assert near.tolist() == [True, False, False]
    people = np.array([[0.4, 0.0], [0.9, 0.5]])  # base_link, the robot at (1.0, 0.5) facing +x
    kept = off_walls(people, Pose2(1.0, 0.5, 0.0), lambda w: cm.near_static(w, 0.15))
    assert kept.tolist() == [[0.9, 0.5]]  # (1.4, 0.5) is on the wall, (1.9, 1.0) is not
    assert off_walls(people, None, lambda w: cm.near_static(w, 0.15)).tolist() == people.tolist()


def test_the_detector_finds_a_walking_person_in_most_noisy_scans() -> None:
    hits = 0
    for i in range(200):
        spread = 0.3 * math.sin(i / 5)  # legs passing each other along the line of sight
        d = 1.0 + 0.01 * i
        legs = [(d + spread / 2, 0.1, 0.06), (d - spread / 2, -0.1, 0.06)]
        found = detect_people(scan(legs, noise=0.01, seed=i), singles=True)
        hits += bool(len(found)) and abs(found[0][0] - d) < 0.25
    assert hits >= 190, hits  # measured 200 of 200 (1-3 m, 1 cm range noise)


def test_the_control_law_keeps_the_distance_turns_to_face_and_never_backs_up() -> None:
    p = FollowParams()
    assert follow_command(1.0, 0.0, p) == (0.0, 0.0)
    assert follow_command(0.5, 0.0, p) == (0.0, 0.0)  # closer: stop, never back up
    v, w = follow_command(1.2, 0.0, p)
    assert v == pytest.approx(p.k_linear * 0.2) and w == 0.0
    assert follow_command(5.0, 0.0, p)[0] == p.max_linear
    v, w = follow_command(2.0, math.pi / 2, p)
    assert v == 0.0 and w == p.max_angular  # at the side: turn first
    v, w = follow_command(2.0, -0.1, p)
    assert 0 < v < p.max_linear and w == pytest.approx(-0.2)


def test_a_walking_person_is_fed_forward_so_the_robot_keeps_the_distance() -> None:
    p = FollowParams()
    assert follow_command(1.0, 0.0, p, away=0.3) == (0.0, 0.0)  # at the distance: no push
    v, _ = follow_command(1.1, 0.0, p, away=0.3)
    assert v == pytest.approx(0.3 + p.k_linear * 0.1)
    assert follow_command(1.1, 0.0, p, away=-0.5)[0] == pytest.approx(p.k_linear * 0.1)
    t = Track(p)
    here = Pose2()
    for i in range(11):  # a person walking off at 0.4 m/s, seen at 10 Hz
        t.update(here, np.array([[1.0 + 0.04 * i, 0.0]]), i / 10, acquire=True)
        t.moved(i / 10)
    assert t.away(here) == pytest.approx(0.4, abs=0.05)
    assert t.away(Pose2(3.0, 0.0, 0.0)) == pytest.approx(-0.4, abs=0.05)  # towards that one


def test_the_body_stops_for_what_is_in_front() -> None:
    p = FollowParams()
    ahead = np.array([[0.35, 0.0]])
    assert blocked(ahead, 0.3, p) and not blocked(ahead, 0.0, p)
    assert not blocked(np.array([[0.35, 0.5], [-0.3, 0.0]]), 0.3, p)


def test_the_track_keeps_its_person_and_loses_them_after_a_while() -> None:
    p = FollowParams(lost_after=1.0)
    t = Track(p)
    here = Pose2(1.0, 0.0, math.pi / 2)
    assert not t.update(here, np.array([[3.0, 0.0]]), 0.0, acquire=True)  # too far
    assert t.update(here, np.array([[1.0, 0.0], [1.5, 0.0]]), 0.0, acquire=True)
    assert t.xy == pytest.approx((1.0, 1.0))  # the nearest, in the world
    assert t.update(here, np.array([[0.9, 1.0], [1.2, 0.1]]), 0.5, acquire=True)
    assert t.xy == pytest.approx((0.9, 1.2))  # the one near the track, not another
    seen = t.seen_from(Pose2(0.9, 0.2, 0.0))
    assert seen is not None and seen.distance == pytest.approx(1.0)
    assert seen.bearing == pytest.approx(math.pi / 2)
    assert not t.update(here, np.zeros((0, 2)), 2.0, acquire=True)
    assert t.xy is None  # lost after lost_after


def sense(now: float, points: np.ndarray) -> Sense:
    return Sense(now=now, dt=0.05, pose=Pose2(), obstacles=points)


def test_follow_drives_to_the_person_stops_near_and_reports_a_loss() -> None:
    f = Follow("legs", FollowParams(lost_after=1.0))
    v, w = f.step(sense(0.0, scan(person(2.0, 0.3))))
    assert f.state == "following" and v > 0 and w > 0
    for t, x in ((0.1, 1.6), (0.2, 1.2)):
        assert f.step(sense(t, scan(person(x, 0.0))))[0] > 0
    assert f.step(sense(0.3, scan(person(0.9, 0.0))))[0] == 0.0  # within 1 m: stop
    assert f.step(sense(0.4, scan([]))) == (0.0, 0.0) and f.state == "following"
    assert f.step(sense(2.0, scan([]))) == (0.0, 0.0)
    assert f.state == "lost" and "lost the person" in f.message


def test_uwb_follow_uses_the_tag_reading_while_it_is_fresh() -> None:
    reading: list[tuple[float, float, float]] = [(2.0, 0.0, 0.0)]
    f = Follow("uwb", FollowParams(lost_after=1.0), lambda: reading[-1] if reading else None)
    v, _ = f.step(sense(0.05, np.zeros((0, 2))))
    assert v > 0 and f.sighting is not None and f.sighting.distance == pytest.approx(2.0)
    assert f.step(sense(5.0, np.zeros((0, 2)))) == (0.0, 0.0)  # stale: stopped
    assert f.state == "lost"


class Goal(Behavior):
    name = "navigate"

    def tick(self, sense: Sense) -> tuple[float, float]:
        return 0.1, 0.0


def test_following_is_one_mode_at_a_time_and_never_over_a_goal() -> None:
    motion = Motion()
    ctl = FollowControl(motion, FollowParams(), lambda: None)
    res = ctl.handle_set(SetFollowRequest(mode="legs", enable=True))
    assert res.success and res.status.enabled and res.status.mode == "legs"
    res = ctl.handle_set(SetFollowRequest(mode="uwb", enable=True))
    assert res.success and res.status.mode == "uwb"  # the other mode replaced
    res = ctl.handle_set(SetFollowRequest(mode="legs", enable=False))
    assert res.success and res.status.mode == "uwb"  # not on: nothing to turn off
    assert ctl.handle_set(SetFollowRequest(mode="uwb", enable=False)).status.state == "off"
    goal = Goal()
    motion.start(goal)
    res = ctl.handle_set(SetFollowRequest(mode="legs", enable=True))
    assert not res.success and "a navigate goal is running" in res.message
    assert motion.active is goal
    motion.halt(goal)
    ctl.handle_set(SetFollowRequest(mode="legs", enable=True))
    motion.start(Goal())  # a goal sent while following takes over
    status = ctl.handle_status(None).status
    assert not status.enabled and status.message == "preempted by a new goal"
    off = FollowControl(Motion(), FollowParams(), lambda: None, active=lambda: "nav is inactive")
    assert off.handle_set(SetFollowRequest(mode="legs", enable=True)).message == "nav is inactive"
