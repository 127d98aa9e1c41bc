"""REST map transfer (docs/robot-api.md §6.1, §6.3): live map updating while navigating
(``GET|PUT /navigation/update_map``), and one map in and out of the robot as an archive
(``download_map_from_robot``, ``upload_map_to_robot``; the layout is `zenros.maps.archive`'s,
the export and import `zenros.maps.transfer`'s).

An upload is checked whole (zip-slip, size, YAML, image, manifest, nav data) in a folder of
its own before nav's ``map_server/import_map`` copies it into the maps store, so a refused
upload leaves the stored maps untouched.
"""

from __future__ import annotations

import asyncio
from typing import Annotated, Any

import msgspec
from starlette.requests import Request
from starlette.responses import Response
from zenros.maps.archive import MAX_ARCHIVE, ArchiveError, read_archive
from zenros.maps.transfer import NavCall, export_map, import_map
from zenros.msgs import zenros_msgs as zm
from zenros.msgs.geometry_msgs import Pose2D

from ...errors import NotFound, PortError
from ..api import Answer, Api, ApiError, Call
from ..context import Context
from ..fields import Name
from ..forms import SLACK, read_form
from .mapping import slam_port

__all__ = ["add_map_transfer_routes"]


class UpdateMapBody(msgspec.Struct, forbid_unknown_fields=True):
    enabled: bool


class MapNameQuery(msgspec.Struct, forbid_unknown_fields=True):
    map_name: Name


class ServerQuery(msgspec.Struct, forbid_unknown_fields=True):
    server_id: Annotated[str, msgspec.Meta(pattern=r"^[A-Za-z0-9_]{1,64}$")]


class DownloadQuery(msgspec.Struct, forbid_unknown_fields=True):
    server_id: Annotated[str, msgspec.Meta(pattern=r"^[A-Za-z0-9_]{1,64}$")]
    map_id: Annotated[str, msgspec.Meta(pattern=r"^[0-9a-f]{32}$")]


# ------------------------------------------------------------------ update_map


async def get_update_map(call: Call[None, None]) -> Answer:
    """Whether the map in use is being updated live while navigating."""
    slam = call.ctx.slam
    return {"enabled": bool(slam is not None and slam.update_map and slam.mapping())}


async def put_update_map(call: Call[UpdateMapBody, None]) -> Answer:
    """Turn live map updating on (the mapping node extends the map in use from where the
    robot stands, nav keeps navigating on it) or off (the updated map is saved over the map
    in use, then mapping stops and nav reloads it)."""
    ctx = call.ctx
    slam = slam_port(ctx)
    b = call.body
    on = slam.update_map and slam.mapping()
    if b.enabled == on:
        return {"enabled": on}
    current = await ctx.nav_services.current_map()
    if b.enabled:
        if slam.mapping():
            raise ApiError(409, "cannot update the map live: the robot is mapping already "
                                "(GET /map/stop first)")
        if not ctx.core.state.nav_open:
            raise ApiError(409, "live map updating works while navigating: GET "
                                "/navigation/start first")
        s = ctx.core.state
        pose = Pose2D(x=s.pose[0], y=s.pose[1], theta=s.pose[2]) if s.pose else None
        await slam.start("laser", current, pose)
        slam.update_map = True
        return {"enabled": True}
    listed = await ctx.nav_services.call(zm.ListMaps, zm.ListMapsRequest(name=current))
    info = listed.maps[0] if listed.maps else zm.MapInfo()
    await slam.save(current, info.type or "floor", list(info.levels))
    await slam.stop()
    slam.update_map = False
    return {"enabled": False}


# ------------------------------------------------------------------ download


def nav_call(ctx: Context, loop: asyncio.AbstractEventLoop) -> NavCall:
    """Nav's services as a blocking call for `zenros.maps.transfer` run in a worker thread:
    each call runs on the gateway's loop (the port's presence and error mapping kept)."""
    def call(srv: Any, request: Any) -> Any:
        return asyncio.run_coroutine_threadsafe(ctx.nav_services.call(srv, request),
                                                loop).result()
    return call


