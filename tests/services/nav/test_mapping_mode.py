"""Nav's side of mapping without Zenoh: save_grid and map_saver into the maps folder, the
record of a built map, mapping mode in the core (refused while driving, the SLAM node's map
and transform followed, the map taken back), and localisation on a built map."""

from __future__ import annotations

import math
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from zenros.maps import GridMap, load_map, read_image, read_meta
from zenros.msgs.geometry_msgs import Pose2D
from zenros.msgs.nav2_msgs import SaveMapRequest
from zenros.msgs.zenros_msgs.nav import ListMapsRequest
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.msgs.zenros_msgs.slam import SaveGridRequest
from zenros.se2 import Pose2
from zenros.services.nav.core import MappingRefused, NavConfig, NavCore
from zenros.services.nav.maps.mapmeta import RECORD_FILE, MapRecord
from zenros.services.nav.maps.saver import SaveRefused
from zenros.services.nav.motion.behavior import Behavior, Sense
from zenros.services.nav.params import DEMO_MAP


def built_grid() -> GridMap:
    """A 3 m x 2 m room (walls occupied, inside free, a strip unknown), in a frame whose
    origin is not the world's."""
    g = np.zeros((40, 60), dtype=np.int8)
    g[0, :] = g[-1, :] = 100
    g[:, 0] = g[:, -1] = 100
    g[10:20, 40:50] = -1
    g[25, 20] = 37  # in between: unknown once saved (trinary)
    return GridMap(g, 0.05, (-1.2, -0.7, 0.0))


@pytest.fixture
def core(tmp_path: Path) -> Iterator[NavCore]:
    c = NavCore(NavConfig(), tmp_path / "maps")
    c.maps.start(DEMO_MAP)
    yield c
    c.close()


def test_save_grid_writes_a_map_server_map_listed_with_its_record(core: NavCore) -> None:
    grid = built_grid()
    req = SaveGridRequest(name="site2", grid=grid.to_msg(), type="elevator", levels=[1, 2],
                          map_to_odom=Pose2D(x=0.5, y=-0.25, theta=0.1), use_map_to_odom=True)
    resp = core.saver.handle_save_grid(req)
    assert (resp.code, resp.name) == (ResultCode.OK, "site2"), resp.message
    folder = core.maps.store.folder("site2")
    assert {p.name for p in folder.iterdir()} == {"site2.yaml", "site2.pgm", "site2.png",
                                                  RECORD_FILE}
    meta = read_meta(folder / "site2.yaml")
    assert (meta.occupied_thresh, meta.free_thresh, meta.mode) == (0.65, 0.196, "trinary")
    assert meta.image.name == "site2.pgm" and meta.origin == (-1.2, -0.7, 0.0)
    assert np.array_equal(read_image(folder / "site2.png"), read_image(folder / "site2.pgm"))
    assert set(np.unique(read_image(folder / "site2.pgm"))) == {0, 205, 254}
    back = load_map(folder / "site2.yaml").grid
    want = grid.grid.copy()
    want[25, 20] = -1
    assert np.array_equal(back, want)  # trinary round trip is exact
    rec = core.maps.store.record("site2")
    assert rec.built_by_slam and rec.map_to_odom == Pose2D(x=0.5, y=-0.25, theta=0.1)
    listed = {m.name: m for m in core.maps.handle_list_maps(ListMapsRequest()).maps}
    assert (listed["site2"].type, listed["site2"].levels, listed["site2"].slam_type) == (
        "elevator", [1, 2], "lidar")
    assert (listed["office"].type, listed["office"].levels) == ("floor", [])


@pytest.mark.parametrize("name", ["", "../evil", "a/b", ".hidden", "x" * 65])
def test_save_grid_refuses_bad_names(core: NavCore, name: str) -> None:
    resp = core.saver.handle_save_grid(SaveGridRequest(name=name, grid=built_grid().to_msg()))
    assert resp.code == ResultCode.INVALID and "invalid map name" in resp.message
    assert core.maps.store.names() == ["office"]


def test_save_grid_refuses_the_map_in_use_bad_grids_and_types(core: NavCore) -> None:
    resp = core.saver.handle_save_grid(SaveGridRequest(name="office",
                                                       grid=built_grid().to_msg()))
    assert resp.code == ResultCode.CONFLICT and "in use" in resp.message
    msg = built_grid().to_msg()
    msg.info.width = 7  # 7 x 40 cells but 2400 values
    resp = core.saver.handle_save_grid(SaveGridRequest(name="x", grid=msg))
    assert resp.code == ResultCode.INVALID and "values" in resp.message
    resp = core.saver.handle_save_grid(SaveGridRequest(name="x"))  # 0 x 0
    assert resp.code == ResultCode.INVALID
    core.saver.handle_save_grid(SaveGridRequest(name="lab", grid=built_grid().to_msg()))
    before = {p.name: p.read_bytes() for p in core.maps.store.folder("lab").iterdir()}
    msg = built_grid().to_msg()
    msg.info.origin.position.x = math.inf
    msg.data[:] = 100
    resp = core.saver.handle_save_grid(SaveGridRequest(name="lab", grid=msg))
    assert resp.code == ResultCode.INVALID and "origin" in resp.message
    assert {p.name: p.read_bytes() for p in core.maps.store.folder("lab").iterdir()} == before
    resp = core.saver.handle_save_grid(SaveGridRequest(name="x", grid=built_grid().to_msg(),
                                                       type="basement"))
    assert resp.code == ResultCode.INVALID and "type" in resp.message
    assert core.maps.store.names() == ["lab", "office"]


