"""nav_msgs: Odometry, OccupancyGrid (numpy cells, MessagePack on the wire), MapMetaData, Path."""

from __future__ import annotations

import msgspec
import numpy as np

from ..message import Int8Array, Message, array_field
from .builtin_interfaces import Time
from .geometry_msgs import Pose, PoseStamped, PoseWithCovariance, TwistWithCovariance
from .std_msgs import Header


class Odometry(Message):
    __msgtype__ = "nav_msgs/Odometry"
    header: Header = msgspec.field(default_factory=Header)
    child_frame_id: str = ""
    pose: PoseWithCovariance = msgspec.field(default_factory=PoseWithCovariance)
    twist: TwistWithCovariance = msgspec.field(default_factory=TwistWithCovariance)


class MapMetaData(Message):
    __msgtype__ = "nav_msgs/MapMetaData"
    map_load_time: Time = msgspec.field(default_factory=Time)
    resolution: float = 0.0
    width: int = 0
    height: int = 0
    origin: Pose = msgspec.field(default_factory=Pose)


class OccupancyGrid(Message):
    """A 2-D grid map, row-major from the origin; cells -1 unknown, 0 free .. 100 occupied."""

    __msgtype__ = "nav_msgs/OccupancyGrid"
    __bulk__ = True
    header: Header = msgspec.field(default_factory=Header)
    info: MapMetaData = msgspec.field(default_factory=MapMetaData)
    data: Int8Array = array_field(Int8Array)

    def grid(self) -> np.ndarray:
        """The cells as a (height, width) int8 view, without a copy."""
        return np.asarray(self.data).reshape(self.info.height, self.info.width)


class Path(Message):
    __msgtype__ = "nav_msgs/Path"
    header: Header = msgspec.field(default_factory=Header)
    poses: list[PoseStamped] = msgspec.field(default_factory=list)
