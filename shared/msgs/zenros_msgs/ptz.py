"""zenros_msgs for the chassis's simulated pan-tilt-zoom (ONVIF) camera (docs/chassis.md,
PTZ camera).

- ``zenros_msgs/PtzState`` on ``ptz_camera/state``: where the camera points, in the ONVIF
  normalised units and in physical ones, whether it moves, its presets.
- ``zenros_msgs/MovePtz`` (``ptz_camera/move``): an absolute move (ONVIF ``AbsoluteMove``).
- ``zenros_msgs/MovePtzSpeed`` (``ptz_camera/move_speed``): a continuous move at speeds
  (ONVIF ``ContinuousMove``); all zeros stop it.
- ``zenros_msgs/GotoPtzPreset`` (``ptz_camera/goto_preset``): to a preset, by name or token.
- ``zenros_msgs/GetPtzTemperature`` (``ptz_camera/temperature``): the thermal reading of the
  current view, per rule (one rule: the whole frame).

Units: ``x`` (pan) and ``y`` (tilt) are -1..1 over the camera's ranges, ``+x`` to the right
(clockwise seen from above) and ``+y`` up, as ONVIF's generic spaces; ``zoom_ratio`` 0..1
over 1x..``zoom_max``. ``pan`` and ``tilt`` are radians with the same signs, ``zoom`` the
magnification (the field of view is ``hfov`` = base field of view / ``zoom``).
"""

from __future__ import annotations

import msgspec

from ...message import Message, define_service
from ..std_msgs import Header

__all__ = [
    "GetPtzTemperature",
    "GetPtzTemperatureRequest",
    "GetPtzTemperatureResponse",
    "GotoPtzPreset",
    "GotoPtzPresetRequest",
    "MovePtz",
    "MovePtzRequest",
    "MovePtzSpeed",
    "MovePtzSpeedRequest",
    "PtzMoveResponse",
    "PtzState",
    "ThermalRule",
]


class PtzState(Message):
    """The camera's position and limits, published on ``ptz_camera/state`` at 10 Hz while
    someone listens, and when a move ends.

    ``x``, ``y``, ``zoom_ratio``: the normalised position (module docstring); ``pan``,
    ``tilt`` (rad), ``zoom`` (x) and ``hfov`` (rad): the physical one; ``pan_min`` ..
    ``zoom_max``: the ranges; ``moving``: an absolute or continuous move is under way;
    ``presets``: the preset names, token ``i + 1`` for ``presets[i]``; ``width`` x
    ``height``, ``frame_rate`` (per sim second) and ``jpeg_quality``: its video's.
    """

    __msgtype__ = "zenros_msgs/PtzState"
    header: Header = msgspec.field(default_factory=Header)
    x: float = 0.0
    y: float = 0.0
    zoom_ratio: float = 0.0
    pan: float = 0.0
    tilt: float = 0.0
    zoom: float = 1.0
    hfov: float = 0.0
    pan_min: float = 0.0
    pan_max: float = 0.0
    tilt_min: float = 0.0
    tilt_max: float = 0.0
    zoom_max: float = 1.0
    moving: bool = False
    presets: list[str] = msgspec.field(default_factory=list)
    width: int = 0
    height: int = 0
    frame_rate: float = 0.0
    jpeg_quality: int = 0


class MovePtzRequest(Message):
    """Move to ``x``, ``y`` (-1..1) and ``zoom`` (0..1), each axis at its top speed."""

    __msgtype__ = "zenros_msgs/MovePtzRequest"
    x: float = 0.0
    y: float = 0.0
    zoom: float = 0.0


class MovePtzSpeedRequest(Message):
    """Move at ``speed_x``, ``speed_y``, ``speed_zoom`` (-1..1, fractions of each axis's top
    speed) until an axis's limit or a stop (all zeros)."""

    __msgtype__ = "zenros_msgs/MovePtzSpeedRequest"
    speed_x: float = 0.0
    speed_y: float = 0.0
    speed_zoom: float = 0.0


class GotoPtzPresetRequest(Message):
    """Go to the preset named ``preset`` (or its token, ``"1"`` for the first)."""

    __msgtype__ = "zenros_msgs/GotoPtzPresetRequest"
    preset: str = ""


class PtzMoveResponse(Message):
    """``success`` false with the reason in ``message`` (a value out of range, an unknown
    preset); ``not_found`` marks an unknown preset; ``state``: the camera after the request."""

    __msgtype__ = "zenros_msgs/PtzMoveResponse"
    success: bool = False
    message: str = ""
    not_found: bool = False
    state: PtzState = msgspec.field(default_factory=PtzState)


class ThermalRule(Message):
    """One thermometry rule's reading (degrees Celsius) over its area of the frame; the
    points are normalised, 0..1 from the frame's left (``x``) and top (``y``)."""

    __msgtype__ = "zenros_msgs/ThermalRule"
    id: int = 1
    max_temperature: float = 0.0
    min_temperature: float = 0.0
    average_temperature: float = 0.0
    max_x: float = 0.0
    max_y: float = 0.0
    min_x: float = 0.0
    min_y: float = 0.0
    frozen: bool = False


class GetPtzTemperatureRequest(Message):
    """The thermal reading of the view now."""

    __msgtype__ = "zenros_msgs/GetPtzTemperatureRequest"


class GetPtzTemperatureResponse(Message):
    """``rules``: rule 1 is the whole frame; ``width`` x ``height``: the thermal image's
    size the points were found on; ``state``: where the camera pointed."""

    __msgtype__ = "zenros_msgs/GetPtzTemperatureResponse"
    success: bool = False
    message: str = ""
    rules: list[ThermalRule] = msgspec.field(default_factory=list)
    width: int = 0
    height: int = 0
    state: PtzState = msgspec.field(default_factory=PtzState)


MovePtz = define_service("zenros_msgs/MovePtz", MovePtzRequest, PtzMoveResponse)
MovePtzSpeed = define_service("zenros_msgs/MovePtzSpeed", MovePtzSpeedRequest, PtzMoveResponse)
GotoPtzPreset = define_service("zenros_msgs/GotoPtzPreset", GotoPtzPresetRequest,
                               PtzMoveResponse)
GetPtzTemperature = define_service("zenros_msgs/GetPtzTemperature", GetPtzTemperatureRequest,
                                   GetPtzTemperatureResponse)
