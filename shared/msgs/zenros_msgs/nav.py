"""zenros_msgs for the nav service (see DESIGN.md, "Robot interfaces"; docs/nav.md).

Maps live under ``$ZENROS_HOME/maps/<name>/``; every per-map service takes ``map_name``,
and an empty ``map_name`` means the current map. Unknown maps or paths are refused with an
error naming the known ones (the caller's client raises ``ServiceError``).

- ``map_server/list_maps`` (ListMaps), ``map_server/current_map`` (GetCurrentMap),
  ``map_server/import_map`` (ImportMap),
  ``switch_map`` (SwitchMap).
- ``list_paths`` (ListPaths), ``get_path`` / ``set_path`` / ``delete_path`` (a path's
  recorded ``x y z`` points), ``get_nav_points`` / ``set_nav_points`` / ``delete_nav_points``
  (the indexed named poses of a path).
- ``get_virtual_walls`` / ``set_virtual_walls``, ``get_forbidden_areas`` /
  ``set_forbidden_areas`` (lethal keep-out in both costmaps), ``get_charge_pose`` /
  ``set_charge_pose``.
- ``patrol`` (action Patrol): loop over a path's nav points.
- ``local_move_target`` (action LocalMoveTarget): a precise short move to a pose without
  the global planner (Nav2's ``drive_on_heading``, ``backup`` and ``spin`` are nav2_msgs).
- ``list_point_connections`` / ``add_point_connection`` / ``delete_point_connection``:
  links between nav points of different maps (multi-map navigation, docs/robot-api.md §6.7).
- ``nav/status`` (NavStatus, latched): what navigation is doing, for the gateway.
- ``get_landmarks`` (GetLandmarks): a map's reflectors (``landmarks.yaml``);
  ``relocalize_landmarks`` (RelocalizeLandmarks): the robot's pose from the reflectors the
  last scan saw; ``landmarks/detections`` (LandmarkDetections): what each scan sees.
"""

from __future__ import annotations

from typing import Any

import msgspec

from ...message import Message, ServiceType, define_action, define_service
from ..builtin_interfaces import Duration
from ..geometry_msgs import Point, Pose2D, PoseStamped
from ..std_msgs import Header

__all__ = [
    "NAV_SERVICE_NAMES",
    "AddPointConnection",
    "AddPointConnectionRequest",
    "AddPointConnectionResponse",
    "ComputeCoveragePath",
    "ComputeCoveragePathRequest",
    "ComputeCoveragePathResponse",
    "ConnectionPoint",
    "CoverageHole",
    "DeleteNavPoints",
    "DeleteNavPointsRequest",
    "DeleteNavPointsResponse",
    "DeletePath",
    "DeletePathRequest",
    "DeletePathResponse",
    "DeletePointConnection",
    "DeletePointConnectionRequest",
    "DeletePointConnectionResponse",
    "ForbiddenArea",
    "GetChargePose",
    "GetChargePoseRequest",
    "GetChargePoseResponse",
    "GetCurrentMap",
    "GetCurrentMapRequest",
    "GetCurrentMapResponse",
    "GetForbiddenAreas",
    "GetForbiddenAreasRequest",
    "GetForbiddenAreasResponse",
    "GetLandmarks",
    "GetLandmarksRequest",
    "GetLandmarksResponse",
    "GetNavPoints",
    "GetNavPointsRequest",
    "GetNavPointsResponse",
    "GetPath",
    "GetPathRequest",
    "GetPathResponse",
    "GetVirtualWalls",
    "GetVirtualWallsRequest",
    "GetVirtualWallsResponse",
    "ImportMap",
    "ImportMapRequest",
    "ImportMapResponse",
    "Landmark",
    "LandmarkDetections",
    "ListMaps",
    "ListMapsRequest",
    "ListMapsResponse",
    "ListPaths",
    "ListPathsRequest",
    "ListPathsResponse",
    "ListPointConnections",
    "ListPointConnectionsRequest",
    "ListPointConnectionsResponse",
    "LocalMoveTarget",
    "LocalMoveTargetFeedback",
    "LocalMoveTargetGoal",
    "LocalMoveTargetResult",
    "MapInfo",
    "NavPoint",
    "NavStatus",
    "PathRef",
    "Patrol",
    "PatrolFeedback",
    "PatrolGoal",
    "PatrolResult",
    "PointConnection",
    "PointRef",
    "RelocalizeLandmarks",
    "RelocalizeLandmarksRequest",
    "RelocalizeLandmarksResponse",
    "SetChargePose",
    "SetChargePoseRequest",
    "SetChargePoseResponse",
    "SetForbiddenAreas",
    "SetForbiddenAreasRequest",
    "SetForbiddenAreasResponse",
    "SetNavPoints",
    "SetNavPointsRequest",
    "SetNavPointsResponse",
    "SetPath",
    "SetPathRequest",
    "SetPathResponse",
    "SetVirtualWalls",
    "SetVirtualWallsRequest",
    "SetVirtualWallsResponse",
    "SwitchMap",
    "SwitchMapRequest",
    "SwitchMapResponse",
    "VirtualWall",
]


