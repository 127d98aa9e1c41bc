"""The actions a task can hold (docs/robot-api.md §9.2): one tagged union, `Action`.

Each action type is a Struct tagged by its ``type`` ("nav_action", ...), so a document
decodes straight into the right class and a missing, mistyped or unknown field is refused
with its path (``at $.sub_tasks[0].wait_time``). The same classes are the request bodies
the gateway builds, the documents the tasks service runs and the answers it gives.

Besides its parameters every action carries the common fields (``id``, ``state``,
``result``, ``progress``); ``nav_action`` documents also carry ``current_location`` and
``current_distance``. An optional parameter never given is `UNSET` and left out of the
document (a JSON ``null`` is read as not given).
"""

from __future__ import annotations

import math
import re
from typing import Annotated, Any, Final, Literal

import msgspec
from msgspec import UNSET, Meta, UnsetType

__all__ = [
    "ACTION_TYPES",
    "COMMON_FIELDS",
    "LAUNCH_CMD",
    "Action",
    "ActionBase",
    "AudioRecordAction",
    "BlocklyAction",
    "CallbackAction",
    "ChangeSettingAction",
    "ChargeAction",
    "DownloadMapAction",
    "ElevatorReqAction",
    "ImageAction",
    "IoAction",
    "JackingAction",
    "JackingRotateAction",
    "LbtElevatorAckAction",
    "LbtElevatorReqAction",
    "LocalMoveAction",
    "LocalMoveTargetAction",
    "Location",
    "NavAction",
    "NoneStopNavAction",
    "OnvifCameraMoveAction",
    "OnvifCameraSnapshotAction",
    "RoslaunchAction",
    "SleepAction",
    "SlideAction",
    "SwitchMapAction",
    "TtsAction",
    "UploadMapAction",
    "VideoRecordAction",
    "WaitReqAction",
    "check_action",
]

Seconds = Annotated[float, Meta(ge=0)]
Level = Annotated[float, Meta(ge=0, le=1)]
Coordinate = Annotated[float, Meta(ge=-1e5, le=1e5)]


class Location(msgspec.Struct, kw_only=True):
    """Where a ``nav_action`` is (-1 while unknown)."""

    x: float = -1.0
    y: float = -1.0
    theta: float = -1.0


class ActionBase(msgspec.Struct, kw_only=True, forbid_unknown_fields=True, tag_field="type"):
    """The fields every action document carries; a request may send them (ignored)."""

    id: str = ""
    state: str = "WAITTING"
    result: str = ""
    progress: float = 0.0
    current_location: Location | UnsetType = UNSET
    current_distance: float | UnsetType = UNSET


class NavAction(ActionBase, kw_only=True, tag="nav_action"):
    """Navigate to (x, y, theta) in ``map``, or to nav point ``index`` of the current map."""

    x: float | None | UnsetType = UNSET
    y: float | None | UnsetType = UNSET
    theta: float = 0.0
    index: Annotated[int, Meta(ge=0)] | None | UnsetType = UNSET
    map: str = ""
    path: str = ""
    timeout: Seconds = 0.0  # 0: no limit


class SleepAction(ActionBase, kw_only=True, tag="sleep_action"):
    wait_time: Seconds


class ChargeAction(ActionBase, kw_only=True, tag="charge_action"):
    """Dock at the charger; complete when charging starts, or when ``level`` is reached."""

    x: float | None | UnsetType = UNSET
    y: float | None | UnsetType = UNSET
    theta: float = 0.0
    level: Level = 0.0  # 0: complete as soon as charging starts (§9.2 impl. note)
    timeout: Seconds = 0.0


class CallbackAction(ActionBase, kw_only=True, tag="callback_action"):
    url: str
    method: str = "GET"
    data: Any = UNSET
    timeout: Annotated[float, Meta(gt=0)] = 10.0


class WaitReqAction(ActionBase, kw_only=True, tag="wait_req_action"):
    timeout: Seconds = 0.0  # 0: wait until released


class TtsAction(ActionBase, kw_only=True, tag="tts_action"):
    text: str


class SwitchMapAction(ActionBase, kw_only=True, tag="switch_map_action"):
    map: str
    path: str = ""
    start_index: Annotated[int, Meta(ge=-1)] = -1


class LocalMoveAction(ActionBase, kw_only=True, tag="local_move_action"):
    """Move ``distance`` m (+ forward) and turn ``angle`` rad (+ CCW) without the planner.

    ``method`` (illegible in the spec; our reading): 0 moves then turns, 1 turns then moves.
    """

    distance: Annotated[float, Meta(ge=-20, le=20)] = 0.0
    angle: Annotated[float, Meta(ge=-20, le=20)] = 0.0
    method: Literal[0, 1] = 0
    speed: Annotated[float, Meta(gt=0, le=2)] = 0.3
    timeout: Seconds = 0.0  # 0: no limit


