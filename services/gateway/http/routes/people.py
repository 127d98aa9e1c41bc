"""REST person following and greeting (docs/robot-api.md §3.5): ``/system/tracking_mode``
(follow the nearest person on the laser's leg detector), ``/system/uwb_track`` (follow the
person carrying the UWB tag) and ``PUT /system/greeting`` (speak when a person comes near),
over nav's ``follow/set`` and ``follow/status`` (`ports.people_link.PeopleLink`)."""

from __future__ import annotations

from typing import Annotated, Any

import msgspec
from zenros.msgs.zenros_msgs import FollowStatus

from ...ports.people_link import PeopleLink
from ..api import Answer, Api, ApiError, Call

__all__ = ["add_people_routes"]


class EnableBody(msgspec.Struct, forbid_unknown_fields=True):
    enable: bool


class GreetingBody(msgspec.Struct, forbid_unknown_fields=True):
    greeting: bool
    text: Annotated[str, msgspec.Meta(min_length=1, max_length=200)] | None = None


def _link(call: Call[Any, Any]) -> PeopleLink:
    if call.ctx.people is None:
        raise ApiError(501, "this gateway has no robot whose following it could reach")
    return call.ctx.people


def _status(s: FollowStatus, mode: str) -> dict[str, Any]:
    """The status of following in ``mode``: on, whether it has its person (``state``
    searching, following, lost, off), where the person is (m, rad), and why."""
    on = s.enabled and s.mode == mode
    return {"following": on and s.following, "state": s.state if on else "off",
            "distance": s.distance if on else 0.0, "bearing": s.bearing if on else 0.0,
            "message": s.message if s.mode == mode else ""}


async def get_tracking(call: Call[None, None]) -> Answer:
    s = await _link(call).status()
    return {"tracking_flag": s.enabled and s.mode == "legs", **_status(s, "legs")}


async def put_tracking(call: Call[EnableBody, None]) -> Answer:
    """Follow the nearest person seen by the laser at about 1 m (409 while a goal runs)."""
    s = await _link(call).set_follow("legs", call.body.enable)
    return {"tracking_flag": s.enabled and s.mode == "legs", **_status(s, "legs")}


async def get_uwb(call: Call[None, None]) -> Answer:
    s = await _link(call).status()
    return {"enable": s.enabled and s.mode == "uwb", **_status(s, "uwb")}


async def put_uwb(call: Call[EnableBody, None]) -> Answer:
    """Follow the person carrying the UWB tag at about 1 m (409 while a goal runs)."""
    s = await _link(call).set_follow("uwb", call.body.enable)
    return {"status": "ok", "enable": s.enabled and s.mode == "uwb", **_status(s, "uwb")}


async def put_greeting(call: Call[GreetingBody, None]) -> Answer:
    """Greet (speak ``text``, once per approach) people coming within 1.5 m."""
    link = _link(call)
    await link.set_greeting(call.body.greeting, call.body.text)
    return {"greeting": link.greeting, "text": link.greeting_text}


def add_people_routes(api: Api) -> None:
    """Route the §3.5 rows about people: following and greeting."""
    api.add("GET", "/system/tracking_mode", get_tracking)
    api.add("PUT", "/system/tracking_mode", put_tracking)
    api.add("GET", "/system/uwb_track", get_uwb)
    api.add("PUT", "/system/uwb_track", put_uwb)
    api.add("PUT", "/system/greeting", put_greeting)
