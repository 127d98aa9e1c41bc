"""Connections: point connections between maps, checked against the map store, on disk."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from zenros.errors import MapError
from zenros.msgs.zenros_msgs.nav import (
    AddPointConnectionRequest,
    DeletePointConnectionRequest,
    ListPointConnectionsRequest,
    NavPoint,
    PointRef,
)
from zenros.services.nav.maps.connections import CONNECTIONS_FILE, Connections
from zenros.services.nav.maps.navdata import StoredPath
from zenros.services.nav.maps.store import MapStore
from zenros.services.nav.params import DEMO_MAP


@pytest.fixture
def store(tmp_path: Path) -> MapStore:
    s = MapStore(tmp_path / "maps")
    for name in ("office", "office2"):
        s.import_map(DEMO_MAP, name)
        s.update_nav_data(name, lambda d: d.paths.__setitem__("p1", StoredPath(nav_points=[
            NavPoint(x=1.0, y=0.0, name="a"), NavPoint(x=2.0, y=0.5, theta=1.0)])))
    return s


def ref(m: str, i: int, path: str = "p1") -> PointRef:
    return PointRef(map_name=m, path_name=path, index=i)


def add(c: Connections, a: PointRef, b: PointRef, kind: str = "direct") -> str:
    req = AddPointConnectionRequest(points=[a, b], type=kind, is_available=True)
    return c.handle_add(req).connection.id


def test_add_list_delete_persist(store: MapStore) -> None:
    c = Connections(store)
    res = c.handle_add(AddPointConnectionRequest(points=[ref("office", 1), ref("office2", 1)],
                                                 type="elevator", is_available=False))
    conn = res.connection
    assert re.fullmatch(r"[0-9a-f-]{36}", conn.id) and re.fullmatch(r"[0-9a-f]{24}", conn.oid)
    assert conn.type == "elevator" and not conn.is_available
    listing = c.handle_list(ListPointConnectionsRequest())
    assert [(p.map_name, p.path_name, p.index, p.name) for p in listing.points] == [
        ("office", "p1", 0, "a"), ("office", "p1", 1, ""),
        ("office2", "p1", 0, "a"), ("office2", "p1", 1, "")]
    assert listing.points[1].theta == 1.0
    assert listing.connections == [conn]
    again = Connections(store)  # read back from connections.yaml
    assert again.all() == [conn]
    again.handle_delete(DeletePointConnectionRequest(id=conn.id))
    assert Connections(store).all() == []


@pytest.mark.parametrize(("a", "b", "kind", "message"), [
    (ref("nowhere", 0), ref("office2", 0), "direct", "unknown map 'nowhere'"),
    (ref("office", 0, "p9"), ref("office2", 0), "direct", "unknown path 'p9'"),
    (ref("office", 2), ref("office2", 0), "direct", "unknown nav point 2"),
    (ref("office", 0), ref("office", 0), "direct", "twice"),
    (ref("office", 0), ref("office2", 0), "teleport", "invalid connection type"),
])
def test_bad_connections_are_refused(store: MapStore, a: PointRef, b: PointRef, kind: str,
                                     message: str) -> None:
    c = Connections(store)
    with pytest.raises((MapError, ValueError), match=message):
        add(c, a, b, kind)
    assert c.all() == []


def test_one_connection_per_pair_and_unknown_id(store: MapStore) -> None:
    c = Connections(store)
    first = add(c, ref("office", 0), ref("office2", 0))
    with pytest.raises(ValueError, match=f"already connected.*{first}"):
        add(c, ref("office2", 0), ref("office", 0))
    with pytest.raises(ValueError, match="exactly 2 points"):
        c.handle_add(AddPointConnectionRequest(points=[ref("office", 0)]))
    with pytest.raises(MapError, match="unknown connection id 'nope'"):
        c.handle_delete(DeletePointConnectionRequest(id="nope"))


def test_a_malformed_file_is_named_not_fatal(store: MapStore) -> None:
    (store.root / CONNECTIONS_FILE).write_text("connections: 7\n")
    c = Connections(store)
    with pytest.raises(MapError, match=CONNECTIONS_FILE):
        c.handle_list(ListPointConnectionsRequest())
    with pytest.raises(MapError, match=CONNECTIONS_FILE):
        add(c, ref("office", 0), ref("office2", 0))