class LocalMoveTargetAction(ActionBase, kw_only=True, tag="local_move_target_action"):
    """A precise short move to (x, y, theta) in ``map`` or relative to ``base_link``."""

    x: Coordinate
    y: Coordinate
    theta: float = 0.0
    frame_id: Literal["map", "base_link"] = "map"
    xy_tolerance: Annotated[float, Meta(gt=0, le=10)] = 0.05
    yaw_tolerance: Annotated[float, Meta(gt=0, le=3.15)] = 0.05
    timeout: Seconds = 0.0  # 0: no limit
    start_rotate_enable: bool = True
    target_rotate_enable: bool = True


class IoAction(ActionBase, kw_only=True, tag="io_action"):
    """Set main-board output ``port`` ("1".."3") to ``level`` ("0" low, "1" high)."""

    level: Literal["0", "1"]
    port: Literal["1", "2", "3"]


ServerId = Annotated[str, Meta(pattern=r"^[A-Za-z0-9_]{1,64}$")]
"""A schedule server's ID (`zenros.msgs.zenros_msgs.schedule`)."""


class UploadMapAction(ActionBase, kw_only=True, tag="upload_map_action"):
    """Put the current map (its archive: image, nav points, paths) on schedule server
    ``server_id``; the result names its ``map_id`` there."""

    server_id: ServerId


class DownloadMapAction(ActionBase, kw_only=True, tag="download_map_action"):
    """Get map ``map_id`` from schedule server ``server_id`` into the robot's maps, under the
    name it was put with."""

    server_id: ServerId
    map_id: Annotated[str, Meta(pattern=r"^[0-9a-f]{32}$")]


AxisMode = Literal[0, 1, 2, 3]
"""An actuator move's mode (§9.2): 0 homing, 1 speed mode, 2 stop, 3 position mode."""


class SlideAction(ActionBase, kw_only=True, tag="slide_action"):
    """Move the slide rail: ``mode`` 3 to ``pose`` (m) at ``speed`` (m/s, 0: its default);
    1 at ``speed`` (signed) for ``time`` s; 0 homing; 2 stop."""

    mode: AxisMode = 3
    speed: Annotated[float, Meta(ge=-100, le=100)] = 0.0
    pose: Annotated[float, Meta(ge=-100, le=100)] = 0.0
    time: Annotated[float, Meta(ge=0, le=86400)] = 0.0


class JackingAction(SlideAction, kw_only=True, tag="jacking_action"):
    """Move the jacking lift: the fields of ``slide_action``."""


class JackingRotateAction(ActionBase, kw_only=True, tag="jacking_rotate_action"):
    """Turn the lift's top: ``mode`` 3 to ``angle`` (rad) in ``frame_id`` (``base_link``, or
    ``map``: a heading on the map, from the robot's pose when the move starts) at ``speed``
    (rad/s, 0: its default); 1 at ``speed`` (signed) for ``time`` s; 0 homing; 2 stop."""

    mode: AxisMode = 3
    speed: Annotated[float, Meta(ge=-100, le=100)] = 0.0
    angle: Annotated[float, Meta(ge=-100, le=100)] = 0.0
    time: Annotated[float, Meta(ge=0, le=86400)] = 0.0
    frame_id: Literal["base_link", "map"] = "base_link"


class OnvifCameraMoveAction(ActionBase, kw_only=True, tag="onvif_camera_move_action"):
    """Move the PTZ camera to ``x``, ``y`` (-1..1: pan right, tilt up) and ``zoom`` (0..1),
    ONVIF's normalised units, and wait until it gets there. ``ip``, ``port``, ``username``
    and ``password`` name the camera (§17); the simulated robot has one, reached over
    Zenoh, so they are kept and not used."""

    ip: Annotated[str, Meta(max_length=128)] = ""
    port: Annotated[int, Meta(ge=0, le=65535)] = 0
    username: Annotated[str, Meta(max_length=128)] = ""
    password: Annotated[str, Meta(max_length=128)] = ""
    x: Annotated[float, Meta(ge=-1, le=1)] = 0.0
    y: Annotated[float, Meta(ge=-1, le=1)] = 0.0
    zoom: Annotated[float, Meta(ge=0, le=1)] = 0.0


CameraTopic = Literal["/camera_node/image_raw", "/multi/front/image_raw",
                      "/multi/back/image_raw", "/ptz_camera/image_raw"]
FileName = Annotated[str, Meta(max_length=128)]
Timestamp = Annotated[int, Meta(ge=0, le=10**14)]


