"""The REST status of a nav refusal comes from the code nav sets, never from its wording.

A stand-in nav (a real node on a second Zenoh session) refuses ``get_path`` with a
`RefusedError` whose code and sentence the test chooses: the gateway's answer follows the
code through its one table (`http.api.STATUS`), whatever the sentence says.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from zenros.errors import RefusedError, ServiceError
from zenros.msgs.zenros_msgs import GetPath, GetPathRequest, GetPathResponse, ResultCode
from zenros.node import Node
from zenros.services.gateway.http.api import STATUS as HTTP_STATUS
from zenros.services.gateway.testing import AsgiClient, running_gateway
from zenros.testing import linked_contexts, wait_for

REFUSALS = [code for code in ResultCode if code is not ResultCode.OK]
# wordings the gateway once read statuses from ("unknown" -> 404), and ones with no hint
WORDINGS = ["unknown path 'p' on map 'm'", "there is nothing called p on m",
            "no such path", "the path was not found", "path p is busy"]


class FakeNav:
    """``get_path`` that refuses with ``code`` and ``reason`` (a real service)."""

    def __init__(self, node: Node) -> None:
        self.code, self.reason = ResultCode.NOT_FOUND, ""
        node.create_service(GetPath, "get_path", self.handle)

    def handle(self, req: GetPathRequest) -> GetPathResponse:
        raise RefusedError(self.code, self.reason, "MapError")


@pytest.fixture(scope="module")
def rig(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[FakeNav, AsgiClient, Node]]:
    home: Path = tmp_path_factory.mktemp("gw")
    with linked_contexts(2) as ctxs:
        nav_node = Node("nav", context=ctxs[0])
        try:
            fake = FakeNav(nav_node)
            with running_gateway(ctxs[1], home, no_token_check=True) as gw:
                client = gw.create_client(GetPath, "get_path")
                assert wait_for(client.service_is_ready, 10)
                yield fake, AsgiClient(gw.http, "/api/v1"), gw
        finally:
            nav_node.close()


@pytest.mark.parametrize("code", REFUSALS, ids=[c.name for c in REFUSALS])
def test_status_follows_the_code_not_the_wording(
        rig: tuple[FakeNav, AsgiClient, Node], code: ResultCode) -> None:
    fake, http, _ = rig
    fake.code = code
    for reason in WORDINGS:
        fake.reason = reason
        r = http.get("/navigation/path", params={"map_name": "m", "path_name": "p"})
        assert r.status_code == HTTP_STATUS[code], (code, reason, r.text)
        assert r.json() == {"status": "error", "description": f"MapError: {reason}"}


def test_the_code_reaches_the_caller(rig: tuple[FakeNav, AsgiClient, Node]) -> None:
    fake, _, gw = rig
    fake.code, fake.reason = ResultCode.CONFLICT, "reworded"
    client = gw.create_client(GetPath, "get_path")
    with pytest.raises(ServiceError) as info:
        client.call(GetPathRequest(map_name="m", path_name="p"), timeout=10)
    assert info.value.code == ResultCode.CONFLICT
    assert info.value.reason == "MapError: reworded"


def test_every_code_has_a_status() -> None:
    assert set(HTTP_STATUS) == set(ResultCode)
    assert HTTP_STATUS[ResultCode.OK] == 200
