"""REST ``/token`` and ``/system/...``: status, info, GalileoStatus, speed, config
(docs/robot-api.md §2, §3)."""

from __future__ import annotations

from typing import Annotated, Any

import msgspec

from ...state.settings import KEYS, SettingsPatch
from ...state.status import system_status_name
from ..api import Answer, Api, ApiError, Call

__all__ = ["add_system_routes"]

Lin = Annotated[float, msgspec.Meta(ge=-3.0, le=3.0)]
Ang = Annotated[float, msgspec.Meta(ge=-6.3, le=6.3)]
Text = Annotated[str, msgspec.Meta(max_length=256)]


class TokenQuery(msgspec.Struct, forbid_unknown_fields=True):
    username: Text = "admin"
    password: Text = "admin"


class SpeedBody(msgspec.Struct, forbid_unknown_fields=True):
    """speed_x, speed_y (m/s), speed_angle (rad/s, counter-clockwise)."""

    speed_x: Lin = 0.0
    speed_y: Lin = 0.0
    speed_angle: Ang = 0.0


class ConfigKey(msgspec.Struct, forbid_unknown_fields=True):
    key: Text


async def token(call: Call[None, TokenQuery]) -> Answer:
    """Get an access token (§2): ``result`` and ``token``."""
    core = call.ctx.core
    q = call.query
    tok = core.tokens.issue(q.username, q.password)
    if tok is None:
        raise ApiError(401, "wrong username or password")
    return {"result": True, "token": tok}


async def status(call: Call[None, None]) -> Answer:
    """Robot state: ``Mapping``, ``Navigating``, ``Busy`` or ``Free`` (§3.1)."""
    core = call.ctx.core
    return {"status": system_status_name(core.status)}


async def info(call: Call[None, None]) -> Answer:
    """Battery, sensor rates, charge, loop and version info (§3.1)."""
    core = call.ctx.core
    s = core.state
    ident = core.identity
    st = core.status
    return {
        "battery": round(s.battery_percent),
        "camera_rgb": 0, "camera_depth": 0, "camera_processed": 0,
        "odom": s.odom_rate(), "imu": 0,
        "driver_port": s.odom_rate() > 0,
        "info": {"version": ident.version, "code_name": ident.code_name, "id": ident.id,
                 "mac": ident.mac, "port": ident.port},
        "charge": st.chargeStatus in (1, 2), "loop": bool(st.loopStatus),
        "slam_type": core.settings.current.slam_type,
        "mapping": call.ctx.slam.summary() if call.ctx.slam is not None else None,
    }


async def galileo_status(call: Call[None, None]) -> Answer:
    """The latest GalileoStatus (§4)."""
    core = call.ctx.core
    return core.status


async def get_speed(call: Call[None, None]) -> Answer:
    """Current velocity: ``speed_x``, ``speed_y`` (m/s), ``speed_angle`` (rad/s) (§3.2)."""
    core = call.ctx.core
    st = core.status
    return {"speed_x": st.currentSpeedX, "speed_y": 0.0, "speed_angle": st.currentSpeedTheta}


async def put_speed(call: Call[SpeedBody, None]) -> Answer:
    """Velocity command; holds 0.5 s (dead-man), repeat it for continuous motion (§3.2)."""
    core = call.ctx.core
    b = call.body
    limit = core.settings.current.max_control_speed
    if abs(b.speed_x) > limit or abs(b.speed_y) > limit:
        raise ApiError(400, f"speed over max_control_speed ({limit} m/s)")
    core.deadman.command(b.speed_x, b.speed_y, b.speed_angle)
    return {"result": True}


async def get_config(call: Call[None, None]) -> Answer:
    """Navigation configuration (§3.6): ``default_map``, ``maps``, ``auto_charge``, ..."""
    core = call.ctx.core
    out = core.settings.as_dict()
    maps = core.services.get("maps")
    names, current = await maps() if maps is not None else ([], "")
    out["maps"] = names
    if not out["default_map"]:
        out["default_map"] = current
    return out


# Call[Any, ...]: SettingsPatch is a type made at run time, so `add` is given it by name
async def post_config(call: Call[Any, None]) -> Answer:
    """Change any subset of the configuration keys; returns the full configuration."""
    core = call.ctx.core
    core.settings.update(call.body)
    return await get_config(call)


async def delete_config(call: Call[None, ConfigKey]) -> Answer:
    """Reset one key to its default (§3.6)."""
    core = call.ctx.core
    key = call.query.key
    if key not in KEYS:
        raise ApiError(400, f"unknown config key {key!r}; known: {', '.join(KEYS)}")
    core.settings.reset(key)
    return {"status": "ok"}


def add_system_routes(api: Api) -> None:
    """Add the token and system operations the gateway implements to ``api``."""
    api.add("GET", "/token", token, public=True, result_style=True)
    api.add("GET", "/system/status", status)
    api.add("GET", "/system/info", info)
    api.add("GET", "/system/galileo_status", galileo_status)
    api.add("GET", "/system/speed", get_speed)
    api.add("PUT", "/system/speed", put_speed, result_style=True)
    api.add("GET", "/system/config", get_config)
    api.add("POST", "/system/config", post_config, body=SettingsPatch)
    api.add("DELETE", "/system/config", delete_config)
