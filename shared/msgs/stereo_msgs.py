"""stereo_msgs: made by `zenros interface generate` from its .msg files."""

from __future__ import annotations

import msgspec

from ..message import Message
from .sensor_msgs import Image, RegionOfInterest
from .std_msgs import Header

__all__ = ["DisparityImage"]


class DisparityImage(Message):
    """Separate header for compatibility with current TimeSynchronizer.
    Likely to be removed in a later release, use image.header instead.
    """

    __msgtype__ = "stereo_msgs/DisparityImage"
    header: Header = msgspec.field(default_factory=Header)
    image: Image = msgspec.field(default_factory=Image)
    f: float = 0.0
    t: float = 0.0
    valid_window: RegionOfInterest = msgspec.field(default_factory=RegionOfInterest)
    min_disparity: float = 0.0
    max_disparity: float = 0.0
    delta_d: float = 0.0
