"""visualization_msgs: made by `zenros interface generate` from its .msg/.srv files."""

from __future__ import annotations

from typing import ClassVar

import msgspec

from ..message import Message, UInt8Array, array_field, define_service
from ..primitives import Int32, UInt8, UInt32, UInt64
from .builtin_interfaces import Duration
from .geometry_msgs import Point, Pose, Quaternion, Vector3
from .sensor_msgs import CompressedImage
from .std_msgs import ColorRGBA, Header

__all__ = [
    "GetInteractiveMarkers",
    "GetInteractiveMarkersRequest",
    "GetInteractiveMarkersResponse",
    "ImageMarker",
    "InteractiveMarker",
    "InteractiveMarkerControl",
    "InteractiveMarkerFeedback",
    "InteractiveMarkerInit",
    "InteractiveMarkerPose",
    "InteractiveMarkerUpdate",
    "Marker",
    "MarkerArray",
    "MenuEntry",
    "MeshFile",
    "UVCoordinate",
]


class ImageMarker(Message):
    __msgtype__ = "visualization_msgs/ImageMarker"
    CIRCLE: ClassVar[int] = 0
    LINE_STRIP: ClassVar[int] = 1
    LINE_LIST: ClassVar[int] = 2
    POLYGON: ClassVar[int] = 3
    POINTS: ClassVar[int] = 4
    ADD: ClassVar[int] = 0
    REMOVE: ClassVar[int] = 1
    header: Header = msgspec.field(default_factory=Header)
    ns: str = ""
    id: Int32 = 0
    type: Int32 = 0
    action: Int32 = 0
    position: Point = msgspec.field(default_factory=Point)
    scale: float = 0.0
    outline_color: ColorRGBA = msgspec.field(default_factory=ColorRGBA)
    filled: UInt8 = 0
    fill_color: ColorRGBA = msgspec.field(default_factory=ColorRGBA)
    lifetime: Duration = msgspec.field(default_factory=Duration)
    points: list[Point] = msgspec.field(default_factory=list)
    outline_colors: list[ColorRGBA] = msgspec.field(default_factory=list)


class MeshFile(Message):
    """Used to send raw mesh files."""

    __msgtype__ = "visualization_msgs/MeshFile"
    __bulk__ = True
    filename: str = ""
    data: UInt8Array = array_field(UInt8Array)


class UVCoordinate(Message):
    """Location of the pixel as a ratio of the width of a 2D texture.
    Values should be in range: [0.0-1.0].
    """

    __msgtype__ = "visualization_msgs/UVCoordinate"
    u: float = 0.0
    v: float = 0.0


class Marker(Message):
    """See:
    - http://www.ros.org/wiki/rviz/DisplayTypes/Marker
    - http://www.ros.org/wiki/rviz/Tutorials/Markers%3A%20Basic%20Shapes

    for more information on using this message with rviz.
    """

    __msgtype__ = "visualization_msgs/Marker"
    ARROW: ClassVar[int] = 0
    CUBE: ClassVar[int] = 1
    SPHERE: ClassVar[int] = 2
    CYLINDER: ClassVar[int] = 3
    LINE_STRIP: ClassVar[int] = 4
    LINE_LIST: ClassVar[int] = 5
    CUBE_LIST: ClassVar[int] = 6
    SPHERE_LIST: ClassVar[int] = 7
    POINTS: ClassVar[int] = 8
    TEXT_VIEW_FACING: ClassVar[int] = 9
    MESH_RESOURCE: ClassVar[int] = 10
    TRIANGLE_LIST: ClassVar[int] = 11
    ARROW_STRIP: ClassVar[int] = 12
    ADD: ClassVar[int] = 0
    MODIFY: ClassVar[int] = 0
    DELETE: ClassVar[int] = 2
    DELETEALL: ClassVar[int] = 3
    header: Header = msgspec.field(default_factory=Header)
    ns: str = ""
    id: Int32 = 0
    type: Int32 = 0
    action: Int32 = 0
    pose: Pose = msgspec.field(default_factory=Pose)
    scale: Vector3 = msgspec.field(default_factory=Vector3)
    color: ColorRGBA = msgspec.field(default_factory=ColorRGBA)
    lifetime: Duration = msgspec.field(default_factory=Duration)
    frame_locked: bool = False
    points: list[Point] = msgspec.field(default_factory=list)
    colors: list[ColorRGBA] = msgspec.field(default_factory=list)
    texture_resource: str = ""
    texture: CompressedImage = msgspec.field(default_factory=CompressedImage)
    uv_coordinates: list[UVCoordinate] = msgspec.field(default_factory=list)
    text: str = ""
    mesh_resource: str = ""
    mesh_file: MeshFile = msgspec.field(default_factory=MeshFile)
    mesh_use_embedded_materials: bool = False


class InteractiveMarkerControl(Message):
    """Represents a control that is to be displayed together with an interactive marker"""

    __msgtype__ = "visualization_msgs/InteractiveMarkerControl"
    INHERIT: ClassVar[int] = 0
    FIXED: ClassVar[int] = 1
    VIEW_FACING: ClassVar[int] = 2
    NONE: ClassVar[int] = 0
    MENU: ClassVar[int] = 1
    BUTTON: ClassVar[int] = 2
    MOVE_AXIS: ClassVar[int] = 3
    MOVE_PLANE: ClassVar[int] = 4
    ROTATE_AXIS: ClassVar[int] = 5
    MOVE_ROTATE: ClassVar[int] = 6
    MOVE_3D: ClassVar[int] = 7
    ROTATE_3D: ClassVar[int] = 8
    MOVE_ROTATE_3D: ClassVar[int] = 9
    name: str = ""
    orientation: Quaternion = msgspec.field(default_factory=Quaternion)
    orientation_mode: UInt8 = 0
    interaction_mode: UInt8 = 0
    always_visible: bool = False
    markers: list[Marker] = msgspec.field(default_factory=list)
    independent_marker_orientation: bool = False
    description: str = ""


