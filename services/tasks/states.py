"""Task and action states (the API's spellings) and the transitions a request may make."""

from __future__ import annotations

from typing import Final

__all__ = [
    "CANCELLED",
    "COMPLETE",
    "ERROR",
    "FAILED",
    "PAUSED",
    "STATES",
    "TERMINAL",
    "WAITTING",
    "WORKING",
    "TaskStateError",
    "check_request",
]

WAITTING: Final = "WAITTING"  # sic: the wire value keeps the source's spelling
WORKING: Final = "WORKING"
PAUSED: Final = "PAUSED"
CANCELLED: Final = "CANCELLED"
ERROR: Final = "ERROR"
COMPLETE: Final = "COMPLETE"
# a normal failure of a behaviour-tree child (docs/robot-api.md §8.1 impl. note)
FAILED: Final = "FAILED"

STATES: Final = (WAITTING, WORKING, PAUSED, CANCELLED, ERROR, COMPLETE, FAILED)
TERMINAL: Final = frozenset({CANCELLED, ERROR, COMPLETE, FAILED})

# request -> the states it may start from, and the state it leads to
_REQUESTS: Final[dict[str, tuple[frozenset[str], str]]] = {
    "start": (frozenset({WAITTING}) | TERMINAL, WORKING),
    "pause": (frozenset({WORKING}), PAUSED),
    "resume": (frozenset({PAUSED}), WORKING),
    "stop": (frozenset({WAITTING, WORKING, PAUSED}), CANCELLED),
}

_HINTS: Final = {
    ("start", WORKING): "it is already running; pause or stop it first",
    ("start", PAUSED): "it is paused; resume or stop it",
    ("resume", WORKING): "it is already running",
}


class TaskStateError(ValueError):
    """A request the task's state does not allow (HTTP 409); names state and valid requests."""

    def __init__(self, task_id: str, request: str, state: str) -> None:
        allowed = sorted(r for r, (src, _) in _REQUESTS.items() if state in src)
        hint = _HINTS.get((request, state), "")
        text = f"cannot {request} task {task_id}: it is {state}"
        if hint:
            text += f" ({hint})"
        text += f"; allowed in {state}: {', '.join(allowed) or 'nothing'}"
        super().__init__(text)
        self.task_id, self.request, self.state = task_id, request, state


def check_request(task_id: str, request: str, state: str) -> str:
    """The state ``request`` leads to from ``state``, or raise `TaskStateError`."""
    sources, target = _REQUESTS[request]
    if state not in sources:
        raise TaskStateError(task_id, request, state)
    return target
