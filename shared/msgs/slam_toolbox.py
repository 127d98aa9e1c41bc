"""slam_toolbox's services, with its ROS names and fields (slam_toolbox srvs/), as the mapping
node (``services/slam``) offers them under ``slam_toolbox/...``.

- ``slam_toolbox/save_map`` (SaveMap): save the map being built as the map ``name.data``
  (saved through nav's map store, as map_saver_cli would); ``result`` 0 ok, 1 no map yet,
  255 failed.
- ``slam_toolbox/serialize_map`` (SerializePoseGraph): write the pose graph to
  ``$ZENROS_HOME/slam/<filename>.posegraph``; ``result`` 0 ok, 255 failed.
- ``slam_toolbox/deserialize_map`` (DeserializePoseGraph): load a saved pose graph and map on
  from it (``match_type`` 1 at its first node, 2 at ``initial_pose``, 3 localise at
  ``initial_pose``).
- ``slam_toolbox/pause_new_measurements`` (Pause): toggle; ``status`` is the new state.
- ``slam_toolbox/reset`` (Reset): drop the graph and the map; ``pause_new_measurements`` sets
  (not toggles) the pause.
"""

from __future__ import annotations

import msgspec

from ..message import Message, define_service
from .geometry_msgs import Pose2D
from .std_msgs import String

__all__ = [
    "DeserializePoseGraph",
    "DeserializePoseGraphRequest",
    "DeserializePoseGraphResponse",
    "Pause",
    "PauseRequest",
    "PauseResponse",
    "Reset",
    "ResetRequest",
    "ResetResponse",
    "SaveMap",
    "SaveMapRequest",
    "SaveMapResponse",
    "SerializePoseGraph",
    "SerializePoseGraphRequest",
    "SerializePoseGraphResponse",
]


class SaveMapRequest(Message):
    __msgtype__ = "slam_toolbox/SaveMapRequest"
    name: String = msgspec.field(default_factory=String)


class SaveMapResponse(Message):
    __msgtype__ = "slam_toolbox/SaveMapResponse"
    RESULT_SUCCESS = 0
    RESULT_NO_MAP_RECEIEVD = 1  # slam_toolbox's spelling
    RESULT_UNDEFINED_FAILURE = 255
    result: int = 0


class SerializePoseGraphRequest(Message):
    __msgtype__ = "slam_toolbox/SerializePoseGraphRequest"
    filename: str = ""


class SerializePoseGraphResponse(Message):
    __msgtype__ = "slam_toolbox/SerializePoseGraphResponse"
    RESULT_SUCCESS = 0
    RESULT_FAILED_TO_WRITE_FILE = 255
    result: int = 0


class DeserializePoseGraphRequest(Message):
    __msgtype__ = "slam_toolbox/DeserializePoseGraphRequest"
    UNSET = 0
    START_AT_FIRST_NODE = 1
    START_AT_GIVEN_POSE = 2
    LOCALIZE_AT_POSE = 3
    filename: str = ""
    match_type: int = 0
    initial_pose: Pose2D = msgspec.field(default_factory=Pose2D)


class DeserializePoseGraphResponse(Message):
    __msgtype__ = "slam_toolbox/DeserializePoseGraphResponse"


class PauseRequest(Message):
    __msgtype__ = "slam_toolbox/PauseRequest"


class PauseResponse(Message):
    __msgtype__ = "slam_toolbox/PauseResponse"
    status: bool = False


class ResetRequest(Message):
    __msgtype__ = "slam_toolbox/ResetRequest"
    pause_new_measurements: bool = False


class ResetResponse(Message):
    __msgtype__ = "slam_toolbox/ResetResponse"
    RESULT_SUCCESS = 0
    result: int = 0


SaveMap = define_service("slam_toolbox/SaveMap", SaveMapRequest, SaveMapResponse)
SerializePoseGraph = define_service("slam_toolbox/SerializePoseGraph",
                                    SerializePoseGraphRequest, SerializePoseGraphResponse)
DeserializePoseGraph = define_service("slam_toolbox/DeserializePoseGraph",
                                      DeserializePoseGraphRequest, DeserializePoseGraphResponse)
Pause = define_service("slam_toolbox/Pause", PauseRequest, PauseResponse)
Reset = define_service("slam_toolbox/Reset", ResetRequest, ResetResponse)
