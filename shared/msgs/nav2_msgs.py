"""nav2_msgs: Nav2's actions and services with Nav2's field names and error codes.

Fields follow Nav2 (main, 2024-2025; specs/tf-nav.md Part D4). Where Nav2 changed a field
between releases the Jazzy form is kept: `NavigateThroughPosesGoal.poses` is a plain
``PoseStamped[]`` (newer Nav2 wraps it in ``nav_msgs/Goals``). Error-code constants are
class attributes of the result (``NavigateToPoseResult.TIMEOUT``), as in the generated
ROS classes. The docking actions carry opennav_docking's fields.
"""

from __future__ import annotations

from typing import Annotated

import msgspec

from ..message import Message, define_action, define_service
from .builtin_interfaces import Duration
from .geometry_msgs import Point, PoseStamped
from .nav_msgs import OccupancyGrid, Path

__all__ = [
    "BackUp",
    "BackUpFeedback",
    "BackUpGoal",
    "BackUpResult",
    "ClearEntireCostmap",
    "ClearEntireCostmapRequest",
    "ClearEntireCostmapResponse",
    "ComputePathToPose",
    "ComputePathToPoseFeedback",
    "ComputePathToPoseGoal",
    "ComputePathToPoseResult",
    "DockRobot",
    "DockRobotFeedback",
    "DockRobotGoal",
    "DockRobotResult",
    "DriveOnHeading",
    "DriveOnHeadingFeedback",
    "DriveOnHeadingGoal",
    "DriveOnHeadingResult",
    "FollowPath",
    "FollowPathFeedback",
    "FollowPathGoal",
    "FollowPathResult",
    "FollowWaypoints",
    "FollowWaypointsFeedback",
    "FollowWaypointsGoal",
    "FollowWaypointsResult",
    "LoadMap",
    "LoadMapRequest",
    "LoadMapResponse",
    "ManageLifecycleNodes",
    "ManageLifecycleNodesRequest",
    "ManageLifecycleNodesResponse",
    "NavigateThroughPoses",
    "NavigateThroughPosesFeedback",
    "NavigateThroughPosesGoal",
    "NavigateThroughPosesResult",
    "NavigateToPose",
    "NavigateToPoseFeedback",
    "NavigateToPoseGoal",
    "NavigateToPoseResult",
    "SaveMap",
    "SaveMapRequest",
    "SaveMapResponse",
    "Spin",
    "SpinFeedback",
    "SpinGoal",
    "SpinResult",
    "UndockRobot",
    "UndockRobotFeedback",
    "UndockRobotGoal",
    "UndockRobotResult",
    "WaypointStatus",
]

UInt8 = Annotated[int, msgspec.Meta(ge=0, le=255)]
UInt16 = Annotated[int, msgspec.Meta(ge=0, le=0xFFFF)]
UInt32 = Annotated[int, msgspec.Meta(ge=0, le=0xFFFFFFFF)]
Int16 = Annotated[int, msgspec.Meta(ge=-0x8000, le=0x7FFF)]


# ------------------------------------------------------------------ shared messages


class WaypointStatus(Message):
    """The outcome of one waypoint of NavigateThroughPoses / FollowWaypoints."""

    __msgtype__ = "nav2_msgs/WaypointStatus"
    PENDING = 0
    COMPLETED = 1
    SKIPPED = 2
    FAILED = 3
    waypoint_status: UInt8 = 0
    waypoint_index: UInt32 = 0
    waypoint_pose: PoseStamped = msgspec.field(default_factory=PoseStamped)
    error_code: UInt16 = 0
    error_msg: str = ""


# ------------------------------------------------------------------ NavigateToPose


class NavigateToPoseGoal(Message):
    __msgtype__ = "nav2_msgs/NavigateToPoseGoal"
    pose: PoseStamped = msgspec.field(default_factory=PoseStamped)
    behavior_tree: str = ""


class NavigateToPoseResult(Message):
    __msgtype__ = "nav2_msgs/NavigateToPoseResult"
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 9000
    FAILED_TO_LOAD_BEHAVIOR_TREE = 9001
    TF_ERROR = 9002
    TIMEOUT = 9003
    error_code: UInt16 = 0
    error_msg: str = ""


class NavigateToPoseFeedback(Message):
    __msgtype__ = "nav2_msgs/NavigateToPoseFeedback"
    current_pose: PoseStamped = msgspec.field(default_factory=PoseStamped)
    navigation_time: Duration = msgspec.field(default_factory=Duration)
    estimated_time_remaining: Duration = msgspec.field(default_factory=Duration)
    number_of_recoveries: Int16 = 0
    distance_remaining: float = 0.0
    position_tracking_error: float = 0.0
    heading_tracking_error: float = 0.0


