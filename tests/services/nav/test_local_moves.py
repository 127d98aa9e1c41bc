"""Local-move behaviours tick by tick on an ideal unicycle (no network): DriveOnHeading
stops on the mark, forwards and backwards, and before an obstacle; SpinInPlace turns the
asked angle; LocalMoveTarget reaches map and base_link targets with and without the turns;
timeouts and a missing pose end with the action's codes."""

from __future__ import annotations

import math

import numpy as np
from zenros.msgs.nav2_msgs import BackUpResult, DriveOnHeadingResult, SpinResult
from zenros.se2 import Pose2, angle_diff
from zenros.services.nav.actions.behavior_server import (
    BACKUP_CODES,
    DRIVE_CODES,
    SPIN_CODES,
    TARGET_CODES,
)
from zenros.services.nav.motion.behavior import Behavior, Sense
from zenros.services.nav.motion.collision import points_in_frame
from zenros.services.nav.motion.local_moves import DriveOnHeading, LocalMoveTarget, SpinInPlace

DT = 0.05


class Unicycle:
    def __init__(self, pose: Pose2, obstacles: np.ndarray | None = None) -> None:
        self.pose, self.t = pose, 0.0
        self.obstacles = obstacles if obstacles is not None else np.zeros((0, 2))
        self.localised = True

    def run(self, b: Behavior, seconds: float) -> None:
        for _ in range(int(seconds / DT)):
            pose = self.pose if self.localised else None
            v, w = b.step(Sense(now=self.t, dt=DT, pose=pose,
                                obstacles=points_in_frame(self.obstacles, *self.pose)))
            if b.done.is_set():
                return
            th = self.pose.theta + w * DT / 2
            self.pose = Pose2(self.pose.x + v * DT * math.cos(th),
                              self.pose.y + v * DT * math.sin(th), self.pose.theta + w * DT)
            self.t += DT


def test_drive_on_heading_forward_and_back() -> None:
    for distance in (0.5, -0.35):
        world = Unicycle(Pose2(1.0, 2.0, 0.5))
        b = DriveOnHeading(distance, 0.3, 0.0, DRIVE_CODES, radius=0.2)
        world.run(b, 20)
        assert b.succeeded, b.error_msg
        moved = world.pose.distance(Pose2(1.0, 2.0))
        assert abs(moved - abs(distance)) < 0.01 and abs(b.traveled - abs(distance)) < 0.01
        ahead = (world.pose.x - 1.0) * math.cos(0.5) + (world.pose.y - 2.0) * math.sin(0.5)
        assert math.copysign(1, ahead) == math.copysign(1, distance)


def test_drive_stops_before_an_obstacle_with_collision_ahead() -> None:
    wall = np.array([[1.0, y] for y in np.linspace(-0.5, 0.5, 21)])
    world = Unicycle(Pose2(), wall)
    b = DriveOnHeading(2.0, 0.3, 0.0, DRIVE_CODES, radius=0.2)
    world.run(b, 20)
    assert not b.succeeded and b.error_code == DriveOnHeadingResult.COLLISION_AHEAD
    assert "collision ahead" in b.error_msg and world.pose.x < 0.8
    # with collision checks off it drives on (the chassis's bumper would stop it)
    world = Unicycle(Pose2(), wall)
    b = DriveOnHeading(0.5, 0.3, 0.0, DRIVE_CODES, radius=0.2, check_collisions=False)
    world.run(b, 20)
    assert b.succeeded


def test_backup_timeout_and_no_pose_codes() -> None:
    world = Unicycle(Pose2())
    b = DriveOnHeading(-2.0, 0.1, 1.0, BACKUP_CODES, radius=0.2)
    world.run(b, 20)
    assert b.error_code == BackUpResult.TIMEOUT and "time allowance" in b.error_msg
    world = Unicycle(Pose2())
    world.localised = False
    b = DriveOnHeading(1.0, 0.1, 0.0, BACKUP_CODES, radius=0.2)
    world.run(b, 20)
    assert b.error_code == BackUpResult.TF_ERROR


