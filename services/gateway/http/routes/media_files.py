"""The saved files of a media folder (``/system/saved_images/``, ``/system/saved_videos/``;
docs/robot-api.md §3.9) as REST: listed newest first, one downloaded, one deleted.

The handlers are shared: each finds its folder by the path it serves (`FOLDERS`, filled once
by `add_media_file_routes` for each kind)."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from pathlib import Path

from starlette.responses import FileResponse

from ...ports.media_folder import MediaError, MediaFolder
from ..api import Answer, Api, ApiError, Call
from ..context import Context

__all__ = ["FOLDERS", "add_media_file_routes"]

FOLDERS: dict[str, tuple[Callable[[Context], MediaFolder], str]] = {}
"""A media base path (``/system/saved_images``) -> (its folder of a context, media type)."""


def _folder(call: Call[None, None]) -> tuple[MediaFolder, str]:
    for base, (files_of, media_type) in FOLDERS.items():
        if f"{base}/" in call.path:
            return files_of(call.ctx), media_type
    raise ApiError(404, f"no media folder serves {call.path}")


def _file(call: Call[None, None]) -> tuple[Path, str]:
    folder, media_type = _folder(call)
    try:
        path = folder.find(call.path_params.get("file_timestamp", ""))
    except MediaError as exc:
        raise ApiError(exc.status, str(exc)) from exc
    return path, media_type


async def listing(call: Call[None, None]) -> Answer:
    """The saved files, newest first: ``file_timestamp``, ``filename``, ``size``, ``time``."""
    folder, _ = _folder(call)
    return await asyncio.to_thread(folder.listing)


async def download(call: Call[None, None]) -> Answer:
    """Download one saved file."""
    path, media_type = _file(call)
    return FileResponse(path, media_type=media_type, filename=path.name)


async def delete(call: Call[None, None]) -> Answer:
    """Delete one saved file."""
    path, _ = _file(call)
    await asyncio.to_thread(Path(path).unlink, True)
    return {"status": "ok"}


def add_media_file_routes(api: Api, base: str, files_of: Callable[[Context], MediaFolder],
                          media_type: str) -> None:
    """Route ``GET base/``, ``GET base/{file_timestamp}`` and its ``DELETE`` over the folder
    ``files_of(ctx)`` (which raises `ApiError` when the gateway has none)."""
    FOLDERS[base] = (files_of, media_type)
    api.add("GET", f"{base}/", listing)
    api.add("GET", f"{base}/{{file_timestamp}}", download)
    api.add("DELETE", f"{base}/{{file_timestamp}}", delete)
