"""Schedule mode's traffic gate in nav: the route it sends, the stop it keeps, the release
at the end, and Navigate stopping at the end of its grant then going on (a stand-in
manager answers)."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from test_behaviors import DT, Tools, World, nav
from zenros.msgs.zenros_msgs.traffic import (
    ReleaseRouteRequest,
    RequestRouteRequest,
    RequestRouteResponse,
    RoutePose,
    SetScheduleModeRequest,
)
from zenros.se2 import Pose2
from zenros.services.nav.actions.schedule_mode import ScheduleMode
from zenros.services.nav.motion.behavior import Sense
from zenros.services.nav.motion.navigate import Navigate
from zenros.services.nav.motion.traffic import Ask, Reply, ScheduleGate

PATH = np.column_stack([np.linspace(0.0, 5.0, 101), np.zeros(101)])


def test_off_the_gate_limits_nothing_and_sends_nothing() -> None:
    gate = ScheduleGate()
    assert gate.limit(0.0, Pose2(), PATH, 0.0) is None
    assert gate.take() is None and gate.state == "off"


def test_on_it_sends_the_route_stops_until_answered_then_caps_at_the_stop() -> None:
    gate = ScheduleGate(speed=0.5, renew_period=0.5, lease=3.0, spacing=0.25)
    gate.set_enabled(True)
    assert gate.limit(0.0, Pose2(), PATH, 0.0) == 0.0  # no answer yet: stay
    ask = gate.take()
    assert ask is not None and not ask.release
    assert ask.route[0] == (0.0, 0.0, 0.0) and ask.route[-1] == (5.0, 0.0, 10.0)
    assert all(b[2] > a[2] for a, b in zip(ask.route, ask.route[1:], strict=False))
    gate.on_reply(Reply(0.1, False, (3.0, 0.05), "robot2"))
    assert gate.limit(0.2, Pose2(), PATH, 0.0) == 3.0 and gate.take() is None
    assert gate.limit(0.6, Pose2(1.0, 0.0), PATH, 1.0) == 3.0 and gate.take() is not None  # renew
    gate.on_reply(Reply(0.7, True))
    assert gate.limit(0.8, Pose2(1.0, 0.0), PATH, 1.0) is None
    assert gate.limit(4.0, Pose2(1.0, 0.0), PATH, 1.0) == 1.0  # the answer is stale: stop
    assert gate.state == "no_answer"
    gate.end()
    end = gate.take()
    assert end is not None and end.release and gate.state == "idle"
    gate.set_enabled(False)
    assert gate.limit(5.0, Pose2(), PATH, 0.0) is None


def gated() -> tuple[Tools, ScheduleGate, World, Navigate]:
    """A Navigate from (1, 1) to (4, 1) behind an enabled gate (close ``tools.worker``)."""
    tools = Tools()
    gate = ScheduleGate(speed=0.5, renew_period=0.5)
    gate.set_enabled(True)
    b = nav(tools, Pose2(4.0, 1.0, 0.0))
    b.gate = gate
    return tools, gate, World(Pose2(1.0, 1.0, 0.0)), b


def drive(b: Navigate, gate: ScheduleGate, world: World, answer: Callable[[Ask], Reply],
          seconds: float, watch: Callable[[], None] = lambda: None) -> tuple[int, bool]:
    """Tick ``b`` on ``world`` for ``seconds`` at most; ``answer`` stands in for the manager
    (each route asked, answered at once); ``watch`` runs every tick before the robot moves.
    Returns (routes asked, whether a release was sent)."""
    asked, released = 0, False
    for _ in range(int(seconds / DT)):
        v, w = b.step(Sense(now=world.t, dt=DT, pose=world.pose))
        ask = gate.take()
        released = released or (ask is not None and ask.release)
        if ask is not None and not ask.release:
            asked += 1
            gate.on_reply(answer(ask))
        if b.done.is_set():
            break
        watch()
        th = world.pose.theta + w * DT / 2
        world.pose = Pose2(world.pose.x + v * DT * math.cos(th),
                           world.pose.y + v * DT * math.sin(th), world.pose.theta + w * DT)
        world.t += DT
    return asked, released


def test_navigate_waits_at_the_end_of_its_grant_then_reaches_the_goal() -> None:
    tools, gate, world, b = gated()
    try:
        stood: list[float] = []

        def answer(ask: Ask) -> Reply:
            granted = world.t > 20.0  # the manager holds the robot at x = 2.5 for 20 s
            return Reply(world.t, granted, None if granted else (2.5, 1.0), "r2")

        def watch() -> None:
            if 5.0 < world.t < 20.0:
                stood.append(world.pose.x)

        asked, released = drive(b, gate, world, answer, 60, watch)
        assert b.succeeded, b.error_msg
        assert stood and 2.3 <= min(stood) and max(stood) <= 2.55, (min(stood), max(stood))
        assert b.recoveries == 0 and asked >= 20
        assert released  # at the goal
    finally:
        tools.worker.close()


def test_navigate_waits_aside_where_it_is_told_then_goes_back_to_its_goal() -> None:
    tools, gate, world, b = gated()
    try:
        aside = (2.0, 2.0)
        asked_off: list[tuple[float, float]] = []
        stood: list[tuple[float, float]] = []

        def answer(ask: Ask) -> Reply:
            waiting = 2.0 < world.t < 25.0  # then the manager sends it aside
            if waiting:
                asked_off.append(ask.route[-1][:2])
            return Reply(world.t, not waiting, (2.5, 1.0) if waiting else None, "r2",
                         aside=aside if waiting else None)

        def watch() -> None:
            if 15.0 < world.t < 25.0:
                stood.append((world.pose.x, world.pose.y))

        drive(b, gate, world, answer, 80, watch)
        assert b.succeeded, b.error_msg
        # it waited at the place aside, and asked with its route to the goal all along
        assert stood and all(math.dist(p, aside) < 0.3 for p in stood), stood[-5:]
        assert asked_off and all(math.dist(p, (4.0, 1.0)) < 0.01 for p in asked_off)
        assert math.dist((world.pose.x, world.pose.y), (4.0, 1.0)) < 0.3
    finally:
        tools.worker.close()


def test_without_a_gate_navigate_is_unchanged() -> None:
    tools = Tools()
    try:
        b = Navigate([Pose2(4.0, 1.0)], tools, nav(tools, Pose2()).p, nav(tools, Pose2()).pp.params)
        assert b.gate is None
        World(Pose2(1.0, 1.0, 0.0)).run(b, 60)
        assert b.succeeded
    finally:
        tools.worker.close()


def test_schedule_mode_speaks_the_managers_messages() -> None:
    gate = ScheduleGate()
    switched: list[bool] = []
    mode = ScheduleMode(gate, "robot1", "local", 3.0, lambda: "office", lambda: 1.0,
                        switched.append)
    bad = mode.handle_set(SetScheduleModeRequest(enable=True, server_id="no/pe"))
    assert bad.code != 0 and "bad schedule server id" in bad.message and not mode.enabled
    res = mode.handle_set(SetScheduleModeRequest(enable=True))
    assert res.status.enabled and res.status.server_id == "local" and switched == [True]
    gate.limit(0.0, Pose2(), PATH, 0.0)
    call = mode.next_call()
    assert isinstance(call, RequestRouteRequest) and call.robot == "robot1"
    assert call.map_name == "office" and call.lease == 3.0 and call.route[0] == RoutePose()
    mode.on_answer(RequestRouteResponse(granted=False, stop=RoutePose(x=2.0), wait_for="r2",
                                        segments=[4]))
    assert gate.limit(0.1, Pose2(), PATH, 0.0) == 2.0
    assert mode.status().wait_for == "r2" and mode.status().segments == [4]
    mode.on_answer(RequestRouteResponse(code=3, message="no such map"))
    assert mode.last_error == "no such map"
    mode.handle_set(SetScheduleModeRequest(enable=False))
    assert isinstance(mode.next_call(), ReleaseRouteRequest) and switched == [True, False]
    assert mode.status().state == "off"
