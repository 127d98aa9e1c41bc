"""A building's floors in nav's map store (docs/building.md, "Navigation"): each floor's map
imported under its name, each elevator's hall point as the one nav point of a path
``elevator_<name>`` on every floor it serves, and an ``elevator`` point connection between
every two of those points, so that a goal on another floor finds its route through the car
(`zenros.maps.maproute`). Idempotent: a restart finds everything in place and adds nothing.
"""

from __future__ import annotations

from zenros.building import ELEVATOR_PATH, Building, Elevator
from zenros.msgs.zenros_msgs.nav import (
    AddPointConnectionRequest,
    NavPoint,
    PointConnection,
    PointRef,
)

from .connections import Connections
from .navdata import MapNavData, StoredPath
from .store import MapStore

__all__ = ["install_building"]


def install_building(store: MapStore, connections: Connections, building: Building) -> int:
    """Put ``building``'s floors, hall points and elevator connections in the store; returns
    how many connections it added."""
    for f in building.floors:
        store.import_map(f.map)
    added = 0
    for e in building.elevators:
        for lv in e.levels:
            _hall_point(store, e, lv, building.floor(lv).map_name)
        refs = [PointRef(map_name=building.floor(lv).map_name,
                         path_name=ELEVATOR_PATH + e.name, index=0) for lv in e.levels]
        for i, a in enumerate(refs):
            for b in refs[i + 1:]:
                if not _joined(connections.all(), a, b):
                    connections.handle_add(AddPointConnectionRequest(
                        points=[a, b], type=PointConnection.ELEVATOR, is_available=True))
                    added += 1
    return added


def _hall_point(store: MapStore, e: Elevator, level: int, map_name: str) -> None:
    hall = e.hall_pose(level)
    point = NavPoint(name=f"{e.name} hall, level {level}", x=hall.x, y=hall.y,
                     theta=hall.theta)

    def change(data: MapNavData) -> None:
        path = data.paths.get(ELEVATOR_PATH + e.name)
        if path is None or path.nav_points != [point]:
            data.paths[ELEVATOR_PATH + e.name] = StoredPath(nav_points=[point])

    store.update_nav_data(map_name, change)


def _joined(items: list[PointConnection], a: PointRef, b: PointRef) -> bool:
    return any({(p.map_name, p.path_name, p.index) for p in c.points}
               == {(a.map_name, a.path_name, a.index), (b.map_name, b.path_name, b.index)}
               for c in items)
