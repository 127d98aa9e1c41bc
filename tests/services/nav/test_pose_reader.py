"""PoseReader: the pose part of a message read once while messages share it."""

from __future__ import annotations

import math

import pytest
from zenros.msgs.geometry_msgs import Point, Pose, Quaternion
from zenros.se2 import Pose2
from zenros.services.nav.actions.convert import PoseReader, pose2_to_msg


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
