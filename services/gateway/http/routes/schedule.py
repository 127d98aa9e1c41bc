"""REST schedule mode (docs/robot-api.md §6.1 ``start_schedule_mode``,
``stop_schedule_mode``; §3.1 ``/system/schedule_manager``): nav's ``set_schedule_mode`` and
``get_schedule_mode``, which put the robot's navigation under the schedule server's traffic
schedule (docs/fleet.md, "Traffic schedule")."""

from __future__ import annotations

from typing import Annotated

import msgspec
from zenros.msgs import zenros_msgs as zm

from ...errors import PortError
from ..api import Answer, Call

__all__ = ["schedule_manager", "start_schedule_mode", "stop_schedule_mode"]


class ModeQuery(msgspec.Struct, forbid_unknown_fields=True):
    """``server_id``: the schedule server to follow ("" keeps nav's ``schedule_server``)."""

    server_id: Annotated[str, msgspec.Meta(pattern=r"^[A-Za-z0-9_]{0,64}$")] = ""


async def _set(call: Call[None, ModeQuery], on: bool) -> Answer:
    try:
        res = await call.ctx.nav_services.call(zm.SetScheduleMode, zm.SetScheduleModeRequest(
            enable=on, server_id=call.query.server_id))
    except PortError as exc:
        return {"result": False, "description": str(exc)}
    return {"result": res.code == 0 and res.status.enabled == on, "description": res.message}


async def start_schedule_mode(call: Call[None, ModeQuery]) -> Answer:
    """Navigate under the schedule manager: goals drive only where it grants."""
    return await _set(call, True)


async def stop_schedule_mode(call: Call[None, ModeQuery]) -> Answer:
    """Leave schedule mode: the robot's reservations are released."""
    return await _set(call, False)


async def schedule_manager(call: Call[None, None]) -> Answer:
    """The schedule manager the robot follows and whether schedule mode is on; empty when
    nav does not answer (no manager connected)."""
    try:
        res = await call.ctx.nav_services.call(zm.GetScheduleMode, zm.GetScheduleModeRequest())
    except PortError:
        return {}
    st = res.status
    return {"id": st.server_id, "schedule_mode": st.enabled, "state": st.state,
            "wait_for": st.wait_for, "segments": list(st.segments)}