async def download_map_from_robot(call: Call[None, MapNameQuery]) -> Answer:
    """Export a stored map as a zip archive: its YAML and image, ``map.json`` (size,
    resolution, origin, md5sum) and ``nav.json`` (paths, nav points, point connections)."""
    name = call.query.map_name
    try:
        data = await asyncio.to_thread(export_map, nav_call(call.ctx,
                                                            asyncio.get_running_loop()), name)
    except ArchiveError as exc:
        if exc.status == 404:
            raise NotFound(exc.detail) from exc
        raise ApiError(exc.status, exc.detail) from exc
    return Response(data, media_type="application/zip", headers={
        "content-disposition": f'attachment; filename="{name}.zip"'})


# ------------------------------------------------------------------ upload


async def _form_files(request: Request) -> tuple[str, dict[str, bytes]]:
    """``map_name`` and the uploaded files by name (a zip's unpacked), size-limited."""
    texts, forms = await read_form(request, MAX_ARCHIVE + SLACK,
                                   frozenset({"map_name", "map_files"}),
                                   "`map_name` and `map_files`")
    name = texts.get("map_name")
    if not name:
        raise ApiError(400, "missing the `map_name` form field")
    raw = forms.get("map_files", [])
    if not raw:
        raise ApiError(400, "the form has no `map_files` with a file in it")
    if len(raw) == 1 and (raw[0][0].lower().endswith(".zip") or raw[0][1][:4] == b"PK\x03\x04"):
        return name, await asyncio.to_thread(read_archive, raw[0][1])
    files: dict[str, bytes] = {}
    for filename, content in raw:
        if not filename:
            raise ArchiveError("an uploaded file has no file name")
        files[filename] = content  # check_map refuses a name that leaves the folder
    return name, files


async def _upload(call: Call[None, None]) -> Answer:
    """Import a map: multipart ``map_name`` and ``map_files`` (an archive of
    ``download_map_from_robot``, or the loose YAML and image, with map.json and nav.json
    if any). Everything is checked before the maps store is touched."""
    assert call.request is not None
    name, files = await _form_files(call.request)
    try:
        msgspec.convert(name, Name)
    except msgspec.ValidationError:
        raise ApiError(400, f"invalid map_name {name!r}: use 1-64 letters, digits, '_', "
                            "'.' or '-', not starting with '.' or '-'") from None
    return await asyncio.to_thread(import_map, nav_call(call.ctx, asyncio.get_running_loop()),
                                   name, files, (PortError,))


async def upload_map_to_robot(call: Call[None, None]) -> Answer:
    """Import a map: multipart ``map_name`` and ``map_files`` (an archive of
    ``download_map_from_robot``, or the loose YAML and image, with map.json and nav.json
    if any). Everything is checked before the maps store is touched."""
    try:
        return await _upload(call)
    except ArchiveError as exc:
        raise ApiError(exc.status, exc.detail) from exc


# ------------------------------------------------------------------ schedule server


async def upload_map(call: Call[None, ServerQuery]) -> Answer:
    """Put the current map on schedule server ``server_id``: a task of one
    ``upload_map_action`` (its result names the map's ``map_id`` there); a running task is
    not replaced (409)."""
    action = zm.UploadMapAction(server_id=call.query.server_id)
    return await call.ctx.tasks.run_task("upload_map", [action], replaces=frozenset())


async def download_map(call: Call[None, DownloadQuery]) -> Answer:
    """Get map ``map_id`` from schedule server ``server_id`` into the robot's maps: a task
    of one ``download_map_action``."""
    q = call.query
    action = zm.DownloadMapAction(server_id=q.server_id, map_id=q.map_id)
    return await call.ctx.tasks.run_task("download_map", [action], replaces=frozenset())


def add_map_transfer_routes(api: Api) -> None:
    """Route live map updating and the map archive's export and import."""
    api.add("GET", "/navigation/update_map", get_update_map)
    api.add("PUT", "/navigation/update_map", put_update_map)
    api.add("GET", "/navigation/download_map_from_robot", download_map_from_robot,
            media_type="application/zip")
    api.add("POST", "/navigation/upload_map_to_robot", upload_map_to_robot, raw_body=True)
    api.add("GET", "/navigation/upload_map", upload_map)
    api.add("GET", "/navigation/download_map", download_map)
