"""REST ``/system/saved_videos`` (docs/robot-api.md §3.9): recordings of the robot's cameras as
Matroska files in its ``Videos`` folder, started (recorded in the background), listed,
downloaded and deleted."""

from __future__ import annotations

import asyncio
from typing import Annotated

import msgspec

from ...ports.media_folder import MediaError, MediaFolder
from ...ports.snapshots import CAMERA_TOPICS
from ...ports.videos import MAX_DURATION, Videos
from ..api import Answer, Api, ApiError, Call
from ..context import Context
from .media_files import add_media_file_routes

__all__ = ["add_video_routes"]


class RecordBody(msgspec.Struct, forbid_unknown_fields=True):
    topic: Annotated[str, msgspec.Meta(max_length=256)] = CAMERA_TOPICS[0]
    duration: Annotated[int, msgspec.Meta(ge=1, le=MAX_DURATION)] = 10
    filename: Annotated[str, msgspec.Meta(max_length=128)] = ""


def _videos(ctx: Context) -> Videos:
    if ctx.videos is None:
        raise ApiError(503, "this gateway records no videos (no robot node)")
    return ctx.videos


def _recordings(ctx: Context) -> MediaFolder:
    return _videos(ctx).files


async def record(call: Call[RecordBody, None]) -> Answer:
    """Record a camera (``topic``, default the front camera's) for ``duration`` s into Videos;
    answers at once, the recording goes on in the background."""
    b = call.body
    try:
        rec = await asyncio.to_thread(_videos(call.ctx).start, b.topic, b.duration, b.filename)
    except MediaError as exc:
        raise ApiError(exc.status, str(exc)) from exc
    return {"video": rec.path.name, "file_timestamp": rec.path.stem,
            "duration": b.duration, "status": "recording"}


def add_video_routes(api: Api) -> None:
    """Route the §3.9 video operations."""
    api.add("POST", "/system/saved_videos", record)
    add_media_file_routes(api, "/system/saved_videos", _recordings, "video/x-matroska")