def test_map_saver_writes_a_file_path_or_a_stored_name(core: NavCore, tmp_path: Path) -> None:
    msg = built_grid().to_msg()
    out = core.saver.save_map(msg, SaveMapRequest(map_url=str(tmp_path / "site"),
                                                  image_format="png"))
    assert out == str(tmp_path / "site.yaml")
    assert np.array_equal(load_map(tmp_path / "site.yaml").grid[0], built_grid().grid[0])
    assert read_meta(tmp_path / "site.yaml").image.name == "site.png"
    assert core.saver.save_map(msg, SaveMapRequest(map_url="lab")) == "lab"
    assert core.maps.store.record("lab").built_by_slam
    for bad in (SaveMapRequest(map_url="relative/site"), SaveMapRequest(map_url="/no/such/x"),
                SaveMapRequest(map_url=str(tmp_path / "s"), image_format="gif"),
                SaveMapRequest(map_url=str(tmp_path / "s"), map_mode="scale"),
                SaveMapRequest(map_url=str(tmp_path / "s"), free_thresh=0.9),
                SaveMapRequest(map_url="")):
        with pytest.raises(SaveRefused):
            core.saver.save_map(msg, bad)


class Drive(Behavior):
    def tick(self, sense: Sense) -> tuple[float, float]:
        return (0.1, 0.0)


def test_mapping_mode_follows_the_slam_node_and_gives_the_map_back(core: NavCore) -> None:
    loc = core.localizer
    core.on_odom(1, Pose2(1.0, 0.0, 0.0), 0.0, 0.0)
    core.on_ground_truth(1, Pose2(3.0, 0.0, 0.0))
    assert loc.pose() == Pose2(3.0, 0.0, 0.0)
    core.start(Drive())
    with pytest.raises(MappingRefused, match="busy") as refused:
        core.enter_mapping()
    assert refused.value.code == ResultCode.CONFLICT and not core.mapping
    core.motion.halt(reason="test")
    core.enter_mapping()
    assert core.mapping and loc.pose() is None  # until the SLAM node's transform arrives
    core.on_ground_truth(2, Pose2(9.0, 9.0, 0.0))  # the world's frame: ignored now
    core.on_slam_map_to_odom(Pose2(-1.0, 0.5, 0.0))
    assert loc.pose() == Pose2(0.0, 0.5, 0.0)
    assert not core.costmaps.ready
    core.on_slam_map(built_grid())
    assert core.costmaps.ready and core.cost_at(0.0, 0.6) < 253 and core.cost_at(-1.2, 0.0) == 254
    grown = GridMap(np.zeros((80, 100), dtype=np.int8), 0.05, (-3.0, -2.0, 0.0))
    core.on_slam_map(grown)  # origin and size change
    assert core.cost_at(-2.5, -1.5) == 0
    core.saver.handle_save_grid(SaveGridRequest(
        name="site2", grid=built_grid().to_msg(), map_to_odom=Pose2D(x=-1.0, y=0.5),
        use_map_to_odom=True))
    with pytest.raises(MappingRefused, match="unknown map") as refused:
        core.leave_mapping("nope")
    assert refused.value.code == ResultCode.NOT_FOUND and core.mapping
    core.leave_mapping("site2", Pose2(-1.1, 0.5, 0.0))
    assert not core.mapping and core.maps.current == "site2" and core.built
    assert loc.mode == "scan_match"  # a built map: never the truth
    p = loc.pose()
    assert p is not None and math.isclose(p.x, -0.1) and p.y == 0.5 and loc.relocalize
    core.leave_mapping("office")  # back on the world's map: the parameter's mode
    assert loc.mode == "ground_truth" and not core.built


def test_a_built_map_starts_from_its_recorded_map_to_odom(core: NavCore) -> None:
    core.saver.handle_save_grid(SaveGridRequest(
        name="site2", grid=built_grid().to_msg(), map_to_odom=Pose2D(x=0.25, theta=math.pi / 2),
        use_map_to_odom=True))
    core.on_odom(1, Pose2(1.0, 0.0, 0.0), 0.0, 0.0)
    core.maps.switch("site2")
    p = core.localizer.pose()
    assert p is not None and math.isclose(p.x, 0.25, abs_tol=1e-9) \
        and math.isclose(p.y, 1.0) and core.localizer.mode == "scan_match"
    core.set_localization("odometry")
    assert core.localizer.mode == "odometry"
    core.set_localization("ground_truth")
    assert core.localizer.mode == "scan_match"
    with pytest.raises(ValueError, match="unknown localization mode"):
        core.set_localization("gps")


def test_a_record_that_is_not_a_record_is_a_map_error(core: NavCore) -> None:
    core.saver.handle_save_grid(SaveGridRequest(name="site2", grid=built_grid().to_msg()))
    (core.maps.store.folder("site2") / RECORD_FILE).write_text("type: [1, 2]\n")
    with pytest.raises(ValueError, match=RECORD_FILE):
        core.maps.store.record("site2")
    core.maps.switch("site2")  # still loads, as an imported map would
    assert not core.built
    assert MapRecord().type == "floor"
