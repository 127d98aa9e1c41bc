"""The robot API's schedule server map exchange (docs/robot-api.md §6.3 ``upload_map``,
``download_map``) over real Zenoh: the gateway starts a task, the tasks service exports the current map from nav and
puts it on the schedule server, and gets one back into nav's maps (paths and nav points
with it); and what goes wrong is said (an unknown server or map, an archive that is not a
map, a malformed id, a task already running)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from sim_robot import GatewayRobot, gateway_robot
from zenros.msgs import zenros_msgs as zm
from zenros.msgs.zenros_msgs.result import ResultCode
from zenros.services.schedule.node import ScheduleServerNode
from zenros.testing import wait_for

pytestmark = pytest.mark.xdist_group("schedule_maps")

POINTS = "2 0 0 0 0.1 0.1 0 first\n4 0 0 1.57 0.1 0.1 0 second\n"


class Rig:
    def __init__(self, robot: GatewayRobot, server: ScheduleServerNode) -> None:
        self.robot, self.server, self.http = robot, server, robot.http
        self.map = robot.nav.core.maps.current

    def task_ends(self, task: dict[str, Any]) -> dict[str, Any]:
        """The task's document once it ended (COMPLETE, ERROR...)."""
        done: dict[str, Any] = {}

        def ended() -> bool:
            doc = self.http.get("/task", params={"id": task["id"]}).json()
            done.update(doc)
            return doc["state"] not in ("WAITTING", "WORKING", "PAUSED")

        assert wait_for(ended, 60), done
        return done


@pytest.fixture(scope="module")
def rig(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Rig]:
    tmp: Path = tmp_path_factory.mktemp("schedule")
    with gateway_robot(tmp) as robot:
        server = ScheduleServerNode(context=robot.contexts[-1], parameter_overrides={
            "data_dir": str(tmp / "shelf")})
        try:
            robot.add_nav_points(robot.nav.core.maps.current, "p1", POINTS)
            assert robot.gw.graph.wait_for_service("/schedule/local/put_map", 10)
            yield Rig(robot, server)
        finally:
            server.close()


def test_upload_then_download_brings_the_nav_points_back(rig: Rig) -> None:
    r = rig.http.get("/navigation/upload_map", params={"server_id": "local"})
    assert r.status_code == 200, r.text
    task = r.json()
    assert task["sub_tasks"][0]["type"] == "upload_map_action"
    done = rig.task_ends(task)
    assert done["state"] == "COMPLETE", done
    (kept,) = rig.server.shelf.list()
    assert kept.name == rig.map and kept.width > 0 and kept.md5sum
    assert kept.map_id in done["sub_tasks"][0]["result"]
    # the map's nav points go; the archive brings them back
    r = rig.http.delete("/navigation/nav_points", params={"map_name": rig.map,
                                                          "path_name": "p1"})
    assert r.status_code == 200, r.text
    gone = rig.http.get("/navigation/nav_points", params={"map_name": rig.map,
                                                         "path_name": "p1"}).json()
    assert not gone["path_data"].strip(), gone
    r = rig.http.get("/navigation/download_map", params={"server_id": "local",
                                                         "map_id": kept.map_id})
    assert r.status_code == 200, r.text
    done = rig.task_ends(r.json())
    assert done["state"] == "COMPLETE", done
    assert "1 path(s)" in done["sub_tasks"][0]["result"]
    points = rig.http.get("/navigation/nav_points", params={"map_name": rig.map,
                                                            "path_name": "p1"}).json()
    assert [ln.split()[-1] for ln in points["path_data"].splitlines()] == ["first", "second"]


def test_what_goes_wrong_is_said(rig: Rig) -> None:
    r = rig.http.get("/navigation/upload_map", params={"server_id": "nowhere"})
    done = rig.task_ends(r.json())
    assert done["state"] == "ERROR" and "schedule server 'nowhere'" in \
        done["sub_tasks"][0]["result"], done
    r = rig.http.get("/navigation/download_map", params={"server_id": "local",
                                                         "map_id": "0" * 32})
    done = rig.task_ends(r.json())
    assert done["state"] == "ERROR" and "no map" in done["sub_tasks"][0]["result"], done
    for params in ({"server_id": "local", "map_id": "../etc"}, {"server_id": "a/b"},
                   {"server_id": "local", "map_id": "A" * 32}):
        path = "/navigation/download_map" if "map_id" in params else "/navigation/upload_map"
        assert rig.http.get(path, params=params).status_code == 400, params


def test_the_server_refuses_what_is_not_a_map_and_keeps_nothing(rig: Rig) -> None:
    before = len(rig.server.shelf.list())
    put = rig.robot.user.create_client(zm.PutMapArchive, "/schedule/local/put_map")
    res = put.call(zm.PutMapArchiveRequest(data=b"PK\x03\x04 not a zip"), timeout=10)
    assert res.code == ResultCode.INVALID and "not a map archive" in res.message
    get = rig.robot.user.create_client(zm.GetMapArchive, "/schedule/local/get_map")
    res2 = get.call(zm.GetMapArchiveRequest(map_id="../../index"), timeout=10)
    assert res2.code == ResultCode.NOT_FOUND and not res2.data
    assert len(rig.server.shelf.list()) == before
