"""PoseReader and PoseStream: a pose part read, or built, once while messages share it."""

from __future__ import annotations

import math

import pytest
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import Point, Pose, Quaternion
from zenros.se2 import Pose2
from zenros.services.nav.actions.convert import (
    PoseReader,
    PoseStream,
    pose2_to_msg,
    pose_with_covariance,
    transform_stamped,
)


def test_a_shared_pose_part_is_read_once_and_a_new_one_again() -> None:
    read = PoseReader()
    part = pose2_to_msg(Pose2(1.0, 2.0, 0.5))
    first = read(part)
    assert first == pytest.approx(Pose2(1.0, 2.0, 0.5))
    assert read(part) is first  # the same part: the pose read before
    other = read(pose2_to_msg(Pose2(1.0, 2.0, 0.5)))  # equal, but another message's
    assert other == first and other is not first


def test_a_bad_pose_raises_every_time_and_is_not_remembered() -> None:
    read = PoseReader()
    good = read(pose2_to_msg(Pose2(0.0, 0.0, 0.0)))
    bad = Pose(position=Point(x=math.nan), orientation=Quaternion(w=1.0))
    for _ in range(2):
        with pytest.raises(ValueError, match="non-finite"):
            read(bad)
    zero = Pose(orientation=Quaternion(w=0.0))
    with pytest.raises(ValueError, match="zero quaternion"):
        read(zero)
    assert read(pose2_to_msg(Pose2(0.0, 0.0, 0.0))) == good


def test_a_pose_stream_stamps_the_same_pose_anew_on_the_part_already_built() -> None:
    """robot_pose and map -> odom at rest: each message has its own stamp and shares the
    pose (or transform) part while the pose stays; another pose builds a new one."""
    poses = PoseStream(0.0025, 0.003)
    at = Pose2(1.0, 2.0, 0.5)
    one, two = (poses.pose_with_covariance(Pose2(*at), Time(sec=s)) for s in (1, 2))
    assert (one.header.stamp.sec, two.header.stamp.sec) == (1, 2)
    assert one.pose is two.pose and one.header.frame_id == "map"
    ref = pose_with_covariance(at, Time(sec=1), 0.0025, 0.003)
    assert one == ref
    moved = poses.pose_with_covariance(Pose2(1.5, 2.0, 0.5), Time(sec=3))
    assert moved.pose is not two.pose and moved.pose.pose.position.x == 1.5
    links = [poses.transform_stamped(at, Time(sec=s), "map", "odom") for s in (1, 2)]
    assert links[0].transform is links[1].transform and links[1].header.stamp.sec == 2
    assert links[0] == transform_stamped(at, Time(sec=1), "map", "odom")
    other = poses.transform_stamped(at, Time(sec=2), "odom", "base_link")
    assert other.transform is not links[0].transform and other.child_frame_id == "base_link"
