"""`coded`: a nav service handler whose refusals carry a `ResultCode`, not just a sentence.

The caller (the gateway, the tasks service) branches on the code its `ServiceError`
carries; the reason text is for people and may be reworded freely.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, TypeVar

from zenros.errors import RefusedError
from zenros.msgs.zenros_msgs.result import ResultCode

__all__ = ["code_of", "coded"]

R = TypeVar("R")


def code_of(exc: Exception) -> ResultCode | None:
    """The result code of a refusal: something named is not stored (`LookupError`, e.g.
    `MapItemNotFoundError`), or the request is not valid (`ValueError`, e.g. `MapError`);
    None for any other exception (a failure, not a refusal)."""
    if isinstance(exc, LookupError):
        return ResultCode.NOT_FOUND
    if isinstance(exc, ValueError):
        return ResultCode.INVALID
    return None


def coded(handler: Callable[[Any], R]) -> Callable[[Any], R]:
    """``handler`` with its refusals raised as `RefusedError` (same kind and reason)."""

    @functools.wraps(handler)
    def run(request: Any) -> R:
        try:
            return handler(request)
        except (LookupError, ValueError) as exc:
            code = code_of(exc)
            assert code is not None
            raise RefusedError(code, str(exc), type(exc).__name__) from exc

    return run
