"""Coverage paths (docs/robot-api.md §6.12): nav's ``compute_coverage_path`` over real Zenoh, and
``POST /navigation/coverage_path`` through a real HTTP client against the gateway."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import httpx
import pytest
from zenros.errors import ServiceError
from zenros.msgs.geometry_msgs import Point
from zenros.msgs.zenros_msgs import (
    ComputeCoveragePath,
    ComputeCoveragePathRequest,
    CoverageHole,
)
from zenros.node import Node
from zenros.services.gateway.testing import running_gateway
from zenros.services.nav.node import NavNode
from zenros.testing import linked_contexts

BORDER = [[0, 0, 0], [10, 0, 0], [10, 10, 0], [0, 10, 0], [0, 0, 0]]
HOLE = [[2, 2, 0], [2, 3, 0], [3, 3, 0], [3, 2, 0], [2, 2, 0]]


class Rig:
    def __init__(self, user: Node, port: int) -> None:
        self.client = user.create_client(ComputeCoveragePath, "compute_coverage_path")
        self.http = httpx.Client(base_url=f"http://127.0.0.1:{port}/api/v1", timeout=20)

    def post(self, **body: Any) -> httpx.Response:
        return self.http.post("/navigation/coverage_path", json=body)


@pytest.fixture(scope="module")
def rig(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Rig]:
    tmp = tmp_path_factory.mktemp("rig")  # removed by pytest (it keeps the last 3 runs)
    with linked_contexts(2) as ctxs:
        nodes: list[Node] = []
        try:
            nodes.append(NavNode("nav", context=ctxs[0], parameter_overrides={
                "use_sim_time": True, "maps_dir": str(tmp / "maps")}))
            user = Node("user", context=ctxs[1])
            nodes.append(user)
            with running_gateway(ctxs[1], tmp, no_token_check=True) as gw:
                rig = Rig(user, gw.rest_port)
                assert rig.client.wait_for_service(10)
                assert gw.graph.wait_for_service("/compute_coverage_path", 10)
                yield rig
                rig.http.close()
        finally:
            for n in reversed(nodes):
                n.close()


def test_service_plans_over_zenoh(rig: Rig) -> None:
    req = ComputeCoveragePathRequest(
        op_width=2.0, border=[Point(x=p[0], y=p[1]) for p in BORDER],
        holes=[CoverageHole(points=[Point(x=p[0], y=p[1]) for p in HOLE])])
    res = rig.client.call(req, timeout=10)
    assert res.swaths == 5 and res.swath_angle == 0.0
    ys = [p.y for p in res.path]
    assert ys == [1, 1, 3, 3, 5, 5, 7, 7, 9, 9]
    xs = [p.x for p in res.path]
    assert xs[:4] == [0, 10, 10, 0]
    with pytest.raises(ServiceError, match="op_width must be > 0"):
        rig.client.call(ComputeCoveragePathRequest(
            op_width=0.0, border=req.border), timeout=10)


def test_endpoint_returns_the_path(rig: Rig) -> None:
    r = rig.post(border=BORDER, holes=[HOLE], op_width=0.5)
    assert r.status_code == 200, r.text
    body = r.json()
    assert body["status"] == "ok" and body["swaths"] == 20
    path = body["path"]
    assert len(path) % 2 == 0 and all(len(p) == 3 and p[2] == 0 for p in path)
    for a, b in zip(path[::2], path[1::2], strict=True):
        assert a[1] == b[1]  # swaths along x at the default angle
        mid = ((a[0] + b[0]) / 2, a[1])
        assert not (2 < mid[0] < 3 and 2 < mid[1] < 3)
    rows = {p[1] for p in path}
    assert len(rows) == 20 and len(path) // 2 > 20  # the hole split some swaths

    auto = rig.post(border=[[0, 0, 0], [2, 0, 0], [2, 12, 0], [0, 12, 0]], op_width=0.5,
                    swath_angle=-1, headland_width=0.25).json()
    assert auto["swath_angle"] == pytest.approx(90.0) and auto["swaths"] == 3
    for x, y, _ in auto["path"]:
        assert 0.25 - 1e-9 <= x <= 1.75 + 1e-9 and 0.25 - 1e-9 <= y <= 11.75 + 1e-9
    turned = rig.post(border=BORDER, op_width=2.0, turn_radius=0.5).json()["path"]
    assert len(turned) > 10 and max(p[0] for p in turned) == pytest.approx(10.5, abs=0.01)


@pytest.mark.parametrize(("body", "words"), [
    ({"border": BORDER[:2], "op_width": 1.0}, "border"),
    ({"border": BORDER, "op_width": 0}, "op_width"),
    ({"border": BORDER, "op_width": -1}, "op_width"),
    ({"border": BORDER}, "op_width"),
    ({"border": BORDER, "op_width": 1.0, "headland_width": -0.5}, "headland_width"),
    ({"border": BORDER, "op_width": 1.0, "holes": [[[20, 20, 0], [21, 20, 0],
                                                     [21, 21, 0]]]}, "hole 0 is not inside"),
    ({"border": [[0, 0, 0], [2, 2, 0], [2, 0, 0], [0, 2, 0]], "op_width": 1.0},
     "intersects itself"),
    ({"border": [[0, 0, 0], [1, 1, 0], [2, 2, 0]], "op_width": 1.0}, "no area"),
    ({"border": BORDER, "op_width": 1e-4}, "raise op_width"),
    ({"border": BORDER, "op_width": 1.0, "headland_width": 6}, "nothing"),
    ({"border": BORDER, "op_width": 1.0, "bogus": 1}, "bogus"),
    ({"border": [["a", 0, 0], [1, 0, 0], [1, 1, 0]], "op_width": 1.0}, "border"),
])
def test_bad_input_is_a_400_naming_the_problem(rig: Rig, body: dict[str, Any],
                                               words: str) -> None:
    r = rig.post(**body)
    assert r.status_code == 400, r.text
    assert r.json()["status"] == "error" and words in r.json()["description"], r.text


def test_nan_and_too_many_points_are_refused(rig: Rig) -> None:
    r = rig.http.post("/navigation/coverage_path", content=b'{"border": [[0,0,0],[1,0,0],'
                      b'[1,1,0]], "op_width": NaN}', headers={"content-type":
                                                            "application/json"})
    assert r.status_code == 400, r.text
    many = [[round(math.cos(t / 1000), 3), round(math.sin(t / 1000), 3)]
            for t in range(10_001)]
    r = rig.post(border=many, op_width=0.5)
    assert r.status_code in (400, 413), r.text
    assert r.json()["status"] == "error"
    r = rig.post(border=[[0, 0, 0], [1, 0, 0], [1, 1, 0]], op_width=0.5)
    assert r.status_code == 200 and r.json()["path"]  # the service survived it all


def test_without_nav_the_endpoint_answers_503(tmp_path: Path) -> None:
    with linked_contexts(1) as ctxs, running_gateway(ctxs[0], tmp_path,
                                                     no_token_check=True) as gw:
        r = httpx.post(f"http://127.0.0.1:{gw.rest_port}/api/v1/navigation/coverage_path",
                       json={"border": BORDER, "op_width": 1.0}, timeout=20)
        assert r.status_code == 503, r.text
        assert "nav service is starting" in r.json()["description"]  # just after start
        assert r.headers["retry-after"] == "2"