NavigateToPose = define_action(
    "nav2_msgs/NavigateToPose", NavigateToPoseGoal, NavigateToPoseResult, NavigateToPoseFeedback
)


# ------------------------------------------------------------------ NavigateThroughPoses


class NavigateThroughPosesGoal(Message):
    __msgtype__ = "nav2_msgs/NavigateThroughPosesGoal"
    poses: list[PoseStamped] = msgspec.field(default_factory=list)
    behavior_tree: str = ""


class NavigateThroughPosesResult(Message):
    __msgtype__ = "nav2_msgs/NavigateThroughPosesResult"
    NONE = 0
    GOAL_REJECTED = 1
    SEND_GOAL_FAILURE = 2
    UNKNOWN = 9100
    FAILED_TO_LOAD_BEHAVIOR_TREE = 9101
    TF_ERROR = 9102
    TIMEOUT = 9103
    error_code: UInt16 = 0
    error_msg: str = ""
    waypoint_statuses: list[WaypointStatus] = msgspec.field(default_factory=list)


class NavigateThroughPosesFeedback(Message):
    __msgtype__ = "nav2_msgs/NavigateThroughPosesFeedback"
    current_pose: PoseStamped = msgspec.field(default_factory=PoseStamped)
    navigation_time: Duration = msgspec.field(default_factory=Duration)
    estimated_time_remaining: Duration = msgspec.field(default_factory=Duration)
    number_of_recoveries: Int16 = 0
    distance_remaining: float = 0.0
    number_of_poses_remaining: Int16 = 0
    waypoint_statuses: list[WaypointStatus] = msgspec.field(default_factory=list)


NavigateThroughPoses = define_action(
    "nav2_msgs/NavigateThroughPoses",
    NavigateThroughPosesGoal,
    NavigateThroughPosesResult,
    NavigateThroughPosesFeedback,
)


# ------------------------------------------------------------------ FollowWaypoints


class FollowWaypointsGoal(Message):
    __msgtype__ = "nav2_msgs/FollowWaypointsGoal"
    number_of_loops: UInt32 = 0
    goal_index: UInt32 = 0
    poses: list[PoseStamped] = msgspec.field(default_factory=list)


class FollowWaypointsResult(Message):
    __msgtype__ = "nav2_msgs/FollowWaypointsResult"
    NONE = 0
    UNKNOWN = 600
    TASK_EXECUTOR_FAILED = 601
    NO_VALID_WAYPOINTS = 602
    STOP_ON_MISSED_WAYPOINT = 603
    missed_waypoints: list[WaypointStatus] = msgspec.field(default_factory=list)
    error_code: UInt16 = 0
    error_msg: str = ""


class FollowWaypointsFeedback(Message):
    __msgtype__ = "nav2_msgs/FollowWaypointsFeedback"
    current_waypoint: UInt32 = 0


FollowWaypoints = define_action(
    "nav2_msgs/FollowWaypoints", FollowWaypointsGoal, FollowWaypointsResult,
    FollowWaypointsFeedback,
)


# ------------------------------------------------------------------ ComputePathToPose


class ComputePathToPoseGoal(Message):
    __msgtype__ = "nav2_msgs/ComputePathToPoseGoal"
    goal: PoseStamped = msgspec.field(default_factory=PoseStamped)
    start: PoseStamped = msgspec.field(default_factory=PoseStamped)
    viapoints: list[PoseStamped] = msgspec.field(default_factory=list)
    planner_id: str = ""
    use_start: bool = False


class ComputePathToPoseResult(Message):
    __msgtype__ = "nav2_msgs/ComputePathToPoseResult"
    NONE = 0
    UNKNOWN = 200
    INVALID_PLANNER = 201
    TF_ERROR = 202
    START_OUTSIDE_MAP = 203
    GOAL_OUTSIDE_MAP = 204
    START_OCCUPIED = 205
    GOAL_OCCUPIED = 206
    TIMEOUT = 207
    NO_VALID_PATH = 208
    path: Path = msgspec.field(default_factory=Path)
    planning_time: Duration = msgspec.field(default_factory=Duration)
    error_code: UInt16 = 0
    error_msg: str = ""


class ComputePathToPoseFeedback(Message):
    __msgtype__ = "nav2_msgs/ComputePathToPoseFeedback"


ComputePathToPose = define_action(
    "nav2_msgs/ComputePathToPose",
    ComputePathToPoseGoal,
    ComputePathToPoseResult,
    ComputePathToPoseFeedback,
)


# ------------------------------------------------------------------ FollowPath


