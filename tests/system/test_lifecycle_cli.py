"""`zenros lifecycle nodes|get|set|list` against a managed node on a real router."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from zenros.cli.__main__ import main
from zenros.context import Context
from zenros.examples.lifecycle_talker import LifecycleTalker

pytestmark = pytest.mark.system


@pytest.fixture
def talker(observer: Context) -> Iterator[LifecycleTalker]:
    node = LifecycleTalker("lc_talker", context=observer)
    try:
        yield node
    finally:
        node.close()


def test_lifecycle_verbs(router: str, prefix: str, talker: LifecycleTalker,
                         capsys: pytest.CaptureFixture[str]) -> None:
    def cli(*args: str) -> tuple[int, str]:
        code = main(["lifecycle", *args, "-e", router, "--prefix", prefix])
        return code, capsys.readouterr().out

    assert cli("nodes") == (0, "/lc_talker\n")
    assert cli("get", "/lc_talker") == (0, "unconfigured [1]\n")
    code, out = cli("list", "lc_talker")
    assert code == 0
    assert out.startswith("- configure [1]\n\tStart: unconfigured\n\tGoal: configuring\n")
    assert "- shutdown [5]" in out
    assert cli("set", "/lc_talker", "configure") == (0, "Transitioning successful\n")
    assert cli("set", "/lc_talker", "3") == (0, "Transitioning successful\n")  # by id
    assert talker.current_state.label == "active"
    assert cli("get") == (0, "/lc_talker: active [3]\n")
    assert main(["lifecycle", "set", "/lc_talker", "configure", "-e", router,
                 "--prefix", prefix]) == 1
    err = capsys.readouterr().err
    assert "unknown transition 'configure'" in err and "- deactivate [4]" in err
    code, out = cli("list", "/lc_talker", "--all")
    assert out.count("- ") == 25
