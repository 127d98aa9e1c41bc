"""tf2_msgs: TFMessage, the payload of /tf and /tf_static."""

from __future__ import annotations

import msgspec

from ..message import Message
from .geometry_msgs import TransformStamped


class TFMessage(Message):
    __msgtype__ = "tf2_msgs/TFMessage"
    transforms: list[TransformStamped] = msgspec.field(default_factory=list)
