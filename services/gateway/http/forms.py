"""Reading a multipart/form-data request body within a size limit: its text fields and its
files, by field name; an unknown field, a malformed body or one past the limit is refused."""

from __future__ import annotations

from starlette.datastructures import UploadFile
from starlette.formparsers import MultiPartException
from starlette.requests import Request
from starlette.types import Message, Receive

from .api import ApiError

__all__ = ["SLACK", "Form", "limited", "read_form"]

SLACK = 64 * 1024  # an upload's multipart boundaries and the small fields around the file


def limited(receive: Receive, limit: int) -> Receive:
    """``receive`` refusing (413) a body past ``limit`` bytes."""
    seen = 0

    async def wrapped() -> Message:
        nonlocal seen
        message = await receive()
        seen += len(message.get("body", b""))
        if seen > limit:
            raise ApiError(413, f"upload too large: over {limit} bytes")
        return message
    return wrapped

Form = tuple[dict[str, str], dict[str, list[tuple[str, bytes]]]]
"""(text fields, files by field: [(file name, content)])."""


async def read_form(request: Request, limit: int, fields: frozenset[str],
                    what: str) -> Form:
    """The form's text fields and files, ``limit`` bytes at most; ``what`` says what to
    upload when the body is not a form."""
    declared = request.headers.get("content-length", "")
    if declared.isdigit() and int(declared) > limit:
        raise ApiError(413, f"upload too large: {declared} bytes (limit {limit})")
    if not request.headers.get("content-type", "").startswith("multipart/form-data"):
        raise ApiError(400, f"upload a multipart/form-data body with {what}")
    body = Request(request.scope, limited(request.receive, limit))
    texts: dict[str, str] = {}
    files: dict[str, list[tuple[str, bytes]]] = {}
    try:
        async with body.form(max_files=8, max_fields=len(fields) + 2) as form:
            unknown = sorted(set(form.keys()) - fields)
            if unknown:
                raise ApiError(400, f"unknown form field(s): {', '.join(unknown)}")
            for key, value in form.multi_items():
                if isinstance(value, UploadFile):
                    files.setdefault(key, []).append((value.filename or "", await value.read()))
                else:
                    texts[key] = value
    except MultiPartException as exc:
        raise ApiError(400, f"malformed multipart body: {exc.message}") from exc
    return texts, files
