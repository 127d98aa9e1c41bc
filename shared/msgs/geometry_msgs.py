"""geometry_msgs: points, vectors, quaternions, poses, transforms, twists, polygons."""

from __future__ import annotations

import msgspec

from ..message import Float64Array, Message, array_field
from .std_msgs import Header


class Vector3(Message):
    __msgtype__ = "geometry_msgs/Vector3"
    x: float = 0.0
    y: float = 0.0
    z: float = 0.0


class Vector3Stamped(Message):
    __msgtype__ = "geometry_msgs/Vector3Stamped"
    header: Header = msgspec.field(default_factory=Header)
    vector: Vector3 = msgspec.field(default_factory=Vector3)


class Point(Message):
    __msgtype__ = "geometry_msgs/Point"
    x: float = 0.0
    y: float = 0.0
    z: float = 0.0


class Point32(Message):
    __msgtype__ = "geometry_msgs/Point32"
    x: float = 0.0
    y: float = 0.0
    z: float = 0.0


class PointStamped(Message):
    __msgtype__ = "geometry_msgs/PointStamped"
    header: Header = msgspec.field(default_factory=Header)
    point: Point = msgspec.field(default_factory=Point)


class Quaternion(Message):
    """A rotation; the default is the identity (w = 1), as in ROS."""

    __msgtype__ = "geometry_msgs/Quaternion"
    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    w: float = 1.0


class QuaternionStamped(Message):
    __msgtype__ = "geometry_msgs/QuaternionStamped"
    header: Header = msgspec.field(default_factory=Header)
    quaternion: Quaternion = msgspec.field(default_factory=Quaternion)


class Pose(Message):
    __msgtype__ = "geometry_msgs/Pose"
    position: Point = msgspec.field(default_factory=Point)
    orientation: Quaternion = msgspec.field(default_factory=Quaternion)


class Pose2D(Message):
    __msgtype__ = "geometry_msgs/Pose2D"
    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0


class PoseStamped(Message):
    __msgtype__ = "geometry_msgs/PoseStamped"
    header: Header = msgspec.field(default_factory=Header)
    pose: Pose = msgspec.field(default_factory=Pose)


def _cov() -> Float64Array:
    c: Float64Array = array_field(Float64Array, [0.0] * 36)
    return c


class PoseWithCovariance(Message):
    __msgtype__ = "geometry_msgs/PoseWithCovariance"
    pose: Pose = msgspec.field(default_factory=Pose)
    covariance: Float64Array = _cov()


class PoseWithCovarianceStamped(Message):
    __msgtype__ = "geometry_msgs/PoseWithCovarianceStamped"
    header: Header = msgspec.field(default_factory=Header)
    pose: PoseWithCovariance = msgspec.field(default_factory=PoseWithCovariance)


class PoseArray(Message):
    __msgtype__ = "geometry_msgs/PoseArray"
    header: Header = msgspec.field(default_factory=Header)
    poses: list[Pose] = msgspec.field(default_factory=list)


class Transform(Message):
    __msgtype__ = "geometry_msgs/Transform"
    translation: Vector3 = msgspec.field(default_factory=Vector3)
    rotation: Quaternion = msgspec.field(default_factory=Quaternion)


class TransformStamped(Message):
    __msgtype__ = "geometry_msgs/TransformStamped"
    header: Header = msgspec.field(default_factory=Header)
    child_frame_id: str = ""
    transform: Transform = msgspec.field(default_factory=Transform)


class Twist(Message):
    __msgtype__ = "geometry_msgs/Twist"
    linear: Vector3 = msgspec.field(default_factory=Vector3)
    angular: Vector3 = msgspec.field(default_factory=Vector3)


class TwistStamped(Message):
    __msgtype__ = "geometry_msgs/TwistStamped"
    header: Header = msgspec.field(default_factory=Header)
    twist: Twist = msgspec.field(default_factory=Twist)


class TwistWithCovariance(Message):
    __msgtype__ = "geometry_msgs/TwistWithCovariance"
    twist: Twist = msgspec.field(default_factory=Twist)
    covariance: Float64Array = _cov()


class TwistWithCovarianceStamped(Message):
    __msgtype__ = "geometry_msgs/TwistWithCovarianceStamped"
    header: Header = msgspec.field(default_factory=Header)
    twist: TwistWithCovariance = msgspec.field(default_factory=TwistWithCovariance)


class Polygon(Message):
    __msgtype__ = "geometry_msgs/Polygon"
    points: list[Point32] = msgspec.field(default_factory=list)


class PolygonStamped(Message):
    __msgtype__ = "geometry_msgs/PolygonStamped"
    header: Header = msgspec.field(default_factory=Header)
    polygon: Polygon = msgspec.field(default_factory=Polygon)
