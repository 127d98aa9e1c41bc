"""REST ``/system/tts/records`` (docs/robot-api.md §3.7): voice packages, recorded phrases the
robot plays instead of synthesising their text (`state.voices.VoiceStore`).

``POST`` is three operations on one URL, told apart by the body: JSON ``{"package_name"}``
selects the active package; a form with ``package_name`` and ``package_file`` (a zip of
``records.json`` and its recordings) uploads a package; a form with ``package_name``,
``text`` and ``audio_file`` (a WAV or MP3) adds one phrase.
"""

from __future__ import annotations

import asyncio
from typing import Annotated, Any

import msgspec

from ...state.voices import MAX_FILE, VoiceError, VoiceStore, valid_package_name
from ..api import Answer, Api, ApiError, Call
from ..forms import read_form

__all__ = ["add_voice_routes"]

MAX_UPLOAD = 64 * 1024 * 1024  # a package archive's request
FIELDS = frozenset({"package_name", "package_file", "text", "audio_file"})


class RecordsQuery(msgspec.Struct, forbid_unknown_fields=True):
    package_name: Annotated[str, msgspec.Meta(max_length=64)] = ""


class DeleteQuery(msgspec.Struct, forbid_unknown_fields=True):
    package_name: Annotated[str, msgspec.Meta(max_length=64)] = ""
    text: Annotated[str, msgspec.Meta(max_length=2000)] = ""


class SelectBody(msgspec.Struct, forbid_unknown_fields=True):
    package_name: Annotated[str, msgspec.Meta(min_length=1, max_length=64)]


def _voices(call: Call[Any, Any]) -> VoiceStore:
    if call.ctx.voices is None:
        raise ApiError(501, "this gateway keeps no voice packages (no robot node)")
    return call.ctx.voices


async def _run(fn: Any, *args: Any) -> Any:
    try:
        return await asyncio.to_thread(fn, *args)
    except VoiceError as exc:
        raise ApiError(exc.status, str(exc)) from exc


async def get_records(call: Call[None, RecordsQuery]) -> Answer:
    """The packages, the records of ``package_name`` (default: the active package) and the
    active package's name."""
    store = _voices(call)
    name = call.query.package_name
    if name:
        await _run(valid_package_name, name)
    records = await _run(store.records, name)
    return {"packages": store.packages(), "records": msgspec.to_builtins(records),
            "current_package": store.current}


async def post_records(call: Call[None, None]) -> Answer:
    """Select the active package (JSON), upload a package or add a phrase (forms)."""
    store = _voices(call)
    request = call.request
    assert request is not None
    if request.headers.get("content-type", "").startswith("application/json"):
        body = await request.body()
        if len(body) > 4096:
            raise ApiError(413, "a JSON body here is at most 4096 bytes")
        try:
            select = msgspec.json.decode(body, type=SelectBody)
        except msgspec.MsgspecError as exc:
            raise ApiError(400, f"invalid body: {exc}") from exc
        await _run(store.select, select.package_name)
        return {"status": "ok"}
    texts, files = await read_form(request, MAX_UPLOAD, FIELDS,
                                   "package_name and package_file (or text and audio_file)")
    name = texts.get("package_name", "")
    if not name:
        raise ApiError(400, "missing the `package_name` form field")
    if "package_file" in files:
        [(_, archive)] = files["package_file"][:1]
        count = await _run(store.upload_package, name, archive)
        return {"status": "ok", "records": count}
    if "audio_file" in files and texts.get("text"):
        [(filename, data)] = files["audio_file"][:1]
        if len(data) > MAX_FILE:
            raise ApiError(413, f"audio_file: over {MAX_FILE} bytes")
        rec = await _run(store.add_phrase, name, texts["text"], filename, data)
        return {"status": "ok", "md5sum": rec.md5sum}
    raise ApiError(400, "give `package_file` (a package), or `text` and `audio_file` (a "
                        "phrase)")


async def delete_records(call: Call[None, DeleteQuery]) -> Answer:
    """Delete phrase ``text`` (of ``package_name``, default the active package), or the
    package ``package_name`` when no text is given."""
    store = _voices(call)
    q = call.query
    if q.text:
        await _run(store.delete_phrase, q.text, q.package_name)
    elif q.package_name:
        await _run(store.delete_package, q.package_name)
    else:
        raise ApiError(400, "give `package_name` (a package) or `text` (a phrase)")
    return {"status": "ok"}


def add_voice_routes(api: Api) -> None:
    """Route the voice packages."""
    api.add("GET", "/system/tts/records", get_records)
    api.add("POST", "/system/tts/records", post_records, raw_body=True)
    api.add("DELETE", "/system/tts/records", delete_records)
