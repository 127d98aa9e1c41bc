"""zenros_msgs for the mapping service (``services/slam``; docs/mapping.md).

The mapping node (``slam``, in the robot's namespace) is idle until started. While it maps it
owns ``map`` (nav_msgs/OccupancyGrid, latched) and ``map -> odom`` on ``/tf``; nav follows
that map and that transform instead of its own map server and localiser (nav's mapping mode).

- ``slam/start`` (StartMapping): start a new map, or extend a saved one (``map_name``).
- ``slam/stop`` (StopMapping): stop; what was not saved is dropped.
- ``slam/save`` (SaveSlamMap): save the map being built into the maps store under ``name``
  (map YAML + PGM + PNG, and the pose graph beside it so ``/map/update`` can continue it).
- ``slam/state`` (MappingState, latched): what the mapping node is doing, at every change
  and at 1 Hz while mapping.
- ``slam/track`` (nav_msgs/Path, latched): the corrected trajectory (one pose per graph node).
- ``slam/pose`` (geometry_msgs/PoseWithCovarianceStamped): the robot in the map being built.
- ``explore`` (action Explore, served by the ``explore`` node, ``services/explore``): frontier
  exploration on the map being built, with nav's planner and controller.

Nav's side (served by nav):

- ``nav/set_mapping_mode`` (SetMappingMode): ``enable`` true hands ``map`` and ``map -> odom``
  to the mapping node (nav follows the ``map`` topic for its costmaps and the TF for its pose;
  refused with CONFLICT while a goal is driven); false takes them back (nav reloads its map,
  or ``map_name`` with the robot at ``map_to_odom`` in it, the transform the mapping node had).
- ``map_server/save_grid`` (SaveGrid): store an occupancy grid as a map in the maps folder
  (YAML + PGM + PNG, as map_saver writes them), so it is listed, served and navigable.

slam_toolbox's own names (``slam_toolbox/save_map``, ``serialize_map``, ``deserialize_map``,
``pause_new_measurements``, ``reset``) are offered beside these by the mapping node.
"""

from __future__ import annotations

import msgspec

from ...message import Message, define_action, define_service
from ..geometry_msgs import Pose2D
from ..nav_msgs import OccupancyGrid
from ..std_msgs import Header

__all__ = [
    "Explore",
    "ExploreFeedback",
    "ExploreGoal",
    "ExploreResult",
    "MappingState",
    "SaveGrid",
    "SaveGridRequest",
    "SaveGridResponse",
    "SaveSlamMap",
    "SaveSlamMapRequest",
    "SaveSlamMapResponse",
    "SetMappingMode",
    "SetMappingModeRequest",
    "SetMappingModeResponse",
    "StartMapping",
    "StartMappingRequest",
    "StartMappingResponse",
    "StopMapping",
    "StopMappingRequest",
    "StopMappingResponse",
]


class MappingState(Message):
    """What the mapping node is doing, latched on ``slam/state``.

    ``state``: ``idle``, ``starting``, ``mapping``, ``stopping``. ``mode``: ``laser`` (driven
    by hand) or ``explore``. ``map_name``: the saved map being extended (``/map/update``),
    empty for a new map. ``pose`` is the robot in the map being built; ``width``/``height``/
    ``resolution``/``origin`` describe the current grid; ``area_m2`` the known (free or
    occupied) area. ``message`` says why the last start or stop failed, if one did.
    """

    __msgtype__ = "zenros_msgs/MappingState"
    header: Header = msgspec.field(default_factory=Header)
    state: str = "idle"
    mode: str = ""
    map_name: str = ""
    scans: int = 0
    nodes: int = 0
    loop_closures: int = 0
    width: int = 0
    height: int = 0
    resolution: float = 0.0
    origin: Pose2D = msgspec.field(default_factory=Pose2D)
    area_m2: float = 0.0
    pose: Pose2D = msgspec.field(default_factory=Pose2D)
    message: str = ""


class StartMappingRequest(Message):
    """``mode``: ``laser`` (the default) or ``explore`` (recorded in the state; exploration
    itself is the ``explore`` action). ``map_name``: extend this saved map (its pose graph,
    or its grid as a prior) instead of starting empty. ``initial_pose`` with
    ``use_initial_pose``: where the robot stands in that map (a nav point's pose); without
    it the robot is taken to stand at the saved graph's last pose."""

    __msgtype__ = "zenros_msgs/StartMappingRequest"
    mode: str = "laser"
    map_name: str = ""
    initial_pose: Pose2D = msgspec.field(default_factory=Pose2D)
    use_initial_pose: bool = False


