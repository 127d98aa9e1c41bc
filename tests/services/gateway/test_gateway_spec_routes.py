"""Every HTTP operation in the robot API spec's tables is in the gateway's route list."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from zenros.services.gateway.http.spec_routes import SPEC_OPERATIONS

SPEC = Path("/work/shared/specs/robot-api.md")
_OP = re.compile(r"`((?:GET|POST|PUT|DELETE)(?:/(?:GET|POST|PUT|DELETE))*) "
                 r"(/[A-Za-z0-9_/<>{},.\-]*)")


@pytest.mark.skipif(not SPEC.exists(), reason="the spec is not on this machine")
def test_spec_tables_are_covered() -> None:
    text = SPEC.read_text()
    body = text.split("## 1. Transport overview")[1].split("## 18. Native SDK")[0]
    ops = {(m, path.replace("<", "{").replace(">", "}"))
           for found in _OP.finditer(body)
           for m, path in ((m, found.group(2)) for m in found.group(1).split("/"))}
    missing = ops - set(SPEC_OPERATIONS)
    assert not missing, sorted(missing)
    assert len(ops) >= 175


def test_core_subset_is_listed() -> None:
    ops = set(SPEC_OPERATIONS)
    for op in [("GET", "/token"), ("PUT", "/system/speed"), ("POST", "/navigation/init_pose"),
               ("DELETE", "/navigation/loop_task"), ("GET", "/action/update_wait_req")]:
        assert op in ops
    assert len(ops) == len(SPEC_OPERATIONS)