# ------------------------------------------------------------------ data


class MapInfo(Message):
    """A stored map's metadata (the fields of the robot API's ``saved_maps`` entries).

    ``yaml_path`` and ``image_path`` are the map_server files in the maps folder (absolute),
    for callers on the robot that serve the image as it is.
    """

    __msgtype__ = "zenros_msgs/MapInfo"
    name: str = ""
    resolution: float = 0.0
    origin: list[float] = msgspec.field(default_factory=lambda: [0.0, 0.0, 0.0])
    width: int = 0
    height: int = 0
    occupied_thresh: float = 0.65
    free_thresh: float = 0.196
    negate: int = 0
    mode: str = "trinary"
    md5sum: str = ""
    type: str = "floor"
    levels: list[int] = msgspec.field(default_factory=list)
    slam_type: str = "lidar"
    yaml_path: str = ""
    image_path: str = ""


class NavPoint(Message):
    """A named pose of a path (docs/robot-api.md §6.6 columns: x y z theta errorX errorY direction
    name)."""

    __msgtype__ = "zenros_msgs/NavPoint"
    name: str = ""
    x: float = 0.0
    y: float = 0.0
    z: float = 0.0
    theta: float = 0.0
    error_x: float = 0.1
    error_y: float = 0.1
    direction: int = 0


class PathRef(Message):
    """A path's name and the map it belongs to."""

    __msgtype__ = "zenros_msgs/PathRef"
    map_name: str = ""
    path_name: str = ""


class VirtualWall(Message):
    """A polyline in ``map`` the robot must never cross (lethal, not inflated)."""

    __msgtype__ = "zenros_msgs/VirtualWall"
    name: str = ""
    points: list[Point] = msgspec.field(default_factory=list)


class ForbiddenArea(Message):
    """A polygon in ``map`` the robot must never enter (lethal, not inflated)."""

    __msgtype__ = "zenros_msgs/ForbiddenArea"
    name: str = ""
    points: list[Point] = msgspec.field(default_factory=list)


class NavStatus(Message):
    """What navigation is doing, latched on ``nav/status`` at every change and at 2 Hz.

    ``state``: ``idle``, ``navigating``, ``recovering``, ``docking``, ``undocking``,
    ``charging`` or ``patrolling``. ``goal_status``: 0 none / 1 working / 2 succeeded /
    3 failed / 4 canceled (for the robot API's targetStatus). ``target_distance`` is the
    path length left, -1 without a goal. ``mapping``: nav is in mapping mode (the SLAM
    node owns ``map`` and ``map -> odom``; ``map_name`` is empty then).
    """

    __msgtype__ = "zenros_msgs/NavStatus"
    header: Header = msgspec.field(default_factory=Header)
    map_name: str = ""
    localized: bool = False
    state: str = "idle"
    goal_status: int = 0
    goal: Pose2D = msgspec.field(default_factory=Pose2D)
    target_distance: float = -1.0
    error_code: int = 0
    error_msg: str = ""
    pose: Pose2D = msgspec.field(default_factory=Pose2D)
    mapping: bool = False


# ------------------------------------------------------------------ maps


class ListMapsRequest(Message):
    """``name`` non-empty: only that map."""

    __msgtype__ = "zenros_msgs/ListMapsRequest"
    name: str = ""