class ImageAction(ActionBase, kw_only=True, tag="image_action"):
    """A snapshot of camera ``topic`` into the robot's Pictures, as ``<timestamp>.png`` (ms;
    default: now), through the gateway (``media/save``)."""

    topic: CameraTopic = "/camera_node/image_raw"
    timestamp: Timestamp | UnsetType = UNSET


class VideoRecordAction(ActionBase, kw_only=True, tag="video_record_action"):
    """``duration`` seconds of camera ``topic`` into the robot's Videos, as ``filename`` or
    ``<timestamp>.mkv`` (ms; default: now); done once recorded. ``video_url`` (an RTSP
    source) is refused: the robot records its own cameras."""

    timestamp: Timestamp | UnsetType = UNSET
    duration: Annotated[int, Meta(ge=1, le=600)] = 10
    topic: CameraTopic = "/camera_node/image_raw"
    video_url: Annotated[str, Meta(max_length=512)] = ""
    filename: FileName = ""


class AudioRecordAction(ActionBase, kw_only=True, tag="audio_record_action"):
    """``duration`` seconds of the robot's microphone into its Audios, as ``filename`` or
    ``<timestamp>.wav`` (ms; default: now), through the gateway (``media/save``); done once
    recorded."""

    timestamp: Timestamp | UnsetType = UNSET
    duration: Annotated[int, Meta(ge=1, le=600)] = 10
    filename: FileName = ""


class OnvifCameraSnapshotAction(ActionBase, kw_only=True, tag="onvif_camera_snapshot_action"):
    """A snapshot of the PTZ camera into the robot's Pictures. ``ip``, ``port``,
    ``username``, ``password`` and ``channel`` name the camera (§17); the simulated robot has
    one, reached over Zenoh, so they are kept and not used."""

    ip: Annotated[str, Meta(max_length=128)] = ""
    port: Annotated[int, Meta(ge=0, le=65535)] = 0
    username: Annotated[str, Meta(max_length=128)] = ""
    password: Annotated[str, Meta(max_length=128)] = ""
    channel: Annotated[int, Meta(ge=0, le=16)] = 0


class BlocklyAction(ActionBase, kw_only=True, tag="blockly_action"):
    """Run Blockly program ``api_key`` (its id, docs/robot-api.md §10): its blocks are
    interpreted, step by step; its Python text is never run."""

    api_key: Annotated[str, Meta(min_length=1, max_length=64)]


Floor = Annotated[int, Meta(ge=-1000, le=1000)]
ElevatorName = Annotated[str, Meta(pattern=r"^[A-Za-z0-9_]{0,64}$")]
"""A car of the building (docs/building.md); "": the building's first elevator."""


class ElevatorReqAction(ActionBase, kw_only=True, tag="elevator_req_action"):
    """Call car ``elevator_name`` to floor ``level`` as this robot; complete once it stands
    there with its doors open for the robot (it then holds them, ``WAITING_IN``).
    ``direction`` (the hall button pressed) is kept: the simulated controller serves calls
    first come, first served."""

    level: Floor
    direction: Literal["up", "down", ""] = ""
    elevator_name: ElevatorName = ""
    timeout: Seconds = 0.0  # 0: no limit (a silent controller still ends it)


class LbtElevatorReqAction(ActionBase, kw_only=True, tag="lbt_elevator_req_action"):
    """A request to the elevator controller for a ride from ``from_level`` to
    ``to_level``: ``cmd`` ``enter`` calls the car to ``from_level`` and completes once it
    stands open there, holding its doors until ``lbt_elevator_ack_action``; ``leave``
    completes once the car stands open at ``to_level``, holding its doors until the ack."""

    from_level: Floor
    to_level: Floor
    cmd: Literal["enter", "leave"]
    elevator_name: ElevatorName = ""
    timeout: Seconds = 0.0  # 0: no limit (a silent controller still ends it)


class LbtElevatorAckAction(ActionBase, kw_only=True, tag="lbt_elevator_ack_action"):
    """Tell the controller the robot has entered (the car rides to the request's
    ``to_level``) or left (the car is released) after ``lbt_elevator_req_action``."""


class NoneStopNavAction(ActionBase, kw_only=True, tag="none_stop_nav_action"):
    """Drive toward (``x``, ``y``) in ``map`` and complete, without stopping, once the robot
    is within ``radius`` m of it: the next goal replaces this one; the task's end stops it."""

    x: Coordinate
    y: Coordinate
    radius: Annotated[float, Meta(gt=0, le=100)] = 0.5
    timeout: Seconds = 0.0  # 0: no limit


Settings = Annotated[dict[str, Any], Meta(min_length=1, max_length=64)]


