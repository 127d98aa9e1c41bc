"""tf2 error codes ↔ exceptions, and static links written as text."""

from __future__ import annotations

import pytest
from zenros.errors import (
    BackwardExtrapolationException,
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    LookupException,
    NoDataForExtrapolationException,
    TimeoutException,
    TransformException,
)
from zenros.msgs.tf_srvs import TF2Error
from zenros.tf import error_code, error_msg, exception_from_error, link_from_numbers, parse_link


@pytest.mark.parametrize(("exc", "code"), [
    (LookupException("x"), TF2Error.LOOKUP_ERROR),
    (ConnectivityException("x"), TF2Error.CONNECTIVITY_ERROR),
    (ExtrapolationException("x"), TF2Error.EXTRAPOLATION_ERROR),
    (BackwardExtrapolationException("x"), TF2Error.EXTRAPOLATION_ERROR),
    (NoDataForExtrapolationException("x"), TF2Error.EXTRAPOLATION_ERROR),
    (InvalidArgumentException("x"), TF2Error.INVALID_ARGUMENT_ERROR),
    (TimeoutException("x"), TF2Error.TIMEOUT_ERROR),
    (TransformException("x"), TF2Error.TRANSFORM_ERROR),
])  # fmt: skip
def test_codes_round_trip(exc: TransformException, code: int) -> None:
    assert error_code(exc) == code
    err = error_msg(exc)
    assert err == TF2Error(error=code, error_string="x")
    back = exception_from_error(err)
    assert back is not None and str(back) == "x"
    assert isinstance(exc, type(back))  # the subclass kinds come back as their family


def test_no_error_and_unknown_codes() -> None:
    assert exception_from_error(TF2Error()) is None
    e = exception_from_error(TF2Error(error=42))
    assert type(e) is TransformException and "42" in str(e)


def test_parse_link_takes_a_string_or_tokens() -> None:
    a = parse_link("1 2 3 0 0 0 p c")
    b = parse_link(["1", "2", "3", "0", "0", "0", "1", "p", "c"])
    assert a.transform == b.transform and a.header.frame_id == "p" == b.header.frame_id
    with pytest.raises(InvalidArgumentException, match="got 3 values"):
        parse_link("1 p c")
    with pytest.raises(InvalidArgumentException, match="6 numbers .* or 7"):
        link_from_numbers([1.0, 2.0], "p", "c")
    with pytest.raises(InvalidArgumentException, match="finite"):
        link_from_numbers([float("inf")] * 6, "p", "c")
