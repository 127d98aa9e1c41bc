"""Port errors: how a call from the gateway to the robot failed, in the robot's terms.

The ports (and `state.presence`) raise them; every door says them in its own protocol; the
HTTP door maps them to status codes in one place (`http.api.STATUS`). Each kind is one
`ResultCode` of zenros_msgs, the code the robot's services answer with (`port_error`).
"""

from __future__ import annotations

from typing import ClassVar, Final

from zenros.msgs.zenros_msgs.result import ResultCode

__all__ = ["Conflict", "Failed", "NoAnswer", "NotFound", "PortError", "Refused", "Unavailable",
           "port_error"]


class PortError(Exception):
    """A call to the robot failed; ``detail`` says what, ``retry_after`` (s) when to retry."""

    code: ClassVar[ResultCode] = ResultCode.FAILED

    def __init__(self, detail: str, retry_after: int | None = None) -> None:
        super().__init__(detail)
        self.detail = detail
        self.retry_after = retry_after


class Unavailable(PortError):
    """The backend is not there: starting, gone, or not running."""

    code = ResultCode.UNAVAILABLE


class NoAnswer(PortError):
    """The backend did not answer in time."""

    code = ResultCode.TIMEOUT


class Failed(PortError):
    """The backend failed while handling the call."""

    code = ResultCode.FAILED


class Refused(PortError, ValueError):
    """The backend refused the request as given (a ValueError: a bad argument, as the
    gateway's `NavPort` promises)."""

    code = ResultCode.INVALID


class NotFound(Refused):
    """What the request names does not exist."""

    code = ResultCode.NOT_FOUND


class Conflict(Refused):
    """The request cannot be done in the robot's present state."""

    code = ResultCode.CONFLICT


_BY_CODE: Final[dict[ResultCode, type[PortError]]] = {
    cls.code: cls for cls in (Unavailable, NoAnswer, Failed, Refused, NotFound, Conflict)}


def port_error(code: int | None, detail: str, retry_after: int | None = None) -> PortError:
    """The port error for a service's result ``code``; a missing or unknown code (an error
    that is not a refusal) is `Failed`."""
    try:
        kind = _BY_CODE[ResultCode(code if code is not None else ResultCode.FAILED)]
    except ValueError:
        kind = Failed
    return kind(detail, retry_after)

