"""rosbridge request frames, typed: one msgspec Struct per op, tagged by ``op``, so a frame
decodes into its op's type in one step (`frame_decoder`); and reading their names, ids and
numbers with the reference's errors."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from typing import Any, TypeVar, Union

import msgspec
from zenros.errors import UnknownTypeError
from zenros.names import validate_name

__all__ = ["ActionFeedback", "ActionResult", "Advertise", "AdvertiseAction",
           "AdvertiseService", "Auth", "CallService", "CancelActionGoal", "Fragment", "Frame",
           "Number", "OpError", "Publish", "SendActionGoal", "ServiceResponse", "SetLevel",
           "SubOptions", "Subscribe", "Unadvertise", "UnadvertiseAction", "UnadvertiseService",
           "Unsubscribe", "frame_decoder", "frame_int", "frame_name", "frame_text",
           "frame_type", "legacy_id", "op_of"]

T = TypeVar("T")

Number = int | float | None
"""A numeric field as clients send it (null: the default)."""


class Frame(msgspec.Struct, tag_field="op"):
    """A request frame: its type is its ``op`` (the tag); ``id`` names the interaction (any
    JSON value, echoed back). Fields a client leaves out take their defaults, fields the op
    does not use are ignored; a name left empty is refused by the op, with the reference's
    words (`frame_text`)."""

    id: Any = None


class Advertise(Frame, tag="advertise"):
    topic: str = ""
    type: str = ""
    latch: bool = False
    queue_size: Number = 100


class Unadvertise(Frame, tag="unadvertise"):
    topic: str = ""


class Publish(Frame, tag="publish"):
    topic: str = ""
    msg: Any = None  # the message as JSON, checked against the topic's type by the op
    latch: bool = False


class Subscribe(Frame, tag="subscribe"):
    topic: str = ""
    type: str | None = None
    compression: str | None = None
    throttle_rate: Number = 0
    queue_length: Number = 0
    fragment_size: Number = 0


class Unsubscribe(Frame, tag="unsubscribe"):
    topic: str = ""


class CallService(Frame, tag="call_service"):
    service: str = ""
    args: Any = None  # the request's fields by name (or in order), checked by the op
    fragment_size: Number = 0
    timeout: Number = None


class ServiceResponse(Frame, tag="service_response"):
    service: str = ""
    values: Any = None  # the response's fields, or a failure's reason
    result: bool = True


class AdvertiseService(Frame, tag="advertise_service"):
    service: str = ""
    type: str = ""


class UnadvertiseService(Frame, tag="unadvertise_service"):
    service: str = ""


class SendActionGoal(Frame, tag="send_action_goal"):
    action: str = ""
    action_type: str = ""
    args: Any = None  # the goal's fields, checked by the op
    feedback: bool = False
    fragment_size: Number = 0


class CancelActionGoal(Frame, tag="cancel_action_goal"):
    action: str = ""


class AdvertiseAction(Frame, tag="advertise_action"):
    action: str = ""
    type: str = ""


class UnadvertiseAction(Frame, tag="unadvertise_action"):
    action: str = ""


class ActionFeedback(Frame, tag="action_feedback"):
    action: str = ""
    values: Any = None  # the feedback's fields, checked by the served action


class ActionResult(Frame, tag="action_result"):
    action: str = ""
    values: Any = None  # the result's fields, checked by the served action
    status: Number = None
    result: bool = True


class SetLevel(Frame, tag="set_level"):
    level: str = ""


class Fragment(Frame, tag="fragment"):
    data: Any = None  # checked by fragments.Defragmenter, with its own errors
    num: Any = None
    total: Any = None


class Auth(Frame, tag="auth"):
    """rosauth's op: accepted and ignored (its fields with it)."""


def op_of(frame_type: type[Frame]) -> str:
    """The op code a frame type is tagged with."""
    return str(frame_type.__struct_config__.tag)


@cache
def frame_decoder(types: tuple[type[Frame], ...]) -> msgspec.json.Decoder[Any]:
    """A JSON decoder of any of ``types`` (the ops a session answers), by their ``op``."""
    return msgspec.json.Decoder(Union[types])  # noqa: UP007 (a tuple of types, built here)


class OpError(ValueError):
    """An op that cannot be carried out; reported with the request's id."""


@dataclass
class SubOptions:
    """One subscription id's options; several ids on one topic are merged."""

    throttle_rate: float = 0
    queue_length: int = 0
    fragment_size: int = 0
    compression: str = "none"


def frame_name(frame: Frame, key: str) -> str:
    """``frame.<key>`` as an absolute, valid name (``rosapi/topics`` → ``/rosapi/topics``;
    a legacy ``#id`` suffix dropped)."""
    value = frame_text(frame, key)
    name = value if value.startswith("/") else "/" + value
    name = name.split("#", 1)[0]  # the legacy form carries the call id after '#'
    try:
        validate_name(name, key)
    except ValueError as exc:
        raise OpError(str(exc)) from None
    return name


def frame_text(frame: Frame, key: str) -> str:
    """``frame.<key>`` as a non-empty string."""
    value = getattr(frame, key, None)
    if not isinstance(value, str) or not value:
        raise OpError(f"Expected a key '{key}' with a non-empty string in message")
    return value


def frame_type(frame: Frame, key: str, lookup: Callable[[str], T]) -> T:
    """The registered type named by ``frame.<key>`` (``lookup_service``, ``lookup_action``)."""
    try:
        return lookup(frame_text(frame, key))
    except UnknownTypeError as exc:
        raise OpError(str(exc)) from None


def legacy_id(frame: Frame, key: str) -> Any:
    """The interaction id: the ``id`` field, else what follows ``#`` in the name."""
    if frame.id is not None:
        return frame.id
    value = getattr(frame, key, None)
    if isinstance(value, str) and "#" in value:
        return value.split("#", 1)[1]
    return None


def frame_int(frame: Frame, key: str, default: int = 0) -> int:
    """``frame.<key>`` as an int (``default`` when absent or null)."""
    value = getattr(frame, key, default)
    if value is None:
        return default
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise OpError(f"Expected '{key}' to be a number, got {type(value).__name__}")
    return int(value)


