"""REST ``/system/saved_videos`` (docs/robot-api.md §3.9): recordings of the robot's cameras as
Matroska files in its ``Videos`` folder, started (recorded in the background), listed,
downloaded and deleted."""

from __future__ import annotations

import asyncio
from typing import Annotated

import msgspec
from starlette.responses import FileResponse

from ...ports.media_folder import MediaError
from ...ports.snapshots import CAMERA_TOPICS
from ...ports.videos import MAX_DURATION, Videos
from ..api import Answer, Api, ApiError, Call

__all__ = ["add_video_routes"]


class RecordBody(msgspec.Struct, forbid_unknown_fields=True):
    topic: Annotated[str, msgspec.Meta(max_length=256)] = CAMERA_TOPICS[0]
    duration: Annotated[int, msgspec.Meta(ge=1, le=MAX_DURATION)] = 10
    filename: Annotated[str, msgspec.Meta(max_length=128)] = ""


def _videos(call: Call[None, None] | Call[RecordBody, None]) -> Videos:
    videos = call.ctx.videos
    if videos is None:
        raise ApiError(503, "this gateway records no videos (no robot node)")
    return videos


async def record(call: Call[RecordBody, None]) -> Answer:
    """Record a camera (``topic``, default the front camera's) for ``duration`` s into Videos;
    answers at once, the recording goes on in the background."""
    b = call.body
    try:
        rec = await asyncio.to_thread(_videos(call).start, b.topic, b.duration, b.filename)
    except MediaError as exc:
        raise ApiError(exc.status, str(exc)) from exc
    return {"video": rec.path.name, "file_timestamp": rec.path.stem,
            "duration": b.duration, "status": "recording"}


async def listing(call: Call[None, None]) -> Answer:
    """The saved videos, newest first; those still recording are not listed yet."""
    return await asyncio.to_thread(_videos(call).files.listing)


async def download(call: Call[None, None]) -> Answer:
    """Download one saved video (Matroska)."""
    try:
        path = _videos(call).files.find(call.path_params.get("file_timestamp", ""))
    except MediaError as exc:
        raise ApiError(exc.status, str(exc)) from exc
    return FileResponse(path, media_type="video/x-matroska", filename=path.name)


async def delete(call: Call[None, None]) -> Answer:
    """Delete one saved video."""
    try:
        path = _videos(call).files.find(call.path_params.get("file_timestamp", ""))
    except MediaError as exc:
        raise ApiError(exc.status, str(exc)) from exc
    await asyncio.to_thread(path.unlink, True)
    return {"status": "ok"}


def add_video_routes(api: Api) -> None:
    """Route the §3.9 video operations."""
    api.add("POST", "/system/saved_videos", record)
    api.add("GET", "/system/saved_videos/", listing)
    api.add("GET", "/system/saved_videos/{file_timestamp}", download)
    api.add("DELETE", "/system/saved_videos/{file_timestamp}", delete)
