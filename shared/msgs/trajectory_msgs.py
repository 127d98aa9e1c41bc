"""trajectory_msgs: made by `zenros interface generate` from its .msg files."""

from __future__ import annotations

import msgspec

from ..message import Float64Array, Message, array_field
from .builtin_interfaces import Duration
from .geometry_msgs import Transform, Twist
from .std_msgs import Header

__all__ = [
    "JointTrajectory",
    "JointTrajectoryPoint",
    "MultiDOFJointTrajectory",
    "MultiDOFJointTrajectoryPoint",
]


class JointTrajectoryPoint(Message):
    """Each trajectory point specifies either positions[, velocities[, accelerations]]
    or positions[, effort] for the trajectory to be executed.
    All specified values are in the same order as the joint names in JointTrajectory.msg.
    """

    __msgtype__ = "trajectory_msgs/JointTrajectoryPoint"
    positions: Float64Array = array_field(Float64Array)
    velocities: Float64Array = array_field(Float64Array)
    accelerations: Float64Array = array_field(Float64Array)
    effort: Float64Array = array_field(Float64Array)
    time_from_start: Duration = msgspec.field(default_factory=Duration)


class JointTrajectory(Message):
    """The header is used to specify the coordinate frame and the reference time for
    the trajectory durations
    """

    __msgtype__ = "trajectory_msgs/JointTrajectory"
    header: Header = msgspec.field(default_factory=Header)
    joint_names: list[str] = msgspec.field(default_factory=list)
    points: list[JointTrajectoryPoint] = msgspec.field(default_factory=list)


class MultiDOFJointTrajectoryPoint(Message):
    """Each multi-dof joint can specify a transform (up to 6 DOF)."""

    __msgtype__ = "trajectory_msgs/MultiDOFJointTrajectoryPoint"
    transforms: list[Transform] = msgspec.field(default_factory=list)
    velocities: list[Twist] = msgspec.field(default_factory=list)
    accelerations: list[Twist] = msgspec.field(default_factory=list)
    time_from_start: Duration = msgspec.field(default_factory=Duration)


class MultiDOFJointTrajectory(Message):
    """The header is used to specify the coordinate frame and the reference time for the
    trajectory durations
    """

    __msgtype__ = "trajectory_msgs/MultiDOFJointTrajectory"
    header: Header = msgspec.field(default_factory=Header)
    joint_names: list[str] = msgspec.field(default_factory=list)
    points: list[MultiDOFJointTrajectoryPoint] = msgspec.field(default_factory=list)
