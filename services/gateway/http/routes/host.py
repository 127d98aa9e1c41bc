"""REST operations on the robot's host (docs/robot-api.md §3.3, §3.5).

``/system/restart_robot`` and ``/system/shutdown``: the robot's software restarted, or
stopped, for real, by the launch that supervises it (the gateway's `HostLink`); each answers
``{"result": true}`` once the launch has taken the request, which acts a second later, so the
answer reaches the client before the gateway itself stops. ``/system/wifi``,
``/system/restart_router``, ``/system/restart_novnc`` and ``/system/is_online`` run the
commands the operator configured (`HostCommands`), with the request's values checked.
"""

from __future__ import annotations

from typing import Annotated, Any

import msgspec

from ...ports.certificate import check_certificate
from ...ports.host_commands import HostCommands
from ...ports.host_link import HostLink
from ...ports.updater import Updater
from ..api import Answer, Api, ApiError, Call

__all__ = ["add_host_routes", "add_update_routes"]


class WifiQuery(msgspec.Struct, forbid_unknown_fields=True):
    ssid: Annotated[str, msgspec.Meta(min_length=1, max_length=32)]
    password: Annotated[str, msgspec.Meta(max_length=63)] = ""


class RouterQuery(msgspec.Struct, forbid_unknown_fields=True):
    type: Annotated[str, msgspec.Meta(min_length=1, max_length=32)]
    ip: Annotated[str, msgspec.Meta(min_length=1, max_length=64)]
    username: Annotated[str, msgspec.Meta(max_length=64)] = ""
    password: Annotated[str, msgspec.Meta(max_length=63)] = ""


def _commands(call: Call[Any, Any]) -> HostCommands:
    if call.ctx.commands is None:
        raise ApiError(501, "this gateway runs no host commands (no robot node)")
    return call.ctx.commands


async def _must_run(call: Call[Any, Any], op: str, values: dict[str, str]) -> None:
    try:
        await _commands(call).must_run(op, values)
    except ValueError as exc:
        raise ApiError(400, str(exc)) from exc


async def wifi(call: Call[None, WifiQuery]) -> Answer:
    """Join Wi-Fi network ``ssid`` with ``password`` (the operator's ``wifi`` command)."""
    q = call.query
    await _must_run(call, "wifi", {"ssid": q.ssid, "password": q.password})
    return {"status": "ok"}


async def restart_router(call: Call[None, RouterQuery]) -> Answer:
    """Reboot the on-board router (the operator's ``restart_router`` command)."""
    q = call.query
    await _must_run(call, "restart_router", {"type": q.type, "ip": q.ip,
                                             "username": q.username, "password": q.password})
    return {"status": "ok"}


async def restart_novnc(call: Call[None, None]) -> Answer:
    """Restart the remote desktop (the operator's ``restart_novnc`` command)."""
    await _must_run(call, "restart_novnc", {})
    return {"result": True}


async def is_online(call: Call[None, None]) -> Answer:
    """Whether the robot is online: the operator's ``is_online`` command exits 0."""
    code, _ = await _commands(call).run("is_online")
    return {"result": code == 0}


async def check_cert(call: Call[None, None]) -> Answer:
    """The gateway's TLS certificate, read from its file now: ``status`` (``ok``, ``expired``,
    ``not yet valid``), subject, issuer, validity and ``days_left``."""
    return check_certificate(call.ctx.tls_cert)


def _host(call: Call[None, None]) -> HostLink:
    host = call.ctx.host
    if host is None:
        raise ApiError(501, "this gateway has no robot host to act on")
    return host


async def restart_robot(call: Call[None, None]) -> Answer:
    """Restart the robot's services (every process of its launch, this gateway included)."""
    await _host(call).restart()
    return {"result": True}


async def shutdown(call: Call[None, None]) -> Answer:
    """Stop the robot's services (and power the robot off where the launch was given an
    ``--on-shutdown`` command)."""
    await _host(call).shutdown()
    return {"result": True}


def add_host_routes(api: Api) -> None:
    """Route the host's operations."""
    api.add("GET", "/system/restart_robot", restart_robot)
    api.add("GET", "/system/shutdown", shutdown)
    api.add("GET", "/system/wifi", wifi)
    api.add("GET", "/system/restart_router", restart_router)
    api.add("GET", "/system/restart_novnc", restart_novnc)
    api.add("GET", "/system/is_online", is_online)
    api.add("GET", "/system/check_cert", check_cert)


class UseDevBody(msgspec.Struct, forbid_unknown_fields=True):
    use_dev: bool


def _updater(call: Call[Any, Any]) -> Updater:
    if call.ctx.updater is None:
        raise ApiError(501, "this gateway updates nothing (no robot node)")
    return call.ctx.updater


async def update_check(call: Call[None, None]) -> Answer:
    """Whether the update source has a newer version: ``need_update``, ``current``,
    ``latest``."""
    return await _updater(call).check()


async def update_start(call: Call[None, None]) -> Answer:
    """Start updating in the background (``allow_update`` must be on)."""
    updater = _updater(call)
    if not updater.allowed:
        raise ApiError(403, "updates are off: set \"allow_update\": true in the gateway's "
                            "configuration file")
    await updater.start()
    return {"status": "updating"}


async def update_cancel(call: Call[None, None]) -> Answer:
    """Stop the update under way."""
    await _updater(call).cancel()
    return {"status": "cancelled"}


async def update_log(call: Call[None, None]) -> Answer:
    """The update's ``status``, ``log`` (pip's output) and ``is_complete``."""
    return _updater(call).log()


async def get_use_dev(call: Call[None, None]) -> Answer:
    """Whether updates take pre-releases (the development channel)."""
    return {"use_dev": _updater(call).use_dev}


async def put_use_dev(call: Call[UseDevBody, None]) -> Answer:
    """Take pre-releases in updates, or not."""
    updater = _updater(call)
    updater.set_use_dev(call.body.use_dev)
    return {"use_dev": updater.use_dev}


def add_update_routes(api: Api) -> None:
    """Route §3.4's updates and the development channel."""
    api.add("GET", "/system/update/check", update_check)
    api.add("GET", "/system/update/start", update_start)
    api.add("GET", "/system/update/cancel", update_cancel)
    api.add("GET", "/system/update/log", update_log)
    api.add("GET", "/system/use_dev", get_use_dev)
    api.add("PUT", "/system/use_dev", put_use_dev)
