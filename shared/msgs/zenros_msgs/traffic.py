"""The schedule manager's traffic schedule (docs/fleet.md, "Traffic schedule"): a robot in
schedule mode sends its route, the manager answers how far along it the robot may drive.

Services ``/schedule/<server_id>/request_route`` (`RequestRoute`) and ``release_route``
(`ReleaseRoute`) (`schedule_service`); the latched topic ``/schedule/<server_id>/
reservations`` (`TrafficReservations`) says who holds what. nav's ``set_schedule_mode``
and ``get_schedule_mode`` (in the robot's namespace) turn a robot's schedule mode on and
off and say what it does. ``code`` is a `ResultCode` and ``message`` says why when it is
not OK.
"""

from __future__ import annotations

import msgspec

from ...message import Message, define_service
from ..builtin_interfaces import Time

__all__ = [
    "GetScheduleMode", "GetScheduleModeRequest", "GetScheduleModeResponse", "ReleaseRoute",
    "ReleaseRouteRequest", "ReleaseRouteResponse", "RequestRoute", "RequestRouteRequest",
    "RequestRouteResponse", "RoutePose", "ScheduleModeStatus", "SegmentReservation",
    "SetScheduleMode", "SetScheduleModeRequest", "SetScheduleModeResponse",
    "TrafficReservations", "TrafficRobot",
]


class RoutePose(Message):
    """A point of a route in ``map``, and the seconds from the request the robot expects
    to be there."""

    __msgtype__ = "zenros_msgs/RoutePose"
    x: float = 0.0
    y: float = 0.0
    t: float = 0.0


class RequestRouteRequest(Message):
    """``robot``'s route on map ``map_name`` (its first point is where it stands); it renews
    the robot's lease for ``lease`` seconds (0: the manager's default)."""

    __msgtype__ = "zenros_msgs/RequestRouteRequest"
    robot: str = ""
    map_name: str = ""
    route: list[RoutePose] = msgspec.field(default_factory=list)
    lease: float = 0.0


class RequestRouteResponse(Message):
    """Drive route points ``[0, stop_index)``: all of them when ``granted``; else wait at
    ``stop`` (for ``wait_for``, when it names a robot). With ``must_yield`` the robot is on a
    deadlock and backs off to ``yield_to``; with ``step_aside`` it waits at ``yield_to``, off
    the route of the robot it waits for. ``segments`` are the narrow segments it holds."""

    __msgtype__ = "zenros_msgs/RequestRouteResponse"
    code: int = 0
    message: str = ""
    granted: bool = False
    stop_index: int = 0
    stop: RoutePose = msgspec.field(default_factory=RoutePose)
    wait_for: str = ""
    must_yield: bool = False
    yield_to: RoutePose = msgspec.field(default_factory=RoutePose)
    segments: list[int] = msgspec.field(default_factory=list)
    lease: float = 0.0
    step_aside: bool = False


class ReleaseRouteRequest(Message):
    __msgtype__ = "zenros_msgs/ReleaseRouteRequest"
    robot: str = ""


class ReleaseRouteResponse(Message):
    """``released`` is false when the manager held nothing for the robot."""

    __msgtype__ = "zenros_msgs/ReleaseRouteResponse"
    code: int = 0
    message: str = ""
    released: bool = False


class SegmentReservation(Message):
    """A narrow segment held: its cells' centres (``cell_size`` squares) and when its
    holder expects to be in it (seconds from the message's stamp)."""

    __msgtype__ = "zenros_msgs/SegmentReservation"
    segment: int = 0
    width: float = 0.0
    t_enter: float = 0.0
    t_exit: float = 0.0
    cells: list[RoutePose] = msgspec.field(default_factory=list)


class TrafficRobot(Message):
    """One robot in schedule mode: what it holds, whom it waits for and where."""

    __msgtype__ = "zenros_msgs/TrafficRobot"
    robot: str = ""
    holds: list[SegmentReservation] = msgspec.field(default_factory=list)
    wait_for: str = ""
    stop: list[RoutePose] = msgspec.field(default_factory=list)  # empty: not stopped
    must_yield: bool = False
    expires_in: float = 0.0


class TrafficReservations(Message):
    __msgtype__ = "zenros_msgs/TrafficReservations"
    server_id: str = ""
    map_name: str = ""
    stamp: Time = msgspec.field(default_factory=Time)
    cell_size: float = 0.0
    passing_width: float = 0.0
    robots: list[TrafficRobot] = msgspec.field(default_factory=list)


RequestRoute = define_service("zenros_msgs/RequestRoute", RequestRouteRequest,
                              RequestRouteResponse)
ReleaseRoute = define_service("zenros_msgs/ReleaseRoute", ReleaseRouteRequest,
                              ReleaseRouteResponse)


class ScheduleModeStatus(Message):
    """A robot's schedule mode (nav's ``get_schedule_mode``): on or off, the schedule
    server it follows, and what the traffic gate does now (``off``, ``idle``, ``driving``,
    ``waiting``, ``yielding``, ``no_answer``)."""

    __msgtype__ = "zenros_msgs/ScheduleModeStatus"
    enabled: bool = False
    server_id: str = ""
    state: str = "off"
    wait_for: str = ""
    segments: list[int] = msgspec.field(default_factory=list)


class SetScheduleModeRequest(Message):
    """Enter (``enable``) or leave schedule mode; ``server_id`` "" keeps nav's
    ``schedule_server`` parameter."""

    __msgtype__ = "zenros_msgs/SetScheduleModeRequest"
    enable: bool = False
    server_id: str = ""


class SetScheduleModeResponse(Message):
    __msgtype__ = "zenros_msgs/SetScheduleModeResponse"
    code: int = 0
    message: str = ""
    status: ScheduleModeStatus = msgspec.field(default_factory=ScheduleModeStatus)


class GetScheduleModeRequest(Message):
    __msgtype__ = "zenros_msgs/GetScheduleModeRequest"


class GetScheduleModeResponse(Message):
    __msgtype__ = "zenros_msgs/GetScheduleModeResponse"
    status: ScheduleModeStatus = msgspec.field(default_factory=ScheduleModeStatus)


SetScheduleMode = define_service("zenros_msgs/SetScheduleMode", SetScheduleModeRequest,
                                 SetScheduleModeResponse)
GetScheduleMode = define_service("zenros_msgs/GetScheduleMode", GetScheduleModeRequest,
                                 GetScheduleModeResponse)
