"""REST ``/system/onvif_camera*`` (docs/robot-api.md §17): the simulated PTZ (ONVIF) camera,
fixed in the world and watching the robot (`ports.ptz_link.PtzLink`).

Every operation takes the camera's ``ip``, ``port``, ``username`` and ``password``, each
optional: another address is a 404, wrong credentials a 401 when the gateway's configuration
sets ``onvif_username``. Positions are ONVIF's normalised units: ``x`` (pan) and ``y``
(tilt) -1..1 over the camera's ranges, +x to the right and +y up; ``zoom`` 0..1 over 1x to
its top zoom. The stream is MJPEG over HTTP on this server (``/system/onvif_camera/mjpeg``),
which a browser's ``<img src>`` shows.
"""

from __future__ import annotations

from collections.abc import AsyncIterator
from typing import Annotated, Any
from urllib.parse import urlencode

import msgspec
from starlette.responses import StreamingResponse
from zenros.msgs.zenros_msgs import MovePtzRequest, MovePtzSpeedRequest, PtzMoveResponse, PtzState

from ...ports.media_folder import MediaError
from ...ports.ptz_link import BadCredentials, PtzLink
from ...ports.snapshots import PTZ_TOPIC
from ..api import Answer, Api, ApiError, Call

__all__ = ["BOUNDARY", "add_onvif_routes"]

BOUNDARY = "zenrosframe"
Text = Annotated[str, msgspec.Meta(max_length=128)]


class CameraQuery(msgspec.Struct, forbid_unknown_fields=True):
    """Which camera, and the credentials (all optional: there is one camera)."""

    ip: Text | None = None
    port: Annotated[int, msgspec.Meta(ge=0, le=65535)] | None = None
    username: Text | None = None
    password: Text | None = None


class ChannelQuery(CameraQuery, forbid_unknown_fields=True):
    channel: int | None = None


class MoveQuery(CameraQuery, forbid_unknown_fields=True):
    x: float | None = None
    y: float | None = None
    zoom: float | None = None


class SpeedQuery(CameraQuery, forbid_unknown_fields=True):
    speed_x: float = 0.0
    speed_y: float = 0.0
    speed_zoom: float = 0.0


class PresetQuery(CameraQuery, forbid_unknown_fields=True, kw_only=True):
    preset: Annotated[str, msgspec.Meta(min_length=1, max_length=64)]


def _camera(call: Call[Any, Any]) -> PtzLink:
    """The camera the query names, its credentials checked."""
    link = call.ctx.ptz
    if link is None:
        raise ApiError(503, "this gateway has no robot whose PTZ camera it could reach")
    q: CameraQuery = call.query
    try:
        link.address.check(q.ip, q.port, q.username, q.password)
    except BadCredentials as exc:
        raise ApiError(401, str(exc)) from exc
    if isinstance(q, ChannelQuery) and q.channel not in (None, 1):
        raise ApiError(404, f"no channel {q.channel}: the camera has one, channel 1")
    return link


def _done(res: PtzMoveResponse) -> Answer:
    return {"status": "ok", "description": res.message}


def _profile(link: PtzLink, state: PtzState) -> dict[str, Any]:
    """The camera's one media profile, ONVIF's fields from the simulated camera's values."""
    size = {"width": state.width, "height": state.height}
    return {
        "token": "Profile_1", "name": "mainStream",
        "video_source": {"token": "VideoSource_1", "framerate": state.frame_rate,
                         "resolution": size},
        "video_encoder": {"token": "VideoEncoder_1", "encoding": "JPEG", "resolution": size,
                          "quality": state.jpeg_quality, "frame_rate_limit": state.frame_rate,
                          "multicast": False},
        "ptz": {"token": "PTZ_1", "presets": [{"token": str(i + 1), "name": name}
                                                for i, name in enumerate(state.presets)],
                "pan_range_rad": [state.pan_min, state.pan_max],
                "tilt_range_rad": [state.tilt_min, state.tilt_max],
                "zoom_range": [1.0, state.zoom_max]},
        "address": {"ip": link.address.ip, "port": link.address.port},
    }


async def cameras(call: Call[None, CameraQuery]) -> Answer:
    """The cameras found (``{ip, port}``); with ``ip``, ``port``, ``username`` or
    ``password``, the media profiles of that camera."""
    q = call.query
    link = _camera(call)
    if (q.ip, q.port, q.username, q.password) == (None, None, None, None):
        found = link.present()
        return {"cameras": [{"ip": link.address.ip, "port": link.address.port}] if found
                else []}
    return {"profiles": [_profile(link, await link.current())]}