class ListMapsResponse(Message):
    __msgtype__ = "zenros_msgs/ListMapsResponse"
    maps: list[MapInfo] = msgspec.field(default_factory=list)
    current: str = ""


ListMaps = define_service("zenros_msgs/ListMaps", ListMapsRequest, ListMapsResponse)


class GetCurrentMapRequest(Message):
    __msgtype__ = "zenros_msgs/GetCurrentMapRequest"


class GetCurrentMapResponse(Message):
    __msgtype__ = "zenros_msgs/GetCurrentMapResponse"
    name: str = ""
    md5sum: str = ""
    info: MapInfo = msgspec.field(default_factory=MapInfo)


GetCurrentMap = define_service(
    "zenros_msgs/GetCurrentMap", GetCurrentMapRequest, GetCurrentMapResponse
)


class ImportMapRequest(Message):
    """Copy a map_server YAML and its image into the maps folder as ``name``.

    An empty ``name`` takes the YAML file's stem. ``overwrite`` false refuses an existing
    name. Nav points and walls of an existing map are kept when it is overwritten.
    """

    __msgtype__ = "zenros_msgs/ImportMapRequest"
    name: str = ""
    yaml_path: str = ""
    overwrite: bool = False


class ImportMapResponse(Message):
    __msgtype__ = "zenros_msgs/ImportMapResponse"
    info: MapInfo = msgspec.field(default_factory=MapInfo)


ImportMap = define_service("zenros_msgs/ImportMap", ImportMapRequest, ImportMapResponse)


class SwitchMapRequest(Message):
    __msgtype__ = "zenros_msgs/SwitchMapRequest"
    map_name: str = ""


class SwitchMapResponse(Message):
    """``success`` false (with ``message``) leaves the current map loaded."""

    __msgtype__ = "zenros_msgs/SwitchMapResponse"
    success: bool = False
    message: str = ""
    info: MapInfo = msgspec.field(default_factory=MapInfo)


SwitchMap = define_service("zenros_msgs/SwitchMap", SwitchMapRequest, SwitchMapResponse)


# ------------------------------------------------------------------ paths and nav points


class ListPathsRequest(Message):
    """``map_name`` empty: the paths of every map."""

    __msgtype__ = "zenros_msgs/ListPathsRequest"
    map_name: str = ""


class ListPathsResponse(Message):
    __msgtype__ = "zenros_msgs/ListPathsResponse"
    paths: list[PathRef] = msgspec.field(default_factory=list)


ListPaths = define_service("zenros_msgs/ListPaths", ListPathsRequest, ListPathsResponse)


class GetPathRequest(Message):
    __msgtype__ = "zenros_msgs/GetPathRequest"
    map_name: str = ""
    path_name: str = ""


class GetPathResponse(Message):
    """A path's recorded points (robot API ``path_data`` lines ``x y z``)."""

    __msgtype__ = "zenros_msgs/GetPathResponse"
    map_name: str = ""
    path_name: str = ""
    points: list[Point] = msgspec.field(default_factory=list)


GetPath = define_service("zenros_msgs/GetPath", GetPathRequest, GetPathResponse)


class SetPathRequest(Message):
    """Create or replace a path's recorded points (its nav points are kept)."""

    __msgtype__ = "zenros_msgs/SetPathRequest"
    map_name: str = ""
    path_name: str = ""
    points: list[Point] = msgspec.field(default_factory=list)


class SetPathResponse(Message):
    __msgtype__ = "zenros_msgs/SetPathResponse"
    map_name: str = ""
    path_name: str = ""
    points: list[Point] = msgspec.field(default_factory=list)


SetPath = define_service("zenros_msgs/SetPath", SetPathRequest, SetPathResponse)


class DeletePathRequest(Message):
    """Delete a path and its nav points."""

    __msgtype__ = "zenros_msgs/DeletePathRequest"
    map_name: str = ""
    path_name: str = ""


class DeletePathResponse(Message):
    __msgtype__ = "zenros_msgs/DeletePathResponse"


DeletePath = define_service("zenros_msgs/DeletePath", DeletePathRequest, DeletePathResponse)


class GetNavPointsRequest(Message):
    __msgtype__ = "zenros_msgs/GetNavPointsRequest"
    map_name: str = ""
    path_name: str = ""