class MenuEntry(Message):
    """MenuEntry message.

    Each InteractiveMarker message has an array of MenuEntry messages.
    A collection of MenuEntries together describe a
    menu/submenu/subsubmenu/etc tree, though they are stored in a flat
    array.  The tree structure is represented by giving each menu entry
    an ID number and a "parent_id" field.  Top-level entries are the
    ones with parent_id = 0.  Menu entries are ordered within their
    level the same way they are ordered in the containing array.  Parent
    entries must appear before their children.

    Example:
    - id = 3
    parent_id = 0
    title = "fun"
    - id = 2
    parent_id = 0
    title = "robot"
    - id = 4
    parent_id = 2
    title = "pr2"
    - id = 5
    parent_id = 2
    title = "turtle"

    Gives a menu tree like this:
    - fun
    - robot
    - pr2
    - turtle
    """

    __msgtype__ = "visualization_msgs/MenuEntry"
    FEEDBACK: ClassVar[int] = 0
    ROSRUN: ClassVar[int] = 1
    ROSLAUNCH: ClassVar[int] = 2
    id: UInt32 = 0
    parent_id: UInt32 = 0
    title: str = ""
    command: str = ""
    command_type: UInt8 = 0


class InteractiveMarker(Message):
    """Time/frame info.
    If header.time is set to 0, the marker will be retransformed into
    its frame on each timestep. You will receive the pose feedback
    in the same frame.
    Otherwise, you might receive feedback in a different frame.
    For rviz, this will be the current 'fixed frame' set by the user.
    """

    __msgtype__ = "visualization_msgs/InteractiveMarker"
    header: Header = msgspec.field(default_factory=Header)
    pose: Pose = msgspec.field(default_factory=Pose)
    name: str = ""
    description: str = ""
    scale: float = 0.0
    menu_entries: list[MenuEntry] = msgspec.field(default_factory=list)
    controls: list[InteractiveMarkerControl] = msgspec.field(default_factory=list)


class InteractiveMarkerFeedback(Message):
    """Time/frame info."""

    __msgtype__ = "visualization_msgs/InteractiveMarkerFeedback"
    KEEP_ALIVE: ClassVar[int] = 0
    POSE_UPDATE: ClassVar[int] = 1
    MENU_SELECT: ClassVar[int] = 2
    BUTTON_CLICK: ClassVar[int] = 3
    MOUSE_DOWN: ClassVar[int] = 4
    MOUSE_UP: ClassVar[int] = 5
    header: Header = msgspec.field(default_factory=Header)
    client_id: str = ""
    marker_name: str = ""
    control_name: str = ""
    event_type: UInt8 = 0
    pose: Pose = msgspec.field(default_factory=Pose)
    menu_entry_id: UInt32 = 0
    mouse_point: Point = msgspec.field(default_factory=Point)
    mouse_point_valid: bool = False


class InteractiveMarkerInit(Message):
    """Identifying string. Must be unique in the topic namespace
    that this server works on.
    """

    __msgtype__ = "visualization_msgs/InteractiveMarkerInit"
    server_id: str = ""
    seq_num: UInt64 = 0
    markers: list[InteractiveMarker] = msgspec.field(default_factory=list)


class InteractiveMarkerPose(Message):
    """Time/frame info."""

    __msgtype__ = "visualization_msgs/InteractiveMarkerPose"
    header: Header = msgspec.field(default_factory=Header)
    pose: Pose = msgspec.field(default_factory=Pose)
    name: str = ""


class InteractiveMarkerUpdate(Message):
    """Identifying string. Must be unique in the topic namespace
    that this server works on.
    """

    __msgtype__ = "visualization_msgs/InteractiveMarkerUpdate"
    KEEP_ALIVE: ClassVar[int] = 0
    UPDATE: ClassVar[int] = 1
    server_id: str = ""
    seq_num: UInt64 = 0
    type: UInt8 = 0
    markers: list[InteractiveMarker] = msgspec.field(default_factory=list)
    poses: list[InteractiveMarkerPose] = msgspec.field(default_factory=list)
    erases: list[str] = msgspec.field(default_factory=list)


class MarkerArray(Message):
    __msgtype__ = "visualization_msgs/MarkerArray"
    markers: list[Marker] = msgspec.field(default_factory=list)


class GetInteractiveMarkersRequest(Message):
    __msgtype__ = "visualization_msgs/GetInteractiveMarkersRequest"


class GetInteractiveMarkersResponse(Message):
    """Sequence number.
    Set to the sequence number of the latest update message
    at the time the server received the request.
    Clients use this to detect if any updates were missed.
    """

    __msgtype__ = "visualization_msgs/GetInteractiveMarkersResponse"
    sequence_number: UInt64 = 0
    markers: list[InteractiveMarker] = msgspec.field(default_factory=list)


GetInteractiveMarkers = define_service(
    "visualization_msgs/GetInteractiveMarkers", GetInteractiveMarkersRequest, GetInteractiveMarkersResponse)
