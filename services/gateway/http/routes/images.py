"""REST ``/system/saved_images`` (docs/robot-api.md §3.9): snapshots of the robot's cameras as
PNG files in its ``Pictures`` folder, listed, downloaded and deleted."""

from __future__ import annotations

import asyncio
from typing import Annotated

import msgspec
from starlette.responses import FileResponse

from ...ports.media_folder import MediaError
from ...ports.snapshots import CAMERA_TOPICS, Snapshots
from ..api import Answer, Api, ApiError, Call

__all__ = ["add_image_routes"]


class SnapshotBody(msgspec.Struct, forbid_unknown_fields=True):
    topic: Annotated[str, msgspec.Meta(max_length=256)] = CAMERA_TOPICS[0]
    filename: Annotated[str, msgspec.Meta(max_length=128)] = ""


def _shots(call: Call[None, None] | Call[SnapshotBody, None]) -> Snapshots:
    shots = call.ctx.snapshots
    if shots is None:
        raise ApiError(503, "this gateway saves no pictures (no robot node)")
    return shots


async def take(call: Call[SnapshotBody, None]) -> Answer:
    """Take a snapshot of a camera (``topic``, default the front camera's) into Pictures."""
    try:
        path = await _shots(call).take(call.body.topic, call.body.filename)
    except MediaError as exc:
        raise ApiError(exc.status, str(exc)) from exc
    return {"image": path.name, "file_timestamp": path.stem}


async def listing(call: Call[None, None]) -> Answer:
    """The saved pictures, newest first."""
    return await asyncio.to_thread(_shots(call).files.listing)


async def download(call: Call[None, None]) -> Answer:
    """Download one saved picture (PNG)."""
    try:
        path = _shots(call).files.find(call.path_params.get("file_timestamp", ""))
    except MediaError as exc:
        raise ApiError(exc.status, str(exc)) from exc
    return FileResponse(path, media_type="image/png", filename=path.name)


async def delete(call: Call[None, None]) -> Answer:
    """Delete one saved picture."""
    try:
        path = _shots(call).files.find(call.path_params.get("file_timestamp", ""))
    except MediaError as exc:
        raise ApiError(exc.status, str(exc)) from exc
    await asyncio.to_thread(path.unlink, True)
    return {"status": "ok"}


def add_image_routes(api: Api) -> None:
    """Route the §3.9 picture operations."""
    api.add("POST", "/system/saved_images", take)
    api.add("GET", "/system/saved_images/", listing)
    api.add("GET", "/system/saved_images/{file_timestamp}", download)
    api.add("DELETE", "/system/saved_images/{file_timestamp}", delete)
