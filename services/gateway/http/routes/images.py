"""REST ``/system/saved_images`` (docs/robot-api.md §3.9): snapshots of the robot's cameras as
PNG files in its ``Pictures`` folder, listed, downloaded and deleted."""

from __future__ import annotations

from typing import Annotated

import msgspec

from ...ports.media_folder import MediaError, MediaFolder
from ...ports.snapshots import CAMERA_TOPICS, Snapshots
from ..api import Answer, Api, ApiError, Call
from ..context import Context
from .media_files import add_media_file_routes

__all__ = ["add_image_routes"]


class SnapshotBody(msgspec.Struct, forbid_unknown_fields=True):
    topic: Annotated[str, msgspec.Meta(max_length=256)] = CAMERA_TOPICS[0]
    filename: Annotated[str, msgspec.Meta(max_length=128)] = ""


def _snapshots(ctx: Context) -> Snapshots:
    if ctx.snapshots is None:
        raise ApiError(503, "this gateway saves no pictures (no robot node)")
    return ctx.snapshots


def _pictures(ctx: Context) -> MediaFolder:
    return _snapshots(ctx).files


async def take(call: Call[SnapshotBody, None]) -> Answer:
    """Take a snapshot of a camera (``topic``, default the front camera's) into Pictures."""
    try:
        path = await _snapshots(call.ctx).take(call.body.topic, call.body.filename)
    except MediaError as exc:
        raise ApiError(exc.status, str(exc)) from exc
    return {"image": path.name, "file_timestamp": path.stem}


def add_image_routes(api: Api) -> None:
    """Route the §3.9 picture operations."""
    api.add("POST", "/system/saved_images", take)
    add_media_file_routes(api, "/system/saved_images", _pictures, "image/png")