class GetNavPointsResponse(Message):
    """The nav points in index order."""

    __msgtype__ = "zenros_msgs/GetNavPointsResponse"
    map_name: str = ""
    path_name: str = ""
    points: list[NavPoint] = msgspec.field(default_factory=list)


GetNavPoints = define_service("zenros_msgs/GetNavPoints", GetNavPointsRequest, GetNavPointsResponse)


class SetNavPointsRequest(Message):
    """Create or replace a path's nav points (names, when given, unique within the path)."""

    __msgtype__ = "zenros_msgs/SetNavPointsRequest"
    map_name: str = ""
    path_name: str = ""
    points: list[NavPoint] = msgspec.field(default_factory=list)


class SetNavPointsResponse(Message):
    __msgtype__ = "zenros_msgs/SetNavPointsResponse"
    map_name: str = ""
    path_name: str = ""
    points: list[NavPoint] = msgspec.field(default_factory=list)


SetNavPoints = define_service("zenros_msgs/SetNavPoints", SetNavPointsRequest, SetNavPointsResponse)


class DeleteNavPointsRequest(Message):
    __msgtype__ = "zenros_msgs/DeleteNavPointsRequest"
    map_name: str = ""
    path_name: str = ""


class DeleteNavPointsResponse(Message):
    __msgtype__ = "zenros_msgs/DeleteNavPointsResponse"


DeleteNavPoints = define_service(
    "zenros_msgs/DeleteNavPoints", DeleteNavPointsRequest, DeleteNavPointsResponse
)


# ------------------------------------------------------------------ keep-out and charge pose


class GetVirtualWallsRequest(Message):
    __msgtype__ = "zenros_msgs/GetVirtualWallsRequest"
    map_name: str = ""


class GetVirtualWallsResponse(Message):
    __msgtype__ = "zenros_msgs/GetVirtualWallsResponse"
    map_name: str = ""
    walls: list[VirtualWall] = msgspec.field(default_factory=list)


GetVirtualWalls = define_service(
    "zenros_msgs/GetVirtualWalls", GetVirtualWallsRequest, GetVirtualWallsResponse
)


class SetVirtualWallsRequest(Message):
    """Replace a map's virtual walls (an empty list deletes them)."""

    __msgtype__ = "zenros_msgs/SetVirtualWallsRequest"
    map_name: str = ""
    walls: list[VirtualWall] = msgspec.field(default_factory=list)


class SetVirtualWallsResponse(Message):
    __msgtype__ = "zenros_msgs/SetVirtualWallsResponse"
    map_name: str = ""
    walls: list[VirtualWall] = msgspec.field(default_factory=list)


SetVirtualWalls = define_service(
    "zenros_msgs/SetVirtualWalls", SetVirtualWallsRequest, SetVirtualWallsResponse
)


class GetForbiddenAreasRequest(Message):
    __msgtype__ = "zenros_msgs/GetForbiddenAreasRequest"
    map_name: str = ""


class GetForbiddenAreasResponse(Message):
    __msgtype__ = "zenros_msgs/GetForbiddenAreasResponse"
    map_name: str = ""
    areas: list[ForbiddenArea] = msgspec.field(default_factory=list)


GetForbiddenAreas = define_service(
    "zenros_msgs/GetForbiddenAreas", GetForbiddenAreasRequest, GetForbiddenAreasResponse
)


class SetForbiddenAreasRequest(Message):
    """Replace a map's forbidden areas (an empty list deletes them)."""

    __msgtype__ = "zenros_msgs/SetForbiddenAreasRequest"
    map_name: str = ""
    areas: list[ForbiddenArea] = msgspec.field(default_factory=list)


class SetForbiddenAreasResponse(Message):
    __msgtype__ = "zenros_msgs/SetForbiddenAreasResponse"
    map_name: str = ""
    areas: list[ForbiddenArea] = msgspec.field(default_factory=list)


SetForbiddenAreas = define_service(
    "zenros_msgs/SetForbiddenAreas", SetForbiddenAreasRequest, SetForbiddenAreasResponse
)


class GetChargePoseRequest(Message):
    __msgtype__ = "zenros_msgs/GetChargePoseRequest"
    map_name: str = ""


