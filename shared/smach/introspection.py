"""Introspection data: a machine's structure, its status and its events, as plain typed data.

These are the messages a Zenoh introspection server publishes; nothing here does I/O.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, Literal

import msgspec

from ..message import Message, define_service

__all__ = [
    "ContainerEvent",
    "ContainerStatus",
    "EventKind",
    "Listener",
    "SetInitialState",
    "SetInitialStateRequest",
    "SetInitialStateResponse",
    "StateStructure",
    "TransitionInfo",
    "snapshot_userdata",
]

EventKind = Literal["start", "transition", "termination"]


class TransitionInfo(Message, kw_only=True):
    """One edge inside a container: ``source`` ends with ``outcome`` and control goes to ``target``.

    ``target`` is a child label or a container outcome. In a Concurrence the edges are
    the outcome map (child outcome -> container outcome); in an Iterator, the loop and
    break outcomes. ``implicit`` marks an outcome left unmapped that falls through to
    the container outcome of the same name.
    """

    __msgtype__ = "zenros_smach/TransitionInfo"

    source: str
    outcome: str
    target: str
    implicit: bool = False


class StateStructure(Message, kw_only=True):
    """The static shape of a state and, for a container, of everything inside it."""

    __msgtype__ = "zenros_smach/StateStructure"

    path: str
    label: str
    type: str
    outcomes: list[str]
    input_keys: list[str] = msgspec.field(default_factory=list)
    output_keys: list[str] = msgspec.field(default_factory=list)
    remapping: dict[str, str] = msgspec.field(default_factory=dict)
    is_container: bool = False
    initial_states: list[str] = msgspec.field(default_factory=list)
    transitions: list[TransitionInfo] = msgspec.field(default_factory=list)
    info: dict[str, Any] = msgspec.field(default_factory=dict)
    children: list[StateStructure] = msgspec.field(default_factory=list)


class ContainerStatus(Message, kw_only=True):
    """What a container is doing now, with its userdata, and the same for nested containers.

    ``active_paths`` lists the deepest active states (``/PATROL/NAV/GO``).
    ``userdata`` holds the values that convert to plain data; the keys of the others are in
    ``unserializable`` with their type name.
    """

    __msgtype__ = "zenros_smach/ContainerStatus"

    path: str
    type: str
    running: bool
    initial_states: list[str]
    active_states: list[str]
    active_paths: list[str]
    userdata: dict[str, Any] = msgspec.field(default_factory=dict)
    unserializable: dict[str, str] = msgspec.field(default_factory=dict)
    last_outcome: str | None = None
    info: dict[str, Any] = msgspec.field(default_factory=dict)
    children: list[ContainerStatus] = msgspec.field(default_factory=list)


class ContainerEvent(Message, kw_only=True):
    """A container started, moved between children, or terminated.

    ``start``: ``active_states`` are the children about to run. ``transition``: child
    ``label`` ended with ``outcome`` and ``target`` runs next (None in a Concurrence, where
    the child just finished). ``termination``: the container ended with ``outcome``, or
    raised (``error`` holds the message).
    """

    __msgtype__ = "zenros_smach/ContainerEvent"

    kind: EventKind
    path: str
    active_states: list[str]
    label: str | None = None
    outcome: str | None = None
    target: str | None = None
    error: str | None = None


class SetInitialStateRequest(Message, kw_only=True):
    """Where the container at ``path`` starts its next run, and userdata keys to set in it.

    Empty ``initial_states`` keeps the current choice. ``userdata`` holds plain data (what
    JSON or YAML can say).
    """

    __msgtype__ = "zenros_smach/SetInitialStateRequest"

    path: str = "/"
    initial_states: list[str] = msgspec.field(default_factory=list)
    userdata: dict[str, Any] = msgspec.field(default_factory=dict)


class SetInitialStateResponse(Message, kw_only=True):
    """``success`` False says why in ``message``; ``applied`` False: deferred to the next run."""

    __msgtype__ = "zenros_smach/SetInitialStateResponse"

    success: bool = False
    applied: bool = False
    message: str = ""


SetInitialState = define_service(
    "zenros_smach/SetInitialState", SetInitialStateRequest, SetInitialStateResponse
)
"""The introspection server's ``<name>/set_initial_state`` service."""

Listener = Callable[[ContainerEvent], None]
"""A callback on container events; called on the executing thread, so keep it short."""


def _plain(obj: Any) -> Any:
    tolist = getattr(obj, "tolist", None)  # numpy arrays and scalars
    if callable(tolist):
        return tolist()
    raise NotImplementedError(f"cannot convert {type(obj).__name__}")


def snapshot_userdata(data: Mapping[str, Any]) -> tuple[dict[str, Any], dict[str, str]]:
    """Split userdata into plain-data values and the type names of the rest.

    Returns:
        ``(plain, unserializable)``: key -> builtins (dicts, lists, numbers, strings), and
        key -> type name for values msgspec cannot convert.
    """
    plain: dict[str, Any] = {}
    skipped: dict[str, str] = {}
    for key, value in data.items():
        try:
            plain[key] = msgspec.to_builtins(value, enc_hook=_plain)
        except (TypeError, ValueError, NotImplementedError):
            skipped[key] = type(value).__qualname__
    return plain, skipped