class StartMappingResponse(Message):
    """``code`` is a `ResultCode`; ``message`` says why when it is not OK."""

    __msgtype__ = "zenros_msgs/StartMappingResponse"
    code: int = 0
    message: str = ""


StartMapping = define_service("zenros_msgs/StartMapping", StartMappingRequest,
                              StartMappingResponse)


class StopMappingRequest(Message):
    __msgtype__ = "zenros_msgs/StopMappingRequest"


class StopMappingResponse(Message):
    __msgtype__ = "zenros_msgs/StopMappingResponse"
    code: int = 0
    message: str = ""


StopMapping = define_service("zenros_msgs/StopMapping", StopMappingRequest,
                             StopMappingResponse)


class SaveSlamMapRequest(Message):
    """``name``: a map name (no path); ``type``: ``floor`` or ``elevator``; ``levels``: the
    floors the map serves (docs/robot-api.md §5, POST /map/current_map_image)."""

    __msgtype__ = "zenros_msgs/SaveSlamMapRequest"
    name: str = ""
    type: str = "floor"
    levels: list[int] = msgspec.field(default_factory=list)


class SaveSlamMapResponse(Message):
    __msgtype__ = "zenros_msgs/SaveSlamMapResponse"
    code: int = 0
    message: str = ""
    name: str = ""


SaveSlamMap = define_service("zenros_msgs/SaveSlamMap", SaveSlamMapRequest,
                             SaveSlamMapResponse)


class ExploreGoal(Message):
    """``return_to_start``: drive back to where exploring started when no frontier is left
    (m-explore-ros2's ``return_to_init``). ``min_frontier_size`` in metres (explore_lite 0.5)."""

    __msgtype__ = "zenros_msgs/ExploreGoal"
    return_to_start: bool = True
    min_frontier_size: float = 0.5
    progress_timeout: float = 30.0


class ExploreResult(Message):
    """``error_code`` 0 when no frontier is left (and the robot is back, if asked)."""

    __msgtype__ = "zenros_msgs/ExploreResult"
    error_code: int = 0
    error_msg: str = ""
    explored_area_m2: float = 0.0
    goals_reached: int = 0
    goals_failed: int = 0


class ExploreFeedback(Message):
    """``stage``: ``exploring``, ``returning``. ``target``: the frontier being driven to."""

    __msgtype__ = "zenros_msgs/ExploreFeedback"
    stage: str = "exploring"
    explored_area_m2: float = 0.0
    frontiers_left: int = 0
    target: Pose2D = msgspec.field(default_factory=Pose2D)


Explore = define_action("zenros_msgs/Explore", ExploreGoal, ExploreResult, ExploreFeedback)


class SetMappingModeRequest(Message):
    """``enable``: hand the map and ``map -> odom`` to the mapping node (true) or take them
    back (false). On false, ``map_name`` (when set) is the map to navigate on next and
    ``map_to_odom`` the robot's odometry frame in it (``use_map_to_odom``), so nav goes on
    from where mapping left the robot without relocalising."""

    __msgtype__ = "zenros_msgs/SetMappingModeRequest"
    enable: bool = False
    map_name: str = ""
    map_to_odom: Pose2D = msgspec.field(default_factory=Pose2D)
    use_map_to_odom: bool = False


class SetMappingModeResponse(Message):
    __msgtype__ = "zenros_msgs/SetMappingModeResponse"
    code: int = 0
    message: str = ""


SetMappingMode = define_service("zenros_msgs/SetMappingMode", SetMappingModeRequest,
                                SetMappingModeResponse)


class SaveGridRequest(Message):
    """Store ``grid`` as the map ``name`` (a name, never a path). ``type``/``levels`` as in
    `MapInfo`. ``map_to_odom`` (with ``use_map_to_odom``) is where the robot's odometry
    frame was in this map when it was saved (kept with the map, for navigating on it next)."""

    __msgtype__ = "zenros_msgs/SaveGridRequest"
    name: str = ""
    grid: OccupancyGrid = msgspec.field(default_factory=OccupancyGrid)
    type: str = "floor"
    levels: list[int] = msgspec.field(default_factory=list)
    map_to_odom: Pose2D = msgspec.field(default_factory=Pose2D)
    use_map_to_odom: bool = False


class SaveGridResponse(Message):
    __msgtype__ = "zenros_msgs/SaveGridResponse"
    code: int = 0
    message: str = ""
    name: str = ""


SaveGrid = define_service("zenros_msgs/SaveGrid", SaveGridRequest, SaveGridResponse)
