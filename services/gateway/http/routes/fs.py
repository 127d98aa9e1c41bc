"""REST ``/fs/...`` (docs/robot-api.md §16): the robot's files, confined to the `FileRoot`
sandbox."""

from __future__ import annotations

import asyncio
from collections.abc import Callable
from typing import Annotated, TypeVar

import msgspec
from starlette.datastructures import UploadFile
from starlette.formparsers import MultiPartException
from starlette.requests import Request
from starlette.responses import FileResponse

from ...ports.fs_sandbox import FsError
from ..api import Answer, Api, ApiError, Call
from ..forms import SLACK, limited

__all__ = ["add_fs_routes"]

T = TypeVar("T")

PathText = Annotated[str, msgspec.Meta(min_length=1, max_length=4096)]


class PathQuery(msgspec.Struct, forbid_unknown_fields=True):
    path: PathText


class OptionalPath(msgspec.Struct, forbid_unknown_fields=True):
    path: PathText | None = None


class PathBody(msgspec.Struct, forbid_unknown_fields=True):
    path: PathText


class RenameBody(msgspec.Struct, forbid_unknown_fields=True):
    """``name``: the current path, ``new_name``: the new one (or a folder to move into)."""

    name: PathText
    new_name: PathText


class FromTo(msgspec.Struct, forbid_unknown_fields=True):
    """``from``: the source path, ``to``: the new path (or a folder to put it into)."""

    from_: PathText = msgspec.field(name="from")
    to: PathText


class DeleteBody(msgspec.Struct, forbid_unknown_fields=True):
    delete: Annotated[list[PathText], msgspec.Meta(min_length=1, max_length=1000)]


async def _fs(fn: Callable[[], T]) -> T:
    try:
        return await asyncio.to_thread(fn)
    except FsError as exc:
        raise ApiError(exc.status, str(exc)) from exc
    except OSError as exc:
        raise ApiError(409, f"the file system refused: {exc.strerror or exc}") from exc




async def download(call: Call[None, PathQuery]) -> Answer:
    """Download a file (its bytes, with a guessed content type)."""
    root = call.ctx.files
    full = await _fs(lambda: root.file(call.query.path))
    return FileResponse(full, filename=full.name)


async def upload(call: Call[None, OptionalPath]) -> Answer:
    """Upload a multipart form field ``file`` to ``path`` (form field or query).

    ``path`` names the file, or a folder (existing, or ending in ``/``) to put it in
    under its own name; an existing file is replaced. Token in the query string.
    """
    root = call.ctx.files
    assert call.request is not None
    declared = call.request.headers.get("content-length", "")
    if declared.isdigit() and int(declared) > root.max_upload + SLACK:
        raise ApiError(413, f"upload too large: {declared} bytes "
                            f"(limit {root.max_upload})")
    ctype = call.request.headers.get("content-type", "")
    if not ctype.startswith("multipart/form-data"):
        raise ApiError(400, "upload a multipart/form-data body with a `file` field")
    request = Request(call.request.scope,
                      limited(call.request.receive, root.max_upload + SLACK))
    try:
        async with request.form(max_files=1, max_fields=8) as form:
            upload_file = form.get("file")
            path = form.get("path", call.query.path)
            unknown = sorted(set(form.keys()) - {"file", "path"})
            if unknown:
                raise ApiError(400, f"unknown form field(s): {', '.join(unknown)}")
            if not isinstance(upload_file, UploadFile):
                raise ApiError(400, "the form has no `file` field with a file in it")
            if not isinstance(path, str) or not path:
                raise ApiError(400, "missing `path` (form field or query parameter)")
            where: str = path
            data = upload_file.file
            full = await _fs(lambda: root.upload_target(where, upload_file.filename or ""))
            size = await _fs(lambda: root.write(full, data))
    except MultiPartException as exc:  # the parser's refusals (malformed, too many parts)
        raise ApiError(400, f"malformed multipart body: {exc.message}") from exc
    return {"status": "ok", "path": root.relative(full), "size": size}


async def rename(call: Call[RenameBody, None]) -> Answer:
    """Rename or move ``name`` to ``new_name``."""
    root = call.ctx.files
    b = call.body
    new = await _fs(lambda: root.move(b.name, b.new_name))
    return {"status": "ok", "path": new}


async def delete_file(call: Call[None, PathQuery]) -> Answer:
    """Delete a file (or a symbolic link)."""
    root = call.ctx.files
    await _fs(lambda: root.remove_file(call.query.path))
    return {"status": "ok"}


async def list_dir(call: Call[None, PathQuery]) -> Answer:
    """List a folder: ``files`` and ``directories`` (names, sorted)."""
    root = call.ctx.files
    return await _fs(lambda: root.list_dir(call.query.path))


async def make_dir(call: Call[PathBody, None]) -> Answer:
    """Create a folder (with missing parents)."""
    root = call.ctx.files
    await _fs(lambda: root.make_dir(call.body.path))
    return {"status": "ok"}


async def delete_dir(call: Call[None, PathQuery]) -> Answer:
    """Delete a folder and everything in it."""
    root = call.ctx.files
    await _fs(lambda: root.remove_dir(call.query.path))
    return {"status": "ok"}


async def file_info(call: Call[None, PathQuery]) -> Answer:
    """Stat a path: ``mode``, ``size``, ``atime``, ``mtime``, ``ctime``, ``mimetype``."""
    root = call.ctx.files
    return await _fs(lambda: root.info(call.query.path))


async def copy(call: Call[FromTo, None]) -> Answer:
    """Copy a file or folder ``from`` to ``to``."""
    root = call.ctx.files
    b = call.body
    new = await _fs(lambda: root.copy(b.from_, b.to))
    return {"status": "ok", "path": new}


async def cut(call: Call[FromTo, None]) -> Answer:
    """Move a file or folder ``from`` to ``to``."""
    root = call.ctx.files
    b = call.body
    new = await _fs(lambda: root.move(b.from_, b.to))
    return {"status": "ok", "path": new}


async def delete_many(call: Call[DeleteBody, None]) -> Answer:
    """Delete the files and folders listed in ``delete`` (all checked first)."""
    root = call.ctx.files
    await _fs(lambda: root.remove_many(call.body.delete))
    return {"status": "ok"}


def add_fs_routes(api: Api) -> None:
    """Route the §16 file operations on ``root``."""
    api.add("GET", "/fs/file_api", download,
            media_type="application/octet-stream")
    api.add("POST", "/fs/file_api", upload, raw_body=True)
    api.add("PUT", "/fs/file_api", rename)
    api.add("DELETE", "/fs/file_api", delete_file)
    api.add("GET", "/fs/dir_api", list_dir)
    api.add("POST", "/fs/dir_api", make_dir)
    api.add("DELETE", "/fs/dir_api", delete_dir)
    api.add("GET", "/fs/get_file_info", file_info)
    api.add("POST", "/fs/copy", copy)
    api.add("POST", "/fs/delete", delete_many)
    api.add("POST", "/fs/cut", cut)