class GetChargePoseResponse(Message):
    """``is_set`` false when the map has no charge pose yet."""

    __msgtype__ = "zenros_msgs/GetChargePoseResponse"
    map_name: str = ""
    is_set: bool = False
    pose: Pose2D = msgspec.field(default_factory=Pose2D)


GetChargePose = define_service(
    "zenros_msgs/GetChargePose", GetChargePoseRequest, GetChargePoseResponse
)


class SetChargePoseRequest(Message):
    """Store ``pose`` (or, with ``use_current_pose``, the robot's pose now) as the charger."""

    __msgtype__ = "zenros_msgs/SetChargePoseRequest"
    map_name: str = ""
    use_current_pose: bool = False
    pose: Pose2D = msgspec.field(default_factory=Pose2D)


class SetChargePoseResponse(Message):
    __msgtype__ = "zenros_msgs/SetChargePoseResponse"
    map_name: str = ""
    pose: Pose2D = msgspec.field(default_factory=Pose2D)


SetChargePose = define_service(
    "zenros_msgs/SetChargePose", SetChargePoseRequest, SetChargePoseResponse
)


# ------------------------------------------------------------------ patrol


class PatrolGoal(Message):
    """Visit a path's nav points in order, ``loops`` times (0 = until canceled).

    ``wait_time`` seconds are spent at each point; ``start_index`` is the first point.
    """

    __msgtype__ = "zenros_msgs/PatrolGoal"
    map_name: str = ""
    path_name: str = ""
    loops: int = 0
    wait_time: float = 0.0
    start_index: int = 0


class PatrolResult(Message):
    """Error codes: NONE 0, UNKNOWN_PATH 1, NO_NAV_POINTS 2, NAVIGATION_FAILED 3."""

    __msgtype__ = "zenros_msgs/PatrolResult"
    NONE = 0
    UNKNOWN_PATH = 1
    NO_NAV_POINTS = 2
    NAVIGATION_FAILED = 3
    error_code: int = 0
    error_msg: str = ""
    loops_completed: int = 0
    points_visited: int = 0


class PatrolFeedback(Message):
    __msgtype__ = "zenros_msgs/PatrolFeedback"
    current_index: int = 0
    loop: int = 0
    current_pose: PoseStamped = msgspec.field(default_factory=PoseStamped)
    distance_remaining: float = 0.0
    waiting: bool = False
    navigation_time: Duration = msgspec.field(default_factory=Duration)


Patrol = define_action("zenros_msgs/Patrol", PatrolGoal, PatrolResult, PatrolFeedback)


# ------------------------------------------------------------------ point connections


class PointRef(Message):
    """One nav point: its map, path and index (docs/robot-api.md §6.7 ``{map, path, index}``)."""

    __msgtype__ = "zenros_msgs/PointRef"
    map_name: str = ""
    path_name: str = ""
    index: int = 0


class ConnectionPoint(Message):
    """A nav point of some map with its pose, as ``point_connections`` lists them."""

    __msgtype__ = "zenros_msgs/ConnectionPoint"
    map_name: str = ""
    path_name: str = ""
    index: int = 0
    name: str = ""
    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0


class PointConnection(Message):
    """Two nav points (of different maps or paths) linked ``direct`` (the same physical
    spot) or by ``elevator``; ``is_available`` false makes route planning skip it."""

    __msgtype__ = "zenros_msgs/PointConnection"
    DIRECT = "direct"
    ELEVATOR = "elevator"
    id: str = ""
    oid: str = ""  # 24 hex digits, the §6.7 ``_id.$oid``
    type: str = "direct"
    is_available: bool = True
    points: list[PointRef] = msgspec.field(default_factory=list)


class ListPointConnectionsRequest(Message):
    __msgtype__ = "zenros_msgs/ListPointConnectionsRequest"


class ListPointConnectionsResponse(Message):
    """Every nav point of every map, and every stored connection."""

    __msgtype__ = "zenros_msgs/ListPointConnectionsResponse"
    points: list[ConnectionPoint] = msgspec.field(default_factory=list)
    connections: list[PointConnection] = msgspec.field(default_factory=list)


ListPointConnections = define_service(
    "zenros_msgs/ListPointConnections", ListPointConnectionsRequest,
    ListPointConnectionsResponse)


