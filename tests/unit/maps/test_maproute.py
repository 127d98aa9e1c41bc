"""find_route: Dijkstra over maps joined by point connections."""

from __future__ import annotations

import pytest
from zenros.maps.maproute import Link, NoRoute, PointEnd, find_route, links_of


def link(ident: str, a: str, b: str, kind: str = "direct", available: bool = True) -> Link:
    return Link(ident, kind, available, PointEnd(a, "p", 0), PointEnd(b, "p", 1))


def maps_of(route: list) -> list[str]:
    return [route[0].leave.map, *(h.enter.map for h in route)] if route else []


def test_same_map_needs_no_hop() -> None:
    assert find_route([link("1", "a", "b")], "a", "a") == []


def test_direct_hop_either_way() -> None:
    (hop,) = find_route([link("1", "a", "b")], "b", "a")
    assert hop.id == "1" and hop.leave == PointEnd("b", "p", 1)
    assert hop.enter == PointEnd("a", "p", 0)
    assert hop.describe() == "direct connection 1 (b/p[1] -> a/p[0])"


def test_several_maps_fewest_hops() -> None:
    links = [link("1", "a", "b"), link("2", "b", "c"), link("3", "c", "d"),
             link("4", "a", "x"), link("5", "x", "d"), link("6", "q", "r")]
    route = find_route(links, "a", "d")
    assert [h.id for h in route] == ["4", "5"] and maps_of(route) == ["a", "x", "d"]


def test_elevator_only_when_no_direct_route() -> None:
    links = [link("e", "a", "d", "elevator"), link("1", "a", "b"), link("2", "b", "c"),
             link("3", "c", "d")]
    assert [h.id for h in find_route(links, "a", "d")] == ["1", "2", "3"]
    assert [h.id for h in find_route(links[:1], "a", "d")] == ["e"]


def test_unavailable_and_same_map_links_are_skipped() -> None:
    links = [link("1", "a", "b", available=False), link("2", "a", "a"), link("3", "b", "c")]
    with pytest.raises(NoRoute, match=r"no route from map 'a' to map 'b'.*1 unavailable"):
        find_route(links, "a", "b")
    with pytest.raises(NoRoute, match="no route from map 'a' to map 'z'"):
        find_route(links, "a", "z")


def test_ties_go_to_the_first_stored_connection() -> None:
    links = [link("first", "a", "b"), link("second", "a", "b")]
    assert [h.id for h in find_route(links, "a", "b")] == ["first"]


def test_links_of_marks_connections_to_missing_points_unavailable() -> None:
    from types import SimpleNamespace as NS

    def pt(m: str, i: int) -> NS:
        return NS(map_name=m, path_name="p", index=i)
    points = [pt("a", 0), pt("b", 0)]
    conns = [NS(id="ok", type="direct", is_available=True, points=[pt("a", 0), pt("b", 0)]),
             NS(id="gone", type="direct", is_available=True, points=[pt("a", 0), pt("b", 7)]),
             NS(id="off", type="elevator", is_available=False,
                points=[pt("a", 0), pt("b", 0)]),
             NS(id="odd", type="direct", is_available=True, points=[pt("a", 0)])]
    assert [(x.id, x.available) for x in links_of(points, conns)] == [
        ("ok", True), ("gone", False), ("off", False)]
