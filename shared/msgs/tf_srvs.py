"""Services of the tf buffer server (`lookup_transform`, `can_transform`, `frames`), and
tf2's `TF2Error`.

`LookupTransform` keeps the layout of tf2_msgs' LookupTransform action (goal as the request,
result as the response), so tf2 BufferClient-shaped JSON decodes as is. Failures come back
in ``error`` with tf2's codes, never as a service error.
"""

from __future__ import annotations

import msgspec

from ..message import Message, define_service
from .builtin_interfaces import Duration, Time
from .geometry_msgs import TransformStamped

__all__ = [
    "CanTransform",
    "CanTransformRequest",
    "CanTransformResponse",
    "FrameInfo",
    "Frames",
    "FramesRequest",
    "FramesResponse",
    "LookupTransform",
    "LookupTransformRequest",
    "LookupTransformResponse",
    "TF2Error",
]


class TF2Error(Message):
    """What went wrong in a remote lookup (tf2_msgs/TF2Error): a code and tf2's message."""

    __msgtype__ = "tf2_msgs/TF2Error"
    error: int = 0
    error_string: str = ""

    NO_ERROR = 0
    LOOKUP_ERROR = 1
    CONNECTIVITY_ERROR = 2
    EXTRAPOLATION_ERROR = 3
    INVALID_ARGUMENT_ERROR = 4
    TIMEOUT_ERROR = 5
    TRANSFORM_ERROR = 6


class LookupTransformRequest(Message):
    """``T_target_source`` at ``source_time``; with ``advanced``, time travel: ``source`` at
    ``source_time`` seen from ``target`` at ``target_time`` through ``fixed_frame``.

    Times of 0 mean "latest"; ``timeout`` is how long the server may wait for the data.
    """

    __msgtype__ = "tf2_msgs/LookupTransformRequest"
    target_frame: str = ""
    source_frame: str = ""
    source_time: Time = msgspec.field(default_factory=Time)
    timeout: Duration = msgspec.field(default_factory=Duration)
    target_time: Time = msgspec.field(default_factory=Time)
    fixed_frame: str = ""
    advanced: bool = False


class LookupTransformResponse(Message):
    """The transform, or (``error.error != 0``) why there is none."""

    __msgtype__ = "tf2_msgs/LookupTransformResponse"
    transform: TransformStamped = msgspec.field(default_factory=TransformStamped)
    error: TF2Error = msgspec.field(default_factory=TF2Error)


class CanTransformRequest(Message):
    """Whether `LookupTransform` with the same fields would succeed."""

    __msgtype__ = "zenros_tf/CanTransformRequest"
    target_frame: str = ""
    source_frame: str = ""
    source_time: Time = msgspec.field(default_factory=Time)
    timeout: Duration = msgspec.field(default_factory=Duration)
    target_time: Time = msgspec.field(default_factory=Time)
    fixed_frame: str = ""
    advanced: bool = False


class CanTransformResponse(Message):
    """The answer, and tf2's explanation when it is false."""

    __msgtype__ = "zenros_tf/CanTransformResponse"
    can_transform: bool = False
    error_string: str = ""


class FramesRequest(Message):
    __msgtype__ = "zenros_tf/FramesRequest"


class FrameInfo(Message):
    """One child frame as the server sees it (tf_monitor's figures).

    ``rate`` is links received per second over the server's window (0 for statics),
    ``delay``/``max_delay`` are the server's clock minus the stamp on arrival (seconds).
    """

    __msgtype__ = "zenros_tf/FrameInfo"
    frame_id: str = ""
    parent: str = ""
    authority: str = ""
    static: bool = False
    rate: float = 0.0
    most_recent: Time = msgspec.field(default_factory=Time)
    delay: float = 0.0
    max_delay: float = 0.0
    count: int = 0


class FramesResponse(Message):
    """Every child frame (sorted), the server's time, and tf2's ``allFramesAsYAML``."""

    __msgtype__ = "zenros_tf/FramesResponse"
    frames: list[FrameInfo] = msgspec.field(default_factory=list)
    stamp: Time = msgspec.field(default_factory=Time)
    yaml: str = ""


LookupTransform = define_service(
    "tf2_msgs/LookupTransform", LookupTransformRequest, LookupTransformResponse
)
CanTransform = define_service("zenros_tf/CanTransform", CanTransformRequest, CanTransformResponse)
Frames = define_service("zenros_tf/Frames", FramesRequest, FramesResponse)
