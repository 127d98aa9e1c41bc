"""zenros.tf: tf2's frame tree over time: math, `Buffer`, conversions, and the transport.

``Buffer`` keeps each link's history (10 s by default), interpolates between samples
(linear + slerp), holds static links, and answers ``lookup_transform`` /
``can_transform`` with tf2's semantics and exceptions, much faster than a tree walk.
`TransformBroadcaster`, `StaticTransformBroadcaster` and `TransformListener` carry links
over ``/tf`` and latched ``/tf_static`` through a node; `BufferClient` asks the tf service.
"""

from ..errors import (
    BackwardExtrapolationException,
    ConnectivityException,
    ExtrapolationException,
    ForwardExtrapolationException,
    InvalidArgumentException,
    LookupException,
    NoDataForExtrapolationException,
    TimeoutException,
    TransformException,
)
from .broadcaster import StaticTransformBroadcaster, TransformBroadcaster
from .buffer import Buffer
from .client import BufferClient
from .codes import error_code, error_msg, exception_from_error
from .convert import (
    matrix_from_msg,
    msg_from_matrix,
    pose_from_msg,
    pose_to_msg,
    quaternion_from_msg,
    quaternion_to_msg,
    transform_from_msg,
    transform_stamped,
    transform_to_msg,
    yaw_from_msg,
    yaw_to_msg,
)
from .listener import DEFAULT_AUTHORITY, ClockJumpGuard, TransformListener
from .matrix import (
    euler_from_matrix,
    euler_matrix,
    inverse_matrix,
    quaternion_from_matrix,
    quaternion_matrix,
    transform_from_matrix,
    transform_matrix,
    transform_points,
    transform_vectors,
)
from .quaternion import (
    IDENTITY_QUATERNION,
    angle_between,
    euler_from_quaternion,
    normalize_angle,
    normalize_angle_positive,
    quaternion_conjugate,
    quaternion_from_axis_angle,
    quaternion_from_euler,
    quaternion_from_yaw,
    quaternion_inverse,
    quaternion_multiply,
    quaternion_normalize,
    quaternion_slerp,
    quaternion_to_axis_angle,
    rotate_vector,
    shortest_angular_distance,
    yaw_from_quaternion,
)
from .rigid import IDENTITY, Tf, compose, interpolate, inverse
from .spec import link_from_numbers, parse_link
from .stamped import (
    do_transform,
    do_transform_point,
    do_transform_pose,
    do_transform_pose_stamped,
    do_transform_quaternion,
    do_transform_vector3,
    register_transformable,
)
from .stamps import LATEST, from_ns, to_ns
from .store import DEFAULT_CACHE_TIME
from .tree import frames_as_dot, frames_as_tree, frames_from_yaml

__all__ = [
    "DEFAULT_AUTHORITY",
    "DEFAULT_CACHE_TIME",
    "IDENTITY",
    "IDENTITY_QUATERNION",
    "LATEST",
    "BackwardExtrapolationException",
    "Buffer",
    "BufferClient",
    "ClockJumpGuard",
    "ConnectivityException",
    "ExtrapolationException",
    "ForwardExtrapolationException",
    "InvalidArgumentException",
    "LookupException",
    "NoDataForExtrapolationException",
    "StaticTransformBroadcaster",
    "Tf",
    "TimeoutException",
    "TransformBroadcaster",
    "TransformException",
    "TransformListener",
    "angle_between",
    "compose",
    "do_transform",
    "do_transform_point",
    "do_transform_pose",
    "do_transform_pose_stamped",
    "do_transform_quaternion",
    "do_transform_vector3",
    "error_code",
    "error_msg",
    "euler_from_matrix",
    "euler_from_quaternion",
    "euler_matrix",
    "exception_from_error",
    "frames_as_dot",
    "frames_as_tree",
    "frames_from_yaml",
    "from_ns",
    "interpolate",
    "inverse",
    "inverse_matrix",
    "link_from_numbers",
    "matrix_from_msg",
    "msg_from_matrix",
    "normalize_angle",
    "normalize_angle_positive",
    "parse_link",
    "pose_from_msg",
    "pose_to_msg",
    "quaternion_conjugate",
    "quaternion_from_axis_angle",
    "quaternion_from_euler",
    "quaternion_from_matrix",
    "quaternion_from_msg",
    "quaternion_from_yaw",
    "quaternion_inverse",
    "quaternion_matrix",
    "quaternion_multiply",
    "quaternion_normalize",
    "quaternion_slerp",
    "quaternion_to_axis_angle",
    "quaternion_to_msg",
    "register_transformable",
    "rotate_vector",
    "shortest_angular_distance",
    "to_ns",
    "transform_from_matrix",
    "transform_from_msg",
    "transform_matrix",
    "transform_points",
    "transform_stamped",
    "transform_to_msg",
    "transform_vectors",
    "yaw_from_msg",
    "yaw_from_quaternion",
    "yaw_to_msg",
]
