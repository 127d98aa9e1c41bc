"""REST extras the simulated robot honours truthfully: log, topic snapshots, self-test and
ROS parameters (docs/robot-api.md §3.1, §3.5), schedule mode (`schedule`); TTS is in
rest_tts."""

from __future__ import annotations

import asyncio
import json
from collections.abc import Callable
from typing import Annotated, Any

import msgspec
from zenros.errors import (
    InvalidParameterValueError,
    ParameterNotFoundError,
    ServiceError,
    ServiceUnavailableError,
    ZenrosError,
    ZenrosTimeout,
)
from zenros.msgs.diagnostic_msgs import DiagnosticStatus

from ...ports.topic_hub import Slot, TopicError, TopicHub
from ..api import Answer, Api, ApiError, Call
from .schedule import schedule_manager, start_schedule_mode, stop_schedule_mode

__all__ = ["add_extra_routes", "latest"]

TOPIC_WAIT = 3.0
SCAN_WAIT = 1.0  # s: a laser at 10 Hz answers within 0.1 s


class TopicQuery(msgspec.Struct, forbid_unknown_fields=True):
    topic_name: Annotated[str, msgspec.Meta(min_length=1, max_length=256)]


class ParamQuery(msgspec.Struct, forbid_unknown_fields=True):
    param: Annotated[str, msgspec.Meta(min_length=1, max_length=256)]


class ParamBody(msgspec.Struct, forbid_unknown_fields=True):
    param: Annotated[str, msgspec.Meta(min_length=1, max_length=256)]
    value: Any


async def _params(fn: Callable[[], Any]) -> Any:
    try:
        return await asyncio.to_thread(fn)
    except ParameterNotFoundError as exc:
        raise ApiError(404, str(exc)) from exc
    except (ServiceUnavailableError, ZenrosTimeout) as exc:
        raise ApiError(503, f"the parameter server (master) is not available: {exc}") from exc
    except (InvalidParameterValueError, ServiceError, ValueError) as exc:
        raise ApiError(400, str(exc)) from exc
    except ZenrosError as exc:
        raise ApiError(400, str(exc)) from exc


async def log(call: Call[None, None]) -> Answer:
    """The recent system log (``/rosout``), oldest first."""
    link = call.ctx.topics
    return {"log": "\n".join(link.log)}


async def _next(hub: TopicHub, name: str, within: float) -> str | None:
    """The next frame on topic ``name``, None when nothing came within ``within`` s; raises
    `TopicError` when the topic is not in the graph."""
    slot = Slot(asyncio.get_running_loop())
    hub.attach(name, slot)
    try:
        return await asyncio.wait_for(slot.get(), within)
    except TimeoutError:
        return None
    finally:
        hub.detach(name, slot)


async def latest(hub: TopicHub, name: str) -> bytes:
    """The next message on topic ``name`` as JSON (404: not in the graph; 504: nothing
    within TOPIC_WAIT s)."""
    try:
        frame = await _next(hub, name, TOPIC_WAIT)
    except TopicError as exc:
        raise ApiError(404, str(exc)) from exc
    if frame is None:
        raise ApiError(504, f"no message on {name} within {TOPIC_WAIT:g} s")
    return frame.encode()


async def topic(call: Call[None, TopicQuery]) -> Answer:
    """The latest message of ``topic_name`` as JSON (waits up to 3 s for one)."""
    hub = call.ctx.hub
    try:
        name = hub.resolve(call.query.topic_name)
    except TopicError as exc:
        raise ApiError(400, str(exc)) from exc
    return msgspec.Raw(await latest(hub, name))


async def wind_info(call: Call[None, None]) -> Answer:
    """The wind sensor's reading (``wind``, zenros_msgs/WindInfo): speed, gust maximum,
    Beaufort level and direction; 404 when the robot has no wind sensor in the graph."""
    hub = call.ctx.hub
    reading = json.loads(await latest(hub, hub.resolve("wind")))
    return {k: reading[k] for k in ("current_speed", "max_speed", "level", "direction")}


async def self_test(call: Call[None, None]) -> Answer:
    """Which parts are OK now: from the aggregated diagnostics (docs/diagnostics.md) where
    the aggregator reports the part (not ERROR or STALE), else whether its topic answers:
    motor driver (odom), lidar (a scan within `SCAN_WAIT` s), battery; the charger
    (chassis/state)."""
    topics = call.ctx.topics
    tree = topics.diagnostics()

    def reported(name: str) -> bool | None:
        status = tree.get(name) if tree is not None else None
        return None if status is None else status.level < DiagnosticStatus.ERROR

    def part(name: str, topic: str) -> bool:
        ok = reported(name)
        return topics.fresh(topic) if ok is None else ok

    lidar = reported("/Chassis/laser")
    if lidar is None:  # the gateway does not follow the scan (10 Hz a robot): listen once
        lidar = await _answers(call.ctx.hub, "scan", SCAN_WAIT)
    return {"motor_driver": part("/Chassis/motors", "odom"), "camera": False,
            "charge": topics.fresh("chassis/state"), "lidar": lidar,
            "bluetooth": False, "battery": part("/Chassis/battery", "battery_state")}


async def _answers(hub: TopicHub, topic: str, within: float) -> bool:
    """Whether ``topic`` (relative to the robot) delivers a message within ``within`` s."""
    try:
        return await _next(hub, hub.resolve(topic), within) is not None
    except TopicError:  # not in the graph
        return False


async def get_param(call: Call[None, ParamQuery]) -> Answer:
    """A parameter (or a namespace as an object) from the parameter server."""
    params = call.ctx.params
    name = call.query.param
    return {"value": await _params(lambda: params.get(name))}


async def put_param(call: Call[ParamBody, None]) -> Answer:
    """Set a parameter; answers the value stored."""
    params = call.ctx.params
    b = call.body
    await _params(lambda: params.set(b.param, b.value))
    return {"value": b.value}


def add_extra_routes(api: Api) -> None:
    """Route the extra system operations."""
    api.add("GET", "/system/log", log)
    api.add("GET", "/system/schedule_manager", schedule_manager)
    api.add("GET", "/navigation/start_schedule_mode", start_schedule_mode)
    api.add("GET", "/navigation/stop_schedule_mode", stop_schedule_mode)
    api.add("GET", "/system/topic", topic)
    api.add("GET", "/navigation/wind_info", wind_info)
    api.add("GET", "/system/self_test", self_test)
    api.add("GET", "/system/ros_params", get_param)
    api.add("PUT", "/system/ros_params", put_param)