class AddPointConnectionRequest(Message):
    """Two existing nav points, the ``type`` (``direct``/``elevator``) and availability."""

    __msgtype__ = "zenros_msgs/AddPointConnectionRequest"
    points: list[PointRef] = msgspec.field(default_factory=list)
    type: str = "direct"
    is_available: bool = True


class AddPointConnectionResponse(Message):
    __msgtype__ = "zenros_msgs/AddPointConnectionResponse"
    connection: PointConnection = msgspec.field(default_factory=PointConnection)


AddPointConnection = define_service(
    "zenros_msgs/AddPointConnection", AddPointConnectionRequest, AddPointConnectionResponse)


class DeletePointConnectionRequest(Message):
    __msgtype__ = "zenros_msgs/DeletePointConnectionRequest"
    id: str = ""


class DeletePointConnectionResponse(Message):
    __msgtype__ = "zenros_msgs/DeletePointConnectionResponse"


DeletePointConnection = define_service(
    "zenros_msgs/DeletePointConnection", DeletePointConnectionRequest,
    DeletePointConnectionResponse)


class LocalMoveTargetGoal(Message):
    """Move to ``pose`` without the global planner (docs/robot-api.md §9.2
    ``local_move_target_action``).

    ``pose.header.frame_id``: ``map`` (or empty) or ``base_link`` (relative to the robot's
    pose when the goal starts). Done within ``xy_tolerance`` m, and ``yaw_tolerance`` rad of
    the pose's heading when ``target_rotate_enable``. ``start_rotate_enable``: turn toward
    the target before driving. ``time_allowance`` 0: no limit.
    """

    __msgtype__ = "zenros_msgs/LocalMoveTargetGoal"
    pose: PoseStamped = msgspec.field(default_factory=PoseStamped)
    xy_tolerance: float = 0.05
    yaw_tolerance: float = 0.05
    time_allowance: Duration = msgspec.field(default_factory=Duration)
    start_rotate_enable: bool = True
    target_rotate_enable: bool = True
    speed: float = 0.0


class LocalMoveTargetResult(Message):
    """Error codes (Nav2 style): NONE 0, UNKNOWN 730, TIMEOUT 731, TF_ERROR 732,
    COLLISION_AHEAD 733, INVALID_INPUT 734."""

    __msgtype__ = "zenros_msgs/LocalMoveTargetResult"
    NONE = 0
    UNKNOWN = 730
    TIMEOUT = 731
    TF_ERROR = 732
    COLLISION_AHEAD = 733
    INVALID_INPUT = 734
    total_elapsed_time: Duration = msgspec.field(default_factory=Duration)
    error_code: int = 0
    error_msg: str = ""


class LocalMoveTargetFeedback(Message):
    __msgtype__ = "zenros_msgs/LocalMoveTargetFeedback"
    current_pose: PoseStamped = msgspec.field(default_factory=PoseStamped)
    distance_remaining: float = 0.0


LocalMoveTarget = define_action("zenros_msgs/LocalMoveTarget", LocalMoveTargetGoal,
                                LocalMoveTargetResult, LocalMoveTargetFeedback)


class CoverageHole(Message):
    """An area a coverage path leaves out (a closed polygon, z ignored)."""

    __msgtype__ = "zenros_msgs/CoverageHole"
    points: list[Point] = msgspec.field(default_factory=list)


class ComputeCoveragePathRequest(Message):
    """A boustrophedon coverage path over ``border`` minus ``holes`` (computed, not driven).

    ``swath_angle`` in degrees (< 0: the angle needing the fewest swaths), ``op_width``
    (> 0), ``turn_radius`` and ``headland_width`` (>= 0) in metres. See services/nav/
    planning/coverage.py and docs/nav.md. A bad field is refused with a reason naming it.
    """

    __msgtype__ = "zenros_msgs/ComputeCoveragePathRequest"
    swath_angle: float = 0.0
    op_width: float = 1.0
    turn_radius: float = 0.0
    headland_width: float = 0.0
    border: list[Point] = msgspec.field(default_factory=list)
    holes: list[CoverageHole] = msgspec.field(default_factory=list)