async def stream(call: Call[None, ChannelQuery]) -> Answer:
    """The camera's stream URL: MJPEG over HTTP on this server."""
    link = _camera(call)
    await link.current()
    q = call.query
    scheme = "https" if call.ctx.tls_cert else "http"
    base = call.path.rstrip("/").rsplit("/", 1)[0]  # .../onvif_camera (a fleet: per robot)
    params = {k: v for k, v in (("token", call.token), ("username", q.username),
                                ("password", q.password)) if v}
    query = "?" + urlencode(params) if params else ""
    a = link.address
    return {"stream": f"{scheme}://{a.ip}:{a.port}{base}/mjpeg{query}"}


async def mjpeg(call: Call[None, ChannelQuery]) -> Answer:
    """The camera's video as MJPEG (``multipart/x-mixed-replace``, one JPEG a frame)."""
    link = _camera(call)
    await link.current()
    frames = link.frames()

    async def parts() -> AsyncIterator[bytes]:
        async for jpeg in frames:
            yield (f"--{BOUNDARY}\r\nContent-Type: image/jpeg\r\n"
                   f"Content-Length: {len(jpeg)}\r\n\r\n").encode() + jpeg + b"\r\n"

    return StreamingResponse(parts(), media_type=f"multipart/x-mixed-replace; boundary={BOUNDARY}",
                             headers={"Cache-Control": "no-cache"})


async def move(call: Call[None, MoveQuery]) -> Answer:
    """Move to ``x``, ``y`` (-1..1) and ``zoom`` (0..1); one left out stays where it is."""
    link = _camera(call)
    q = call.query
    now = await link.current()
    req = MovePtzRequest(x=now.x if q.x is None else q.x, y=now.y if q.y is None else q.y,
                         zoom=now.zoom_ratio if q.zoom is None else q.zoom)
    return _done(await link.move(req))


async def move_speed(call: Call[None, SpeedQuery]) -> Answer:
    """Move at ``speed_x``, ``speed_y``, ``speed_zoom`` (-1..1 of the top speeds) until a
    limit or a stop (all zeros)."""
    q = call.query
    return _done(await _camera(call).move_speed(MovePtzSpeedRequest(
        speed_x=q.speed_x, speed_y=q.speed_y, speed_zoom=q.speed_zoom)))


async def goto_preset(call: Call[None, PresetQuery]) -> Answer:
    """Go to the preset named ``preset`` (or its token, 1 for the first)."""
    return _done(await _camera(call).goto_preset(call.query.preset))


async def snapshot(call: Call[None, ChannelQuery]) -> Answer:
    """Save the camera's next frame as a PNG in Pictures (listed in
    ``/system/saved_images``)."""
    link = _camera(call)
    await link.current()
    snapshots = call.ctx.snapshots
    if snapshots is None:
        raise ApiError(503, "this gateway saves no pictures (no robot node)")
    try:
        path = await snapshots.take(PTZ_TOPIC)
    except MediaError as exc:
        raise ApiError(exc.status, str(exc)) from exc
    base = call.path.rstrip("/").rsplit("/", 2)[0]  # /api/v1/system
    return {"snapshot": path.name, "file_timestamp": path.stem,
            "url": f"{base}/saved_images/{path.stem}"}


async def temperature(call: Call[None, CameraQuery]) -> Answer:
    """The thermal reading of the view now: one rule, the whole frame (C; points 0..1
    from the left and the top)."""
    res = await _camera(call).temperature()
    rules = [{"id": r.id, "maxTemperature": r.max_temperature,
              "minTemperature": r.min_temperature,
              "averageTemperature": r.average_temperature,
              "MaxTemperaturePoint": {"positionX": round(r.max_x, 4),
                                      "positionY": round(r.max_y, 4)},
              "MinTemperaturePoint": {"positionX": round(r.min_x, 4),
                                      "positionY": round(r.min_y, 4)},
              "isFreezedata": r.frozen} for r in res.rules]
    return {"temperature": {"ThermometryRulesTemperatureInfoList": {
        "ThermometryRulesTemperatureInfo": rules}}}


async def pose(call: Call[None, CameraQuery]) -> Answer:
    """Where the camera points: ``x``, ``y`` (-1..1) and ``zoom`` (0..1)."""
    state = await _camera(call).current()
    return {"x": round(state.x, 4), "y": round(state.y, 4), "zoom": round(state.zoom_ratio, 4)}


def add_onvif_routes(api: Api) -> None:
    """Route the §17 camera operations and the camera's MJPEG stream."""
    api.add("GET", "/system/onvif_cameras", cameras)
    api.add("GET", "/system/onvif_camera/stream", stream)
    api.add("GET", "/system/onvif_camera/mjpeg", mjpeg, media_type="multipart/x-mixed-replace")
    api.add("GET", "/system/onvif_camera/move", move)
    api.add("GET", "/system/onvif_camera/goto_preset", goto_preset)
    api.add("GET", "/system/onvif_camera/move_speed", move_speed)
    api.add("GET", "/system/onvif_camera/snapshot", snapshot)
    api.add("GET", "/system/onvif_camera/temperature", temperature)
    api.add("GET", "/system/onvif_camera/pose", pose)
