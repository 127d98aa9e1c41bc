"""Port errors: how a call from the gateway to the robot failed, in the robot's terms.

The ports (and `state.presence`) raise them; every door says them in its own protocol; the
HTTP door maps them to status codes in one place (`http.api.STATUS`).
"""

from __future__ import annotations

__all__ = ["Conflict", "Failed", "NoAnswer", "NotFound", "PortError", "Refused", "TaskError",
           "Unavailable"]


class PortError(Exception):
    """A call to the robot failed; ``detail`` says what, ``retry_after`` (s) when to retry."""

    def __init__(self, detail: str, retry_after: int | None = None) -> None:
        super().__init__(detail)
        self.detail = detail
        self.retry_after = retry_after


class Unavailable(PortError):
    """The backend is not there: starting, gone, or not running."""


class NoAnswer(PortError):
    """The backend did not answer in time."""


class Failed(PortError):
    """The backend failed while handling the call."""


class Refused(PortError):
    """The backend refused the request as given."""


class NotFound(Refused):
    """What the request names does not exist."""


class Conflict(Refused):
    """The request cannot be done in the robot's present state."""


class TaskError(PortError):
    """The tasks service refused a call with its own ``code`` (zenros_msgs/TaskCall)."""

    def __init__(self, code: int, detail: str, retry_after: int | None = None) -> None:
        super().__init__(detail, retry_after)
        self.code = code