def test_spin_turns_the_angle_both_ways() -> None:
    for angle in (math.pi / 2, -2.5, 7.0):
        world = Unicycle(Pose2(0, 0, 3.0))
        b = SpinInPlace(angle, 1.0, 0.0, SPIN_CODES)
        world.run(b, 30)
        assert b.succeeded, b.error_msg
        assert abs(b.turned - abs(angle)) < 0.05
        assert abs(angle_diff(world.pose.theta, 3.0 + angle)) < 0.05
    b = SpinInPlace(6.0, 1.0, 1.0, SPIN_CODES)
    Unicycle(Pose2()).run(b, 10)
    assert b.error_code == SpinResult.TIMEOUT


def test_spin_turns_back_when_a_late_tick_let_it_overshoot() -> None:
    """A control tick late on a loaded machine: the base turned on at its last command past
    the mark (a local move at sim speed 10 ended 0.11 rad off so in CI). The spin turns back
    to the angle instead of ending off by the overshoot."""
    world = Unicycle(Pose2(0, 0, 1.0))
    b = SpinInPlace(0.8, 1.0, 0.0, SPIN_CODES)
    overshot = False
    for _ in range(600):
        v, w = b.step(Sense(now=world.t, dt=DT, pose=world.pose, obstacles=np.zeros((0, 2))))
        if b.done.is_set():
            break
        # the tick that would have slowed it 0.3 rad before the mark comes 1 s late
        late = not overshot and 0.8 - (world.pose.theta - 1.0) < 0.3
        for _ in range(20 if late else 1):
            world.pose = Pose2(0, 0, world.pose.theta + w * DT)
            world.t += DT
        if late:
            overshot = True
            assert world.pose.theta - 1.0 > 0.8 + 0.05  # past the mark
    assert overshot
    assert b.succeeded, b.error_msg
    assert abs(angle_diff(world.pose.theta, 1.8)) <= 0.02 and abs(b.turned - 0.8) <= 0.02


def _target(goal: Pose2, relative: bool, start_rotate: bool, target_rotate: bool
            ) -> LocalMoveTarget:
    return LocalMoveTarget(goal, relative, 0.02, 0.03, 0.0, start_rotate, target_rotate,
                           0.3, 1.0, TARGET_CODES, radius=0.2)


def test_local_move_target_in_map_and_base_link() -> None:
    world = Unicycle(Pose2(1.0, 1.0, 0.0))
    b = _target(Pose2(2.0, 1.5, -1.0), False, True, True)
    world.run(b, 40)
    assert b.succeeded, b.error_msg
    assert world.pose.distance(Pose2(2.0, 1.5)) <= 0.02
    assert abs(angle_diff(world.pose.theta, -1.0)) <= 0.03
    # relative to the start pose: 0.5 m to the robot's left, facing back the way it came
    world = Unicycle(Pose2(0.0, 0.0, math.pi / 2))
    b = _target(Pose2(0.0, 0.5, math.pi), True, True, True)
    world.run(b, 40)
    assert b.succeeded
    assert world.pose.distance(Pose2(-0.5, 0.0)) <= 0.02
    assert abs(angle_diff(world.pose.theta, -math.pi / 2)) <= 0.03


def test_local_move_target_backs_onto_a_target_behind_without_turning() -> None:
    world = Unicycle(Pose2(0.0, 0.0, 0.0))
    b = _target(Pose2(-0.4, 0.02, 0.0), False, False, False)
    world.run(b, 30)
    assert b.succeeded
    assert world.pose.distance(Pose2(-0.4, 0.02)) <= 0.02
    assert abs(world.pose.theta) < 0.2  # it backed up: no half turn


def test_local_move_target_collision() -> None:
    wall = np.array([[0.6, y] for y in np.linspace(-0.5, 0.5, 21)])
    world = Unicycle(Pose2(), wall)
    b = _target(Pose2(1.0, 0.0, 0.0), False, True, False)
    world.run(b, 30)
    assert b.error_code == TARGET_CODES.collision and world.pose.x < 0.45
