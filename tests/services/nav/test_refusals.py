"""nav's refusals carry a `ResultCode`: what is not stored is NOT_FOUND, a bad request
INVALID, whatever the sentence says; other failures are not refusals."""

from __future__ import annotations

from pathlib import Path

import pytest
from zenros.errors import MapError, MapItemNotFoundError, RefusedError
from zenros.msgs.zenros_msgs import ResultCode
from zenros.services.nav.maps.store import MapStore
from zenros.services.nav.refusals import code_of, coded


def _refuse(exc: Exception) -> object:
    def handler(req: object) -> object:
        raise exc
    return coded(handler)


@pytest.mark.parametrize(("exc", "code"), [
    (MapItemNotFoundError("anything at all"), ResultCode.NOT_FOUND),
    (KeyError("x"), ResultCode.NOT_FOUND),
    (MapError("unknown map 'x'"), ResultCode.INVALID),   # the wording does not decide
    (ValueError("no such thing"), ResultCode.INVALID),
])
def test_refusals_carry_their_code(exc: Exception, code: ResultCode) -> None:
    handler = _refuse(exc)
    with pytest.raises(RefusedError) as info:
        handler(None)  # type: ignore[operator]
    assert info.value.code == code
    assert info.value.kind == type(exc).__name__
    assert str(info.value) == str(exc)


def test_a_failure_is_not_a_refusal() -> None:
    assert code_of(RuntimeError("bug")) is None
    with pytest.raises(RuntimeError):
        _refuse(RuntimeError("bug"))(None)  # type: ignore[operator]


def test_an_unknown_map_is_not_found(tmp_path: Path) -> None:
    with pytest.raises(MapItemNotFoundError):
        MapStore(tmp_path).require("nowhere")
