"""A building in nav's map store: its floors, hall points and elevator connections, installed
once however often nav starts, and a route to another floor through the car."""

from __future__ import annotations

from pathlib import Path

from zenros.building import ELEVATOR_PATH, elevator_of_path, load_building
from zenros.maps.maproute import find_route, links_of
from zenros.msgs.zenros_msgs.nav import ListPointConnectionsRequest
from zenros.services.nav.maps.building_maps import install_building
from zenros.services.nav.maps.connections import Connections
from zenros.services.nav.maps.store import MapStore

TOWER = Path(__file__).parents[3] / "deploy" / "buildings" / "tower" / "tower.yaml"


def test_floors_hall_points_and_connections_once(tmp_path: Path) -> None:
    b = load_building(TOWER)
    store = MapStore(tmp_path / "maps")
    conn = Connections(store)
    assert install_building(store, conn, b) == 3  # 1-2, 1-3, 2-3
    assert install_building(store, conn, b) == 0  # a restart adds nothing
    assert {"floor1", "floor2", "floor3"} <= set(store.names())
    hall = b.elevator().hall_pose(2)
    (p,) = store.nav_data("floor2").paths[ELEVATOR_PATH + "lift1"].nav_points
    assert (p.x, p.y, p.theta) == (hall.x, hall.y, hall.theta)
    assert elevator_of_path(ELEVATOR_PATH + "lift1") == "lift1"
    assert elevator_of_path("p1") is None
    listed = conn.handle_list(ListPointConnectionsRequest())
    (hop,) = find_route(links_of(listed.points, listed.connections), "floor1", "floor3")
    assert hop.type == "elevator"
    assert (hop.leave.map, hop.enter.map) == ("floor1", "floor3")
    assert hop.leave.path == ELEVATOR_PATH + "lift1"