class ChangeSettingAction(ActionBase, kw_only=True, tag="change_setting_action"):
    """Change ``/system/config`` keys (the gateway's settings) to ``settings``; when the
    enclosing task ends, ``init_settings`` (if given) are set back."""

    settings: Settings
    init_settings: Settings | UnsetType = UNSET


LAUNCH_CMD: Final = re.compile(
    r"^\s*(?:(?:roslaunch|zenros\s+launch)\s+)?(?:(?P<pkg>[A-Za-z0-9_.-]+)\s+)?"
    r"(?P<file>[A-Za-z0-9_-]+)(?:\.launch|\.ya?ml)?"
    r"(?P<args>(?:\s+[A-Za-z_][A-Za-z0-9_]*:=[A-Za-z0-9_.,:/+@=-]*)*)\s*$")
"""``launch_cmd``: ``roslaunch <pkg> <file>.launch [name:=value ...]``, ``zenros launch
<file>.yaml [...]`` or ``<file>[.yaml] [...]``: a launch file by name, never a path."""


class RoslaunchAction(ActionBase, kw_only=True, tag="roslaunch_action"):
    """Start launch file ``<file>.yaml`` that zenros ships (``deploy/launch``), named as
    ``roslaunch <pkg> <file>.launch [name:=value ...]`` would; complete once its nodes are
    up. It runs until the enclosing task ends."""

    launch_cmd: Annotated[str, Meta(min_length=1, max_length=512)]


Action = (NavAction | SleepAction | ChargeAction | CallbackAction | WaitReqAction | TtsAction
          | SwitchMapAction | LocalMoveAction | LocalMoveTargetAction | IoAction
          | UploadMapAction | DownloadMapAction | SlideAction | JackingAction
          | JackingRotateAction | BlocklyAction | OnvifCameraMoveAction | ImageAction
          | VideoRecordAction | OnvifCameraSnapshotAction | ElevatorReqAction
          | LbtElevatorReqAction | LbtElevatorAckAction | NoneStopNavAction
          | ChangeSettingAction | RoslaunchAction | AudioRecordAction)
"""Any action; decode with ``msgspec.convert(obj, Action)`` (dispatch on ``type``)."""

ACTION_TYPES: Final[dict[str, type[ActionBase]]] = {
    str(cls.__struct_config__.tag): cls for cls in Action.__args__}

# fields every action document carries besides its parameters
COMMON_FIELDS: Final = frozenset({"id", "type", "state", "result", "progress",
                                  "current_location", "current_distance"})

_METHODS: Final = frozenset({"GET", "POST", "PUT", "DELETE", "PATCH", "HEAD"})


def check_action(action: ActionBase) -> None:
    """What the types cannot say: finite numbers, a nav goal's x and y (or index), a
    callback's URL scheme and method.

    Raises:
        ValueError: naming the field.
    """
    kind = action.__struct_config__.tag
    for name in action.__struct_fields__:
        v = getattr(action, name)
        if isinstance(v, float) and not math.isfinite(v):
            raise ValueError(f"({kind}): {name} must be a finite number, got {v}")
    if isinstance(action, NavAction) and action.index in (None, UNSET) and (
            action.x in (None, UNSET) or action.y in (None, UNSET)):
        raise ValueError("(nav_action): give x and y, or a nav point index")
    if isinstance(action, VideoRecordAction) and action.video_url:
        raise ValueError("(video_record_action): video_url sources are not recorded: the "
                         "robot records its own cameras (give topic)")
    if isinstance(action, LbtElevatorReqAction) and action.from_level == action.to_level:
        raise ValueError(f"(lbt_elevator_req_action): to_level must differ from from_level "
                         f"(both {action.from_level})")
    if isinstance(action, RoslaunchAction) and LAUNCH_CMD.match(action.launch_cmd) is None:
        raise ValueError(f"(roslaunch_action): launch_cmd {action.launch_cmd!r} is not "
                         "'roslaunch <package> <file>.launch [name:=value ...]' (or "
                         "'<file>.yaml [name:=value ...]'): a launch file zenros ships, by "
                         "name, never a path or a shell command")
    if isinstance(action, ChangeSettingAction):
        for field, given in (("settings", action.settings),
                             ("init_settings", action.init_settings)):
            if isinstance(given, dict):
                bad = [k for k in given if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]{0,63}", k)]
                if bad:
                    raise ValueError(f"(change_setting_action): {field}: {bad[0]!r} is not "
                                     "a configuration key name")
    if isinstance(action, CallbackAction):
        if not action.url.startswith(("http://", "https://")):
            raise ValueError(f"(callback_action): url must be http:// or https://, got "
                             f"{action.url!r}")
        if action.method.upper() not in _METHODS:
            raise ValueError(f"(callback_action): method {action.method!r} is not one of "
                             f"{', '.join(sorted(_METHODS))}")
