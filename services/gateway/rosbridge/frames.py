"""Reading rosbridge request frames: names, ids and numbers, with the reference's errors."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TypeVar

from zenros.errors import UnknownTypeError
from zenros.names import validate_name

__all__ = ["OpError", "SubOptions", "frame_int", "frame_name", "frame_text", "frame_type",
           "legacy_id"]

T = TypeVar("T")


class OpError(ValueError):
    """An op that cannot be carried out; reported with the request's id."""


@dataclass
class SubOptions:
    """One subscription id's options; several ids on one topic are merged."""

    throttle_rate: float = 0
    queue_length: int = 0
    fragment_size: int = 0
    compression: str = "none"


def frame_name(frame: dict[str, Any], key: str) -> str:
    """``frame[key]`` as an absolute, valid name (``rosapi/topics`` → ``/rosapi/topics``;
    a legacy ``#id`` suffix dropped)."""
    value = frame_text(frame, key)
    name = value if value.startswith("/") else "/" + value
    name = name.split("#", 1)[0]  # the legacy form carries the call id after '#'
    try:
        validate_name(name, key)
    except ValueError as exc:
        raise OpError(str(exc)) from None
    return name


def frame_text(frame: dict[str, Any], key: str) -> str:
    """``frame[key]`` as a non-empty string."""
    value = frame.get(key)
    if not isinstance(value, str) or not value:
        raise OpError(f"Expected a key '{key}' with a non-empty string in message")
    return value


def frame_type(frame: dict[str, Any], key: str, lookup: Callable[[str], T]) -> T:
    """The registered type named by ``frame[key]`` (``lookup_service``, ``lookup_action``)."""
    try:
        return lookup(frame_text(frame, key))
    except UnknownTypeError as exc:
        raise OpError(str(exc)) from None


def legacy_id(frame: dict[str, Any], key: str) -> Any:
    """The interaction id: the ``id`` field, else what follows ``#`` in the name."""
    if "id" in frame:
        return frame["id"]
    value = frame.get(key)
    if isinstance(value, str) and "#" in value:
        return value.split("#", 1)[1]
    return None


def frame_int(frame: dict[str, Any], key: str, default: int = 0) -> int:
    """``frame[key]`` as an int (``default`` when absent or null)."""
    value = frame.get(key, default)
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise OpError(f"Expected '{key}' to be a number, got {type(value).__name__}")
    return int(value)


