"""The action types a task can hold (specs/robot-api.md §9.2) and their parameter schemas.

Each type's parameters are a msgspec Struct: a request with an unknown type, a missing or
mistyped field, or a field the type does not have is refused with the field's name.
"""

from __future__ import annotations

import math
from typing import Annotated, Any, Final, Literal

import msgspec
from msgspec import Meta

__all__ = ["ACTION_TYPES", "COMMON_FIELDS", "ActionParamsError", "validate_params"]

Seconds = Annotated[float, Meta(ge=0)]
Level = Annotated[float, Meta(ge=0, le=1)]


class _Params(msgspec.Struct, forbid_unknown_fields=True, kw_only=True):
    pass


class NavAction(_Params):
    """Navigate to (x, y, theta) in ``map``, or to nav point ``index`` of the current map."""

    x: float | None = None
    y: float | None = None
    theta: float = 0.0
    index: Annotated[int, Meta(ge=0)] | None = None
    map: str = ""
    path: str = ""
    timeout: Seconds = 0.0  # 0: no limit


class SleepAction(_Params):
    wait_time: Seconds


class ChargeAction(_Params):
    """Dock at the charger; complete when charging starts, or when ``level`` is reached."""

    x: float | None = None
    y: float | None = None
    theta: float = 0.0
    level: Level = 0.0  # 0: complete as soon as charging starts (§9.2 impl. note)
    timeout: Seconds = 0.0


class CallbackAction(_Params):
    url: str
    method: str = "GET"
    data: Any = None
    timeout: Annotated[float, Meta(gt=0)] = 10.0


class WaitReqAction(_Params):
    timeout: Seconds = 0.0  # 0: wait until released


class TtsAction(_Params):
    text: str


class SwitchMapAction(_Params):
    map: str
    path: str = ""
    start_index: Annotated[int, Meta(ge=-1)] = -1


class LocalMoveAction(_Params):
    """Move ``distance`` m (+ forward) and turn ``angle`` rad (+ CCW) without the planner.

    ``method`` (illegible in the spec; our reading): 0 moves then turns, 1 turns then moves.
    """

    distance: Annotated[float, Meta(ge=-20, le=20)] = 0.0
    angle: Annotated[float, Meta(ge=-20, le=20)] = 0.0
    method: Literal[0, 1] = 0
    speed: Annotated[float, Meta(gt=0, le=2)] = 0.3
    timeout: Seconds = 0.0  # 0: no limit


class LocalMoveTargetAction(_Params):
    """A precise short move to (x, y, theta) in ``map`` or relative to ``base_link``."""

    x: Annotated[float, Meta(ge=-1e5, le=1e5)]
    y: Annotated[float, Meta(ge=-1e5, le=1e5)]
    theta: float = 0.0
    frame_id: Literal["map", "base_link"] = "map"
    xy_tolerance: Annotated[float, Meta(gt=0, le=10)] = 0.05
    yaw_tolerance: Annotated[float, Meta(gt=0, le=3.15)] = 0.05
    timeout: Seconds = 0.0  # 0: no limit
    start_rotate_enable: bool = True
    target_rotate_enable: bool = True


class IoAction(_Params):
    """Set main-board output ``port`` ("1".."3") to ``level`` ("0" low, "1" high)."""

    level: Literal["0", "1"]
    port: Literal["1", "2", "3"]


ACTION_TYPES: Final[dict[str, type[_Params]]] = {
    "nav_action": NavAction,
    "sleep_action": SleepAction,
    "charge_action": ChargeAction,
    "callback_action": CallbackAction,
    "wait_req_action": WaitReqAction,
    "tts_action": TtsAction,
    "switch_map_action": SwitchMapAction,
    "local_move_action": LocalMoveAction,
    "local_move_target_action": LocalMoveTargetAction,
    "io_action": IoAction,
}

# fields every action document carries besides its parameters
COMMON_FIELDS: Final = frozenset({"id", "type", "state", "result", "progress",
                                  "current_location", "current_distance"})

_METHODS: Final = frozenset({"GET", "POST", "PUT", "DELETE", "PATCH", "HEAD"})


class ActionParamsError(ValueError):
    """An action document that is not valid for its type; the text names the field."""


def validate_params(doc: dict[str, Any], where: str = "action") -> dict[str, Any]:
    """Check one action document's parameters; return them normalised (defaults filled).

    Raises:
        ActionParamsError: unknown ``type``, or a parameter missing, mistyped or unknown.
    """
    kind = doc.get("type")
    if not isinstance(kind, str) or not kind:
        raise ActionParamsError(f"{where}: missing field 'type'; action types: "
                                + ", ".join(ACTION_TYPES))
    spec = ACTION_TYPES.get(kind)
    if spec is None:
        raise ActionParamsError(f"{where}: unknown action type {kind!r}; action types: "
                                + ", ".join(ACTION_TYPES))
    params = {k: v for k, v in doc.items() if k not in COMMON_FIELDS}
    try:
        value = msgspec.convert(params, spec)
    except msgspec.ValidationError as exc:
        raise ActionParamsError(f"{where} ({kind}): {exc}") from exc
    _check_semantics(kind, value, where)
    out: dict[str, Any] = msgspec.to_builtins(value)
    return {k: v for k, v in out.items() if v is not None}


def _check_semantics(kind: str, value: _Params, where: str) -> None:
    for name in value.__struct_fields__:
        v = getattr(value, name)
        if isinstance(v, float) and not math.isfinite(v):
            raise ActionParamsError(f"{where} ({kind}): {name} must be a finite number, got {v}")
    if isinstance(value, NavAction) and value.index is None and (value.x is None
                                                                 or value.y is None):
        raise ActionParamsError(f"{where} (nav_action): give x and y, or a nav point index")
    if isinstance(value, CallbackAction):
        if not value.url.startswith(("http://", "https://")):
            raise ActionParamsError(f"{where} (callback_action): url must be http:// or "
                                    f"https://, got {value.url!r}")
        if value.method.upper() not in _METHODS:
            raise ActionParamsError(f"{where} (callback_action): method {value.method!r} is"
                                    f" not one of {', '.join(sorted(_METHODS))}")
