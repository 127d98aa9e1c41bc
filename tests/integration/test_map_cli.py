"""`zenros map save|show` (docs/cli.md) as a process, through a real router, against a mapping
node that follows the ``zenros_msgs.slam`` contract (`slam_stand_in`) and nav's side of it
(``map_server/save_grid``, ``map_saver/save_map``) served here."""

from __future__ import annotations

import json
import subprocess
import sys
from collections.abc import Iterator
from typing import Any

import pytest
from slam_stand_in import SlamStandIn
from zenros.context import Context
from zenros.msgs.nav2_msgs import SaveMap, SaveMapRequest, SaveMapResponse
from zenros.msgs.zenros_msgs.slam import (
    SaveGrid,
    SaveGridRequest,
    SaveGridResponse,
    StartMapping,
    StartMappingRequest,
)
from zenros.node import Node
from zenros.session import SessionOptions
from zenros.testing import wait_for

TIMEOUT = 20.0


def zenros(router: str, prefix: str, *args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "zenros.cli", *args, "-e", router,
                           "--prefix", prefix], capture_output=True, text=True, timeout=60,
                          check=False)


class NavSide(Node):
    """Nav's side of the contract: records what it is asked to store."""

    node_name = "nav"

    def setup(self) -> None:
        self.grids: list[SaveGridRequest] = []
        self.saved: list[SaveMapRequest] = []
        self.create_service(SaveGrid, "map_server/save_grid", self.on_grid)
        self.create_service(SaveMap, "map_saver/save_map", self.on_save)

    def on_grid(self, req: SaveGridRequest) -> SaveGridResponse:
        self.grids.append(req)
        return SaveGridResponse(name=req.name)

    def on_save(self, req: SaveMapRequest) -> SaveMapResponse:
        self.saved.append(req)
        return SaveMapResponse(result=True)


@pytest.fixture
def robot(router: str, prefix: str) -> Iterator[tuple[Context, SlamStandIn, NavSide]]:
    ctx = Context(SessionOptions(connect=[router]), prefix=prefix)
    nodes: list[Any] = []
    try:
        nodes.append(NavSide(context=ctx))
        nodes.append(SlamStandIn(context=ctx))
        yield ctx, nodes[1], nodes[0]
    finally:
        for n in reversed(nodes):
            n.close()
        ctx.close()


def test_map_show_and_save_with_and_without_mapping(
        router: str, prefix: str, robot: tuple[Context, SlamStandIn, NavSide]) -> None:
    ctx, _, nav = robot
    r = zenros(router, prefix, "map", "show", "--timeout", "2")
    assert r.returncode == 1 and "no map on /map" in r.stderr, r.stderr
    # not mapping: nav's map_saver stores the map topic's grid
    r = zenros(router, prefix, "map", "save", "office")
    assert r.returncode == 0, r.stderr
    assert "map_saver/save_map" in r.stdout
    assert [(s.map_topic, s.map_url) for s in nav.saved] == [("map", "office")]
    start = Node("starter", context=ctx)
    try:
        client = start.create_client(StartMapping, "slam/start")
        assert client.wait_for_service(TIMEOUT)
        assert client.call(StartMappingRequest(), TIMEOUT).code == 0
    finally:
        start.close()
    r = zenros(router, prefix, "map", "show")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0] == ("map: 200 x 200 cells at 0.050 m (10.00 x 10.00 m), origin "
                        "(-5.00, -5.00, 0.00)")
    assert lines[1].startswith("known: 3.1") and "free 3.1" in lines[1]  # a 1 m disc
    assert lines[2].startswith("mapping: mapping (laser, a new map)")
    r = zenros(router, prefix, "map", "show", "--json")
    shown = json.loads(r.stdout)
    assert shown["map"]["width"] == 200 and shown["mapping"]["state"] == "mapping"
    assert 0.0 < shown["map"]["coverage"] < 0.05
    # mapping: the mapping node saves what it built, through nav's save_grid
    r = zenros(router, prefix, "map", "save", "site2", "--type", "elevator", "--levels", "1", "2")
    assert r.returncode == 0, r.stderr
    assert "slam/save" in r.stdout
    assert wait_for(lambda: len(nav.grids) == 1, TIMEOUT)
    g = nav.grids[0]
    assert (g.name, g.type, g.levels, g.grid.info.width) == ("site2", "elevator", [1, 2], 200)
    r = zenros(router, prefix, "map", "save", "../x")
    assert r.returncode == 1 and "invalid map name" in r.stderr and "INVALID" in r.stderr
