"""SharedWorld: other robots' bodies as obstacles, seen by the laser, felt by the bumper."""

from __future__ import annotations

import math

import pytest
from test_chassis_sim import make_sim, run
from zenros.msgs.zenros_msgs import Obstacle as ObstacleMsg
from zenros.se2 import Pose2
from zenros.services.chassis.shared_world import BODY_PREFIX, KEEPALIVE, STALE, SharedWorld
from zenros.services.chassis.world import World


class FakeClock:
    def __init__(self) -> None:
        self.t = 100.0

    def __call__(self) -> float:
        return self.t


def body(name: str, x: float, y: float, radius: float = 0.2) -> ObstacleMsg:
    return ObstacleMsg(id=name, shape="circle", x=x, y=y, radius=radius)


def test_own_body_is_published_and_not_taken_back(room: World) -> None:
    shared = SharedWorld(room, "/robot1", 0.2)
    msg = shared.body(Pose2(1.0, 1.5, 0.3))
    assert (msg.id, msg.shape, msg.x, msg.y, msg.theta, msg.radius) == \
        ("/robot1", "circle", 1.0, 1.5, 0.3, 0.2)
    assert not shared.on_body(msg)
    assert room.obstacles == {}


def test_another_body_is_an_obstacle_the_laser_sees(room: World) -> None:
    rig = make_sim(room, Pose2(1.0, 1.5, 0.0))
    ahead = 4  # 8 beams from -pi: beam 4 looks along +x, to the wall at 4.95 m
    before = rig.scan()[ahead]
    shared = SharedWorld(room, "/robot1", 0.2, FakeClock())
    assert shared.on_body(body("/robot2", 2.5, 1.5))
    assert set(room.obstacles) == {BODY_PREFIX + "/robot2"}
    after = rig.scan()[ahead]
    # the laser sits 0.1 m ahead of the centre: 2.5 - 0.2 (the body) - 1.1
    assert after == pytest.approx(1.2, abs=0.02)
    assert before > 3.5


def test_a_body_stops_the_robot_driving_into_it(room: World) -> None:
    rig = make_sim(room, Pose2(1.0, 1.5, 0.0))
    SharedWorld(room, "/robot1", 0.2, FakeClock()).on_body(body("/robot2", 2.0, 1.5))
    run(rig, 0.5, 0.0, 4.0)
    assert rig.bumper
    assert rig.truth.x == pytest.approx(2.0 - 0.4, abs=0.02)  # the two radii apart


def test_a_moved_body_moves_and_a_silent_one_leaves(room: World) -> None:
    clock = FakeClock()
    shared = SharedWorld(room, "/robot1", 0.2, clock)
    shared.on_body(body("/robot2", 2.0, 1.5))
    shared.on_body(body("/robot3", 3.0, 1.0))
    clock.t += STALE / 2
    shared.on_body(body("/robot2", 2.2, 1.4))
    assert shared.prune() == []
    assert (room.obstacles[BODY_PREFIX + "/robot2"].x,
            room.obstacles[BODY_PREFIX + "/robot2"].y) == (2.2, 1.4)
    clock.t += STALE / 2 + 0.01
    assert shared.prune() == [BODY_PREFIX + "/robot3"]
    assert set(room.obstacles) == {BODY_PREFIX + "/robot2"}


@pytest.mark.parametrize("bad", [
    body("", 1.0, 1.0),
    body("/robot2", math.nan, 1.0),
    body("/robot2", 1.0, 1.0, radius=0.0),
    body("/robot2", 1.0, 1.0, radius=50.0),
    ObstacleMsg(id="/robot2", shape="box", x=1.0, y=1.0, size_x=1.0, size_y=1.0),
])
def test_a_body_that_is_not_a_robot_is_refused_and_counted(room: World,
                                                           bad: ObstacleMsg) -> None:
    shared = SharedWorld(room, "/robot1", 0.2)
    assert not shared.on_body(bad)
    assert shared.refused == 1
    assert room.obstacles == {}


def test_a_body_at_rest_is_sent_again_only_to_keep_it(room: World) -> None:
    clock = FakeClock()
    shared = SharedWorld(room, "/robot1", 0.2, clock)
    here = shared.body(Pose2(1.0, 1.5, 0.0))
    assert shared.due(here)  # the first one
    clock.t += 0.1
    assert not shared.due(shared.body(Pose2(1.0, 1.5, 0.0)))  # the same body, just sent
    clock.t += 0.1
    assert shared.due(shared.body(Pose2(1.05, 1.5, 0.0)))  # moved: sent at once
    clock.t += KEEPALIVE - 0.01
    assert not shared.due(shared.body(Pose2(1.05, 1.5, 0.0)))
    clock.t += 0.02
    assert shared.due(shared.body(Pose2(1.05, 1.5, 0.0)))  # kept alive in the others' worlds
    assert KEEPALIVE * 2 < STALE  # two keep-alives fit in the time before a body is dropped
