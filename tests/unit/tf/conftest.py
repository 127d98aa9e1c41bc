"""Every TF unit test runs twice: with the compiled hot paths and in pure Python."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from zenros.tf import chain, store
from zenros.tf.accel import speedups


@pytest.fixture(autouse=True, params=["c", "python"])
def tf_impl(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> Iterator[str]:
    """``"c"``: buffers made in the test use ``_speedups``; ``"python"``: they do not."""
    if request.param == "c":
        if speedups is None:
            pytest.skip("zenros.tf._speedups is not built here (or ZENROS_TF_PURE is set)")
    else:
        monkeypatch.setattr(store, "speedups", None)
        monkeypatch.setattr(chain, "_c_evaluate", None)
        monkeypatch.setattr(chain, "_c_latest", None)
    yield request.param
