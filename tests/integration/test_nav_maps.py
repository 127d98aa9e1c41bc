"""The nav map server and per-map records over real Zenoh (no chassis needed): the latched
map, load_map result codes with the current map kept, list/switch/import/current, nav
points, paths, virtual walls and charge pose persisted across a restart."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from zenros.context import Context
from zenros.errors import MapError, ServiceError
from zenros.maps import GridMap, save_map
from zenros.msgs.geometry_msgs import Point, Pose2D
from zenros.msgs.nav2_msgs import LoadMap, LoadMapRequest, LoadMapResponse
from zenros.msgs.nav_msgs import OccupancyGrid
from zenros.msgs.zenros_msgs import nav as m
from zenros.node import Node
from zenros.qos import QOS_LATCHED
from zenros.services.nav.node import NavNode
from zenros.testing import linked_contexts, wait_for


@pytest.fixture
def ctxs() -> Iterator[list[Context]]:
    with linked_contexts(2) as c:
        yield c


@pytest.fixture
def nav_factory(ctxs: list[Context], tmp_path: Path) -> Iterator[Any]:
    nodes: list[Node] = []

    def start(**params: Any) -> NavNode:
        node = NavNode("nav", context=ctxs[0],
                       parameter_overrides={"maps_dir": str(tmp_path / "maps"), **params})
        nodes.append(node)
        return node

    yield start
    for n in nodes:
        n.close()


@pytest.fixture
def user(ctxs: list[Context]) -> Iterator[Node]:
    node = Node("user", context=ctxs[1])
    yield node
    node.close()


def call(user: Node, srv: Any, name: str, req: Any) -> Any:
    client = user.create_client(srv, name)
    assert client.wait_for_service(10)
    return client.call(req, timeout=10)


def small_map(folder: Path, name: str = "lab") -> Path:
    grid = np.zeros((40, 60), dtype=np.int8)
    grid[0, :] = grid[-1, :] = grid[:, 0] = grid[:, -1] = 100
    folder.mkdir(parents=True, exist_ok=True)
    save_map(GridMap(grid, 0.1, (-1.0, -2.0, 0.0)), folder / f"{name}.yaml")
    return folder / f"{name}.yaml"


def test_map_is_latched_and_listed(nav_factory: Any, user: Node) -> None:
    nav_factory()
    got: list[OccupancyGrid] = []
    user.create_subscription(OccupancyGrid, "map", got.append, QOS_LATCHED)
    assert wait_for(lambda: got, 10)  # a late subscriber gets the latched map
    assert (got[0].info.width, got[0].info.height) == (600, 400)
    assert got[0].info.resolution == pytest.approx(0.05)
    listed = call(user, m.ListMaps, "map_server/list_maps", m.ListMapsRequest())
    assert listed.current == "office" and [x.name for x in listed.maps] == ["office"]
    info = listed.maps[0]
    assert info.origin == [-3.0, -9.75, 0.0] and len(info.md5sum) == 32
    assert Path(info.yaml_path).is_file() and Path(info.image_path).is_file()
    cur = call(user, m.GetCurrentMap, "map_server/current_map", m.GetCurrentMapRequest())
    assert (cur.name, cur.md5sum) == ("office", info.md5sum)
    # the map's dock (poses.yaml) became its charge pose
    charge = call(user, m.GetChargePose, "get_charge_pose", m.GetChargePoseRequest())
    assert charge.is_set and charge.pose.x == pytest.approx(22.0)


def test_load_map_codes_and_a_bad_map_keeps_the_current_one(
        nav_factory: Any, user: Node, tmp_path: Path) -> None:
    nav = nav_factory()
    client = user.create_client(LoadMap, "map_server/load_map")
    assert client.wait_for_service(10)
    missing = client.call(LoadMapRequest(map_url=str(tmp_path / "nope.yaml")), timeout=10)
    assert missing.result == LoadMapResponse.RESULT_MAP_DOES_NOT_EXIST
    bad_meta = tmp_path / "bad" / "bad.yaml"
    small_map(tmp_path / "bad", "bad")
    bad_meta.write_text(bad_meta.read_text().replace("free_thresh: 0.196", "free_thresh: 0.9"))
    res = client.call(LoadMapRequest(map_url=str(bad_meta)), timeout=10)
    assert res.result == LoadMapResponse.RESULT_INVALID_MAP_METADATA
    no_image = small_map(tmp_path / "noimg", "noimg")
    no_image.with_suffix(".pgm").unlink()
    res = client.call(LoadMapRequest(map_url=str(no_image)), timeout=10)
    assert res.result == LoadMapResponse.RESULT_INVALID_MAP_DATA
    assert nav.core.maps.current == "office"
    good = small_map(tmp_path / "src")
    res = client.call(LoadMapRequest(map_url=str(good)), timeout=10)
    assert res.result == LoadMapResponse.RESULT_SUCCESS
    assert (res.map.info.width, res.map.info.height) == (60, 40)
    assert nav.core.maps.current == "lab"
    assert nav.core.costmaps.snapshot().costs.shape == (40, 60)


def test_switch_and_import_maps(nav_factory: Any, user: Node, tmp_path: Path) -> None:
    nav_factory()
    got: list[OccupancyGrid] = []
    user.create_subscription(OccupancyGrid, "map", got.append, QOS_LATCHED)
    bad = call(user, m.SwitchMap, "switch_map", m.SwitchMapRequest(map_name="attic"))
    assert not bad.success and "unknown map 'attic'" in bad.message and "office" in bad.message
    imported = call(user, m.ImportMap, "map_server/import_map",
                    m.ImportMapRequest(yaml_path=str(small_map(tmp_path / "src"))))
    assert imported.info.name == "lab" and imported.info.width == 60
    with pytest.raises(ServiceError, match="already exists"):
        call(user, m.ImportMap, "map_server/import_map",
             m.ImportMapRequest(yaml_path=str(small_map(tmp_path / "src"))))
    ok = call(user, m.SwitchMap, "switch_map", m.SwitchMapRequest(map_name="lab"))
    assert ok.success and ok.info.name == "lab"
    assert wait_for(lambda: got and got[-1].info.width == 60, 10)
    listed = call(user, m.ListMaps, "map_server/list_maps", m.ListMapsRequest())
    assert [x.name for x in listed.maps] == ["lab", "office"] and listed.current == "lab"
    only = call(user, m.ListMaps, "map_server/list_maps", m.ListMapsRequest(name="lab"))
    assert [x.name for x in only.maps] == ["lab"]


def test_nav_points_paths_walls_persist_across_restart(nav_factory: Any, user: Node) -> None:
    nav = nav_factory()
    points = [m.NavPoint(name="desk", x=1.0, y=2.0, theta=0.5),
              m.NavPoint(name="door", x=3.0, y=-1.0, error_x=0.2, error_y=0.2)]
    res = call(user, m.SetNavPoints, "set_nav_points",
               m.SetNavPointsRequest(path_name="round", points=points))
    assert res.map_name == "office" and res.points == points
    call(user, m.SetPath, "set_path", m.SetPathRequest(
        path_name="round", points=[Point(x=0.0, y=0.0), Point(x=1.0, y=2.0)]))
    wall = m.VirtualWall(name="w", points=[Point(x=5.0, y=-1.3), Point(x=5.0, y=1.3)])
    call(user, m.SetVirtualWalls, "set_virtual_walls", m.SetVirtualWallsRequest(walls=[wall]))
    area = m.ForbiddenArea(name="a", points=[Point(x=1.0, y=-1.0), Point(x=2.0, y=-1.0),
                                             Point(x=2.0, y=0.0)])
    call(user, m.SetForbiddenAreas, "set_forbidden_areas",
         m.SetForbiddenAreasRequest(areas=[area]))
    assert nav.core.costmaps.in_keepout(5.0, 0.0) and nav.core.costmaps.cost_at(5.0, 0.0) == 254
    call(user, m.SetChargePose, "set_charge_pose",
         m.SetChargePoseRequest(pose=Pose2D(x=1.5, y=0.5, theta=math.pi)))
    # bad requests are refused with the reason, and change nothing
    with pytest.raises(ServiceError, match="'desk' is already used"):
        call(user, m.SetNavPoints, "set_nav_points",
             m.SetNavPointsRequest(path_name="round", points=points + points[:1]))
    with pytest.raises(ServiceError, match="finite"):
        call(user, m.SetNavPoints, "set_nav_points", m.SetNavPointsRequest(
            path_name="round", points=[m.NavPoint(x=math.nan)]))
    with pytest.raises(ServiceError, match="at least 2 points"):
        call(user, m.SetVirtualWalls, "set_virtual_walls", m.SetVirtualWallsRequest(
            walls=[m.VirtualWall(points=[Point()])]))
    with pytest.raises(ServiceError, match="unknown path 'nope'.*round"):
        call(user, m.GetNavPoints, "get_nav_points", m.GetNavPointsRequest(path_name="nope"))
    with pytest.raises(ServiceError, match="invalid path name"):
        call(user, m.SetPath, "set_path", m.SetPathRequest(path_name="../x"))
    with pytest.raises(ServiceError, match="unknown map 'attic'"):
        call(user, m.ListPaths, "list_paths", m.ListPathsRequest(map_name="attic"))

    nav.close()
    nav = nav_factory()  # a restart reads it all back from the maps folder
    got = call(user, m.GetNavPoints, "get_nav_points", m.GetNavPointsRequest(
        map_name="office", path_name="round"))
    assert got.points == points
    path = call(user, m.GetPath, "get_path", m.GetPathRequest(path_name="round"))
    assert [(p.x, p.y) for p in path.points] == [(0.0, 0.0), (1.0, 2.0)]
    assert call(user, m.ListPaths, "list_paths", m.ListPathsRequest()).paths == [
        m.PathRef(map_name="office", path_name="round")]
    walls = call(user, m.GetVirtualWalls, "get_virtual_walls", m.GetVirtualWallsRequest())
    assert walls.walls == [wall]
    areas = call(user, m.GetForbiddenAreas, "get_forbidden_areas",
                 m.GetForbiddenAreasRequest())
    assert areas.areas == [area]
    assert nav.core.costmaps.in_keepout(5.0, 0.0)  # keep-out is back in the costmap
    charge = call(user, m.GetChargePose, "get_charge_pose", m.GetChargePoseRequest())
    assert (charge.pose.x, charge.pose.y, charge.pose.theta) == (1.5, 0.5, math.pi)
    call(user, m.DeleteNavPoints, "delete_nav_points",
         m.DeleteNavPointsRequest(path_name="round"))
    assert call(user, m.GetNavPoints, "get_nav_points",
                m.GetNavPointsRequest(path_name="round")).points == []
    call(user, m.DeletePath, "delete_path", m.DeletePathRequest(path_name="round"))
    assert call(user, m.ListPaths, "list_paths", m.ListPathsRequest()).paths == []


def test_a_bad_start_map_fails_startup_naming_file_and_field(
        nav_factory: Any, tmp_path: Path) -> None:
    bad = small_map(tmp_path / "bad", "bad")
    bad.write_text(bad.read_text().replace("resolution: 0.1", "resolution: -1"))
    with pytest.raises(MapError, match=r"bad\.yaml.*'resolution'"):
        nav_factory(map=str(bad))