class FollowPathGoal(Message):
    __msgtype__ = "nav2_msgs/FollowPathGoal"
    path: Path = msgspec.field(default_factory=Path)
    controller_id: str = ""
    goal_checker_id: str = ""
    progress_checker_id: str = ""


class FollowPathResult(Message):
    __msgtype__ = "nav2_msgs/FollowPathResult"
    NONE = 0
    UNKNOWN = 100
    INVALID_CONTROLLER = 101
    TF_ERROR = 102
    INVALID_PATH = 103
    PATIENCE_EXCEEDED = 104
    FAILED_TO_MAKE_PROGRESS = 105
    NO_VALID_CONTROL = 106
    CONTROLLER_TIMED_OUT = 107
    error_code: UInt16 = 0
    error_msg: str = ""


class FollowPathFeedback(Message):
    __msgtype__ = "nav2_msgs/FollowPathFeedback"
    distance_to_goal: float = 0.0
    speed: float = 0.0


FollowPath = define_action(
    "nav2_msgs/FollowPath", FollowPathGoal, FollowPathResult, FollowPathFeedback
)


# ------------------------------------------------------------------ docking (opennav_docking)


class DockRobotGoal(Message):
    __msgtype__ = "nav2_msgs/DockRobotGoal"
    use_dock_id: bool = True
    dock_id: str = ""
    dock_pose: PoseStamped = msgspec.field(default_factory=PoseStamped)
    dock_type: str = ""
    max_staging_time: float = 1000.0
    navigate_to_staging_pose: bool = True


class DockRobotResult(Message):
    __msgtype__ = "nav2_msgs/DockRobotResult"
    NONE = 0
    DOCK_NOT_IN_DB = 901
    DOCK_NOT_VALID = 902
    FAILED_TO_STAGE = 903
    FAILED_TO_DETECT_DOCK = 904
    FAILED_TO_CONTROL = 905
    FAILED_TO_CHARGE = 906
    TIMEOUT = 907
    UNKNOWN = 999
    success: bool = True
    error_code: UInt16 = 0
    num_retries: UInt16 = 0
    error_msg: str = ""


class DockRobotFeedback(Message):
    __msgtype__ = "nav2_msgs/DockRobotFeedback"
    NONE = 0
    NAV_TO_STAGING_POSE = 1
    INITIAL_PERCEPTION = 2
    CONTROLLING = 3
    WAIT_FOR_CHARGE = 4
    RETRY = 5
    state: UInt16 = 0
    docking_time: Duration = msgspec.field(default_factory=Duration)
    num_retries: UInt16 = 0


DockRobot = define_action("nav2_msgs/DockRobot", DockRobotGoal, DockRobotResult, DockRobotFeedback)


class UndockRobotGoal(Message):
    __msgtype__ = "nav2_msgs/UndockRobotGoal"
    dock_type: str = ""
    max_undocking_time: float = 30.0


class UndockRobotResult(Message):
    __msgtype__ = "nav2_msgs/UndockRobotResult"
    NONE = 0
    DOCK_NOT_VALID = 902
    FAILED_TO_CONTROL = 905
    TIMEOUT = 907
    UNKNOWN = 999
    success: bool = True
    error_code: UInt16 = 0
    error_msg: str = ""


class UndockRobotFeedback(Message):
    __msgtype__ = "nav2_msgs/UndockRobotFeedback"


UndockRobot = define_action(
    "nav2_msgs/UndockRobot", UndockRobotGoal, UndockRobotResult, UndockRobotFeedback
)


# ------------------------------------------------------------------ map server services


class LoadMapRequest(Message):
    __msgtype__ = "nav2_msgs/LoadMapRequest"
    map_url: str = ""


class LoadMapResponse(Message):
    __msgtype__ = "nav2_msgs/LoadMapResponse"
    RESULT_SUCCESS = 0
    RESULT_MAP_DOES_NOT_EXIST = 1
    RESULT_INVALID_MAP_DATA = 2
    RESULT_INVALID_MAP_METADATA = 3
    RESULT_UNDEFINED_FAILURE = 255
    map: OccupancyGrid = msgspec.field(default_factory=OccupancyGrid)
    result: UInt8 = 0


LoadMap = define_service("nav2_msgs/LoadMap", LoadMapRequest, LoadMapResponse)


class SaveMapRequest(Message):
    __msgtype__ = "nav2_msgs/SaveMapRequest"
    map_topic: str = ""
    map_url: str = ""
    image_format: str = ""
    map_mode: str = ""
    free_thresh: float = 0.0
    occupied_thresh: float = 0.0


class SaveMapResponse(Message):
    __msgtype__ = "nav2_msgs/SaveMapResponse"
    result: bool = False


