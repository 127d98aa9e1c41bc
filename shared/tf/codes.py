"""tf2's error codes (`TF2Error`) to and from the `TransformException` classes."""

from __future__ import annotations

from ..errors import (
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    TimeoutException,
    TransformException,
)
from ..msgs.tf_srvs import TF2Error

__all__ = ["error_code", "error_msg", "exception_from_error"]

# Most specific first: the three extrapolation kinds share EXTRAPOLATION_ERROR, as in tf2.
_CODES: tuple[tuple[type[TransformException], int], ...] = (
    (LookupException, TF2Error.LOOKUP_ERROR),
    (ConnectivityException, TF2Error.CONNECTIVITY_ERROR),
    (ExtrapolationException, TF2Error.EXTRAPOLATION_ERROR),
    (InvalidArgumentException, TF2Error.INVALID_ARGUMENT_ERROR),
    (TimeoutException, TF2Error.TIMEOUT_ERROR),
)


def error_code(exc: TransformException) -> int:
    """The `TF2Error` code for an exception (TRANSFORM_ERROR for the base class)."""
    for cls, code in _CODES:
        if isinstance(exc, cls):
            return code
    return TF2Error.TRANSFORM_ERROR


def error_msg(exc: TransformException) -> TF2Error:
    """The `TF2Error` message that reports ``exc``."""
    return TF2Error(error=error_code(exc), error_string=str(exc))


def exception_from_error(err: TF2Error) -> TransformException | None:
    """The exception a `TF2Error` stands for (None for NO_ERROR); unknown codes give the
    base `TransformException`."""
    if err.error == TF2Error.NO_ERROR:
        return None
    for cls, code in _CODES:
        if code == err.error:
            return cls(err.error_string)
    return TransformException(err.error_string or f"tf2 error code {err.error}")
