"""Messages about people: the simulated pedestrians, the UWB tag one of them carries, and the
robot following or greeting them.

- ``zenros_msgs/SetPeople`` (chassis ``sim/set_people``): add, replace, remove or clear the
  simulated people walking their routes; ``zenros_msgs/People`` on ``sim/people`` is their
  ground truth (for tests and visualisation, never for the robot's own use).
- ``zenros_msgs/UwbTarget`` on ``uwb/target``: the range and bearing of the UWB tag, as the
  robot's UWB anchor measures them (with noise).
- ``zenros_msgs/PersonDetections`` on ``people/detections``: the people nav's leg detector
  finds in ``scan`` (in ``base_link``).
- ``zenros_msgs/SetFollow`` (nav ``follow/set``) and ``zenros_msgs/GetFollowStatus``
  (``follow/status``): person following on the laser (``legs``) or the UWB tag (``uwb``).
"""

from __future__ import annotations

from typing import Literal

import msgspec

from ...message import Message, define_service
from ..geometry_msgs import Point
from ..std_msgs import Empty, Header

__all__ = [
    "FollowStatus",
    "GetFollowStatus",
    "GetFollowStatusResponse",
    "People",
    "Person",
    "PersonDetections",
    "PersonRoute",
    "SetFollow",
    "SetFollowRequest",
    "SetFollowResponse",
    "SetPeople",
    "SetPeopleRequest",
    "SetPeopleResponse",
    "UwbTarget",
]


class PersonRoute(Message):
    """A simulated person: walks through ``waypoints`` (x, y in ``map``; ``z`` unused) at
    ``speed`` m/s, back and forth (``loop`` false) or round (``loop`` true); ``uwb`` true:
    carries the UWB tag (one person at most)."""

    __msgtype__ = "zenros_msgs/PersonRoute"
    id: str = ""
    waypoints: list[Point] = msgspec.field(default_factory=list)
    speed: float = 1.0
    loop: bool = False
    uwb: bool = False


class Person(Message):
    """Where a simulated person is (``map``), heading ``theta``, and whether they wait for
    the robot in their way."""

    __msgtype__ = "zenros_msgs/Person"
    id: str = ""
    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0
    speed: float = 0.0
    waiting: bool = False
    uwb: bool = False


class People(Message):
    """The simulated people (ground truth), on ``sim/people``."""

    __msgtype__ = "zenros_msgs/People"
    header: Header = msgspec.field(default_factory=Header)
    people: list[Person] = msgspec.field(default_factory=list)


class SetPeopleRequest(Message):
    """``op``: ``set`` (add each route, or replace the person of the same id), ``replace``
    (the people become exactly ``people``), ``remove`` (those named in ``ids``), ``clear``."""

    __msgtype__ = "zenros_msgs/SetPeopleRequest"
    op: Literal["set", "replace", "remove", "clear"] = "set"
    people: list[PersonRoute] = msgspec.field(default_factory=list)
    ids: list[str] = msgspec.field(default_factory=list)


class SetPeopleResponse(Message):
    __msgtype__ = "zenros_msgs/SetPeopleResponse"
    success: bool = False
    message: str = ""
    people: list[Person] = msgspec.field(default_factory=list)


class UwbTarget(Message):
    """The UWB tag seen from the robot: ``range`` (m) and ``bearing`` (rad, left of the
    robot's heading positive) in ``base_link``, with the anchor's noise."""

    __msgtype__ = "zenros_msgs/UwbTarget"
    header: Header = msgspec.field(default_factory=Header)
    range: float = 0.0
    bearing: float = 0.0


class PersonDetections(Message):
    """People found by the leg detector, in ``base_link`` (``z`` unused), nearest first."""

    __msgtype__ = "zenros_msgs/PersonDetections"
    header: Header = msgspec.field(default_factory=Header)
    people: list[Point] = msgspec.field(default_factory=list)


class FollowStatus(Message):
    """Person following: ``mode`` ``legs`` or ``uwb`` while ``enabled``; ``following``
    while it has its person (``distance`` m, ``bearing`` rad in ``base_link``); ``state``
    ``off``, ``searching``, ``following``, ``lost``; ``message`` says why."""

    __msgtype__ = "zenros_msgs/FollowStatus"
    enabled: bool = False
    mode: str = ""
    following: bool = False
    state: str = "off"
    distance: float = 0.0
    bearing: float = 0.0
    message: str = ""


class SetFollowRequest(Message):
    """Start following in ``mode`` (``legs``, ``uwb``) when ``enable``, or stop that mode."""

    __msgtype__ = "zenros_msgs/SetFollowRequest"
    mode: Literal["legs", "uwb"] = "legs"
    enable: bool = False


class SetFollowResponse(Message):
    __msgtype__ = "zenros_msgs/SetFollowResponse"
    success: bool = False
    message: str = ""
    status: FollowStatus = msgspec.field(default_factory=FollowStatus)


class GetFollowStatusResponse(Message):
    __msgtype__ = "zenros_msgs/GetFollowStatusResponse"
    status: FollowStatus = msgspec.field(default_factory=FollowStatus)


SetPeople = define_service("zenros_msgs/SetPeople", SetPeopleRequest, SetPeopleResponse)
SetFollow = define_service("zenros_msgs/SetFollow", SetFollowRequest, SetFollowResponse)
GetFollowStatus = define_service("zenros_msgs/GetFollowStatus", Empty, GetFollowStatusResponse)