SaveMap = define_service("nav2_msgs/SaveMap", SaveMapRequest, SaveMapResponse)


class ClearEntireCostmapRequest(Message):
    __msgtype__ = "nav2_msgs/ClearEntireCostmapRequest"


class ClearEntireCostmapResponse(Message):
    __msgtype__ = "nav2_msgs/ClearEntireCostmapResponse"


ClearEntireCostmap = define_service(
    "nav2_msgs/ClearEntireCostmap", ClearEntireCostmapRequest, ClearEntireCostmapResponse
)


class ManageLifecycleNodesRequest(Message):
    """A command to a lifecycle manager (`zenros.lifecycle.manager`), Nav2's constants."""

    __msgtype__ = "nav2_msgs/ManageLifecycleNodesRequest"
    command: UInt8 = 0

    STARTUP = 0
    PAUSE = 1
    RESUME = 2
    RESET = 3
    SHUTDOWN = 4
    CONFIGURE = 5
    CLEANUP = 6


class ManageLifecycleNodesResponse(Message):
    __msgtype__ = "nav2_msgs/ManageLifecycleNodesResponse"
    success: bool = False


ManageLifecycleNodes = define_service(
    "nav2_msgs/ManageLifecycleNodes", ManageLifecycleNodesRequest, ManageLifecycleNodesResponse
)


# ------------------------------------------------------------------ behavior server actions


class SpinGoal(Message):
    """Turn in place by ``target_yaw`` radians (counter-clockwise positive)."""

    __msgtype__ = "nav2_msgs/SpinGoal"
    target_yaw: float = 0.0
    time_allowance: Duration = msgspec.field(default_factory=Duration)
    disable_collision_checks: bool = False


class SpinResult(Message):
    __msgtype__ = "nav2_msgs/SpinResult"
    NONE = 0
    UNKNOWN = 700
    TIMEOUT = 701
    TF_ERROR = 702
    COLLISION_AHEAD = 703
    total_elapsed_time: Duration = msgspec.field(default_factory=Duration)
    error_code: UInt16 = 0
    error_msg: str = ""


class SpinFeedback(Message):
    __msgtype__ = "nav2_msgs/SpinFeedback"
    angular_distance_traveled: float = 0.0


Spin = define_action("nav2_msgs/Spin", SpinGoal, SpinResult, SpinFeedback)


class BackUpGoal(Message):
    """Drive straight backwards ``target.x`` metres at ``speed`` (m/s, both positive)."""

    __msgtype__ = "nav2_msgs/BackUpGoal"
    target: Point = msgspec.field(default_factory=Point)
    speed: float = 0.0
    time_allowance: Duration = msgspec.field(default_factory=Duration)
    disable_collision_checks: bool = False


class BackUpResult(Message):
    __msgtype__ = "nav2_msgs/BackUpResult"
    NONE = 0
    UNKNOWN = 710
    TIMEOUT = 711
    TF_ERROR = 712
    INVALID_INPUT = 713
    COLLISION_AHEAD = 714
    total_elapsed_time: Duration = msgspec.field(default_factory=Duration)
    error_code: UInt16 = 0
    error_msg: str = ""


class BackUpFeedback(Message):
    __msgtype__ = "nav2_msgs/BackUpFeedback"
    distance_traveled: float = 0.0


BackUp = define_action("nav2_msgs/BackUp", BackUpGoal, BackUpResult, BackUpFeedback)


class DriveOnHeadingGoal(Message):
    """Drive straight ``target.x`` metres (negative: backwards) at ``speed`` (same sign)."""

    __msgtype__ = "nav2_msgs/DriveOnHeadingGoal"
    target: Point = msgspec.field(default_factory=Point)
    speed: float = 0.0
    time_allowance: Duration = msgspec.field(default_factory=Duration)
    disable_collision_checks: bool = False


class DriveOnHeadingResult(Message):
    __msgtype__ = "nav2_msgs/DriveOnHeadingResult"
    NONE = 0
    UNKNOWN = 720
    TIMEOUT = 721
    TF_ERROR = 722
    COLLISION_AHEAD = 723
    INVALID_INPUT = 724
    total_elapsed_time: Duration = msgspec.field(default_factory=Duration)
    error_code: UInt16 = 0
    error_msg: str = ""


class DriveOnHeadingFeedback(Message):
    __msgtype__ = "nav2_msgs/DriveOnHeadingFeedback"
    distance_traveled: float = 0.0


DriveOnHeading = define_action(
    "nav2_msgs/DriveOnHeading", DriveOnHeadingGoal, DriveOnHeadingResult, DriveOnHeadingFeedback
)
