"""Checking an action document's parameters against its type (zenros_msgs.task_actions).

The action types themselves live in the message package, shared with the gateway; here a
request with an unknown type, a missing or mistyped field, or a field the type does not
have is refused with the field's name.
"""

from __future__ import annotations

from typing import Any

import msgspec
from zenros.msgs.zenros_msgs.task_actions import (
    ACTION_TYPES,
    COMMON_FIELDS,
    Action,
    check_action,
)

__all__ = ["ACTION_TYPES", "COMMON_FIELDS", "ActionParamsError", "action_of", "parse_action",
           "validate_params"]


class ActionParamsError(ValueError):
    """An action document that is not valid for its type; the text names the field."""


def parse_action(doc: dict[str, Any], where: str = "action") -> Action:
    """One action document (plain data) as its typed `Action`, checked; the common fields
    (id, state, result, progress, ...) it may carry are not read.

    Raises:
        ActionParamsError: unknown ``type``, or a parameter missing, mistyped or unknown.
    """
    kind = doc.get("type")
    if not isinstance(kind, str) or not kind:
        raise ActionParamsError(f"{where}: missing field 'type'; action types: "
                                + ", ".join(ACTION_TYPES))
    if kind not in ACTION_TYPES:
        raise ActionParamsError(f"{where}: unknown action type {kind!r}; action types: "
                                + ", ".join(ACTION_TYPES))
    params = {k: v for k, v in doc.items() if k not in COMMON_FIELDS}
    try:
        value: Action = msgspec.convert({"type": kind, **params}, Action)
    except msgspec.ValidationError as exc:
        raise ActionParamsError(f"{where} ({kind}): {exc}") from exc
    try:
        check_action(value)
    except ValueError as exc:
        raise ActionParamsError(f"{where} {exc}") from exc
    return value


def validate_params(doc: dict[str, Any], where: str = "action") -> dict[str, Any]:
    """Check one action document's parameters; return them normalised (defaults filled).

    Raises:
        ActionParamsError: as `parse_action`.
    """
    out: dict[str, Any] = msgspec.to_builtins(parse_action(doc, where))
    return {k: v for k, v in out.items() if k not in COMMON_FIELDS and v is not None}


def action_of(kind: str, params: dict[str, Any]) -> Action:
    """The typed action of type ``kind`` with ``params`` (an action document's parameters,
    as `validate_params` returned them: already valid)."""
    action: Action = msgspec.convert({"type": kind, **params}, Action)
    return action