class ComputeCoveragePathResponse(Message):
    """``path``: swath segment ends in driving order; ``swath_angle`` the angle used."""

    __msgtype__ = "zenros_msgs/ComputeCoveragePathResponse"
    path: list[Point] = msgspec.field(default_factory=list)
    swath_angle: float = 0.0
    swaths: int = 0
    segments: int = 0


ComputeCoveragePath = define_service("zenros_msgs/ComputeCoveragePath",
                                     ComputeCoveragePathRequest, ComputeCoveragePathResponse)


# ------------------------------------------------------------------ landmarks


class Landmark(Message):
    """A reflector of a map: its centre (x, y) in ``map`` and its radius (m)."""

    __msgtype__ = "zenros_msgs/Landmark"
    id: str = ""
    x: float = 0.0
    y: float = 0.0
    radius: float = 0.0


class LandmarkDetections(Message):
    """The reflectors one scan saw: their centres in ``header.frame_id`` (base_link), and
    how many strong returns each."""

    __msgtype__ = "zenros_msgs/LandmarkDetections"
    header: Header = msgspec.field(default_factory=Header)
    points: list[Point] = msgspec.field(default_factory=list)
    returns: list[int] = msgspec.field(default_factory=list)


class GetLandmarksRequest(Message):
    __msgtype__ = "zenros_msgs/GetLandmarksRequest"
    map_name: str = ""


class GetLandmarksResponse(Message):
    __msgtype__ = "zenros_msgs/GetLandmarksResponse"
    map_name: str = ""
    landmarks: list[Landmark] = msgspec.field(default_factory=list)


GetLandmarks = define_service("zenros_msgs/GetLandmarks", GetLandmarksRequest,
                              GetLandmarksResponse)


class RelocalizeLandmarksRequest(Message):
    """``use_estimate``: the current estimate breaks ties between equally good fits (and
    is what a fit is compared with); false searches the whole map by the reflectors'
    pairwise distances alone. ``min_matches``: reflectors a fit must match (at least 2)."""

    __msgtype__ = "zenros_msgs/RelocalizeLandmarksRequest"
    use_estimate: bool = True
    min_matches: int = 2


class RelocalizeLandmarksResponse(Message):
    """``success`` false with the reason in ``message`` (too few reflectors seen or
    matched, an ambiguous fit, no scan, a map without landmarks); else ``pose`` (the robot
    in ``map``, now nav's estimate), the reflectors ``detected`` and ``matched`` (their
    ``ids``), the fit's ``rms_error`` (m) and how far it moved the estimate (``shift``,
    ``turn``)."""

    __msgtype__ = "zenros_msgs/RelocalizeLandmarksResponse"
    success: bool = False
    message: str = ""
    map_name: str = ""
    pose: Pose2D = msgspec.field(default_factory=Pose2D)
    detected: int = 0
    matched: int = 0
    ids: list[str] = msgspec.field(default_factory=list)
    rms_error: float = 0.0
    shift: float = 0.0
    turn: float = 0.0


RelocalizeLandmarks = define_service("zenros_msgs/RelocalizeLandmarks",
                                     RelocalizeLandmarksRequest, RelocalizeLandmarksResponse)


NAV_SERVICE_NAMES: dict[ServiceType[Any, Any], str] = {
    ListMaps: "map_server/list_maps",
    GetCurrentMap: "map_server/current_map",
    ImportMap: "map_server/import_map",
    SwitchMap: "switch_map",
    ListPaths: "list_paths",
    GetPath: "get_path",
    SetPath: "set_path",
    DeletePath: "delete_path",
    GetNavPoints: "get_nav_points",
    SetNavPoints: "set_nav_points",
    DeleteNavPoints: "delete_nav_points",
    GetChargePose: "get_charge_pose",
    SetChargePose: "set_charge_pose",
    GetVirtualWalls: "get_virtual_walls",
    SetVirtualWalls: "set_virtual_walls",
    GetForbiddenAreas: "get_forbidden_areas",
    SetForbiddenAreas: "set_forbidden_areas",
    ListPointConnections: "list_point_connections",
    AddPointConnection: "add_point_connection",
    DeletePointConnection: "delete_point_connection",
    GetLandmarks: "get_landmarks",
    RelocalizeLandmarks: "relocalize_landmarks",
}
"""Nav's map, path and nav point services by type (one service each), their names
relative to the robot's namespace: what the gateway and the tasks service call."""
