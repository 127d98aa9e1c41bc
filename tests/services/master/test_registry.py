"""The registry: system state from tokens, flap tolerance, duplicate names, type conflicts."""

from __future__ import annotations

from zenros.names import Token
from zenros.services.master.registry import Eviction, Registry, TypeConflict


def node(name: str, start: int, zid: str = "z1", pid: int = 10) -> Token:
    return Token("node", name, zid=zid, host="h", pid=pid, start_ns=start)


def ep(kind: str, node_name: str, name: str, type_name: str, eid: str = "1") -> Token:
    return Token(kind, node_name, name, type_name, "", "z1", eid)


def build() -> Registry:
    r = Registry(grace=1.0)
    for tok in (
        node("/teleop", 1), node("/robot1/chassis", 2),
        ep("pub", "/teleop", "/robot1/cmd_vel", "geometry_msgs/Twist"),
        ep("sub", "/robot1/chassis", "/robot1/cmd_vel", "geometry_msgs/Twist", "2"),
        ep("pub", "/robot1/chassis", "/robot1/odom", "nav_msgs/Odometry", "3"),
        ep("srv", "/robot1/chassis", "/robot1/reset", "std_srvs/Empty", "4"),
        ep("act", "/nav", "/nav/navigate_to_pose", "nav2_msgs/NavigateToPose", "5"),
    ):
        assert r.put(tok, 0.0) == []
    return r


def test_system_state_views() -> None:
    r = build()
    assert [t.node for t in r.nodes()] == ["/robot1/chassis", "/teleop"]
    topics = {t.name: t for t in r.topics()}
    assert topics["/robot1/cmd_vel"].publishers == ["/teleop"]
    assert topics["/robot1/cmd_vel"].subscribers == ["/robot1/chassis"]
    assert topics["/robot1/cmd_vel"].types == ["geometry_msgs/Twist"]
    assert [(s.name, s.servers, s.types) for s in r.services()] == [
        ("/robot1/reset", ["/robot1/chassis"], ["std_srvs/Empty"])]
    assert [a.name for a in r.actions()] == ["/nav/navigate_to_pose"]
    assert r.topic_types() == {"/robot1/cmd_vel": ["geometry_msgs/Twist"],
                               "/robot1/odom": ["nav_msgs/Odometry"]}
    assert r.published_topics("/robot1") == r.topic_types()
    assert r.published_topics("/other") == {}
    found = r.lookup_node("/teleop")
    assert found is not None and found.pid == 10
    assert r.lookup_node("/nobody") is None


def test_a_flap_changes_nothing() -> None:
    r = build()
    tok = node("/teleop", 1)
    r.delete(tok, 10.0)
    assert r.expire(10.5) == []
    assert r.put(tok, 10.6) == []  # back within the grace period
    assert r.expire(20.0) == []
    assert [t.node for t in r.nodes()] == ["/robot1/chassis", "/teleop"]


def test_a_deletion_applies_after_the_grace_period() -> None:
    r = build()
    r.delete(ep("pub", "/teleop", "/robot1/cmd_vel", "geometry_msgs/Twist"), 10.0)
    r.delete(node("/teleop", 1), 10.0)
    assert "/teleop" in [t.node for t in r.nodes()]  # still shown: it may come back
    assert len(r.expire(11.0)) == 2
    assert [t.node for t in r.nodes()] == ["/robot1/chassis"]
    assert r.topics()[0].publishers == []


def test_the_newer_node_wins_whatever_the_arrival_order() -> None:
    for order in ((1, 2), (2, 1)):
        r = Registry()
        notices = [n for start in order for n in r.put(node("/twin", start, f"z{start}"), 0.0)]
        assert notices == [Eviction(node("/twin", 1, "z1"), node("/twin", 2, "z2"))]
        assert r.evictions() == notices
        found = r.lookup_node("/twin")
        assert found is not None and found.start_ns == 2


def test_an_eviction_is_reported_once_even_across_flaps() -> None:
    r = Registry(grace=1.0)
    old, new = node("/twin", 1, "z1"), node("/twin", 2, "z2")
    r.put(old, 0.0)
    assert len(r.put(new, 0.0)) == 1
    r.delete(old, 1.0)
    assert r.put(old, 1.2) == []
    r.delete(old, 2.0)
    r.expire(5.0)
    assert r.evictions() == []


def test_a_restarted_node_does_not_evict_its_dead_predecessor() -> None:
    r = Registry(grace=1.0)
    old, new = node("/talker", 1, "z1"), node("/talker", 2, "z2")
    r.put(old, 0.0)
    r.delete(old, 5.0)  # killed; its deletion is within the grace period
    assert r.put(new, 5.1) == []


def test_type_conflicts_are_reported_once_and_cleared() -> None:
    r = Registry(grace=0.0)
    a = ep("pub", "/a", "/cmd", "geometry_msgs/Twist")
    b = ep("sub", "/b", "/cmd", "std_msgs/String", "2")
    r.put(a, 0.0)
    assert r.put(b, 0.0) == [TypeConflict("/cmd", ("geometry_msgs/Twist", "std_msgs/String"))]
    assert r.put(ep("sub", "/c", "/cmd", "std_msgs/String", "3"), 0.0) == []
    assert r.type_conflicts() == {"/cmd": ["geometry_msgs/Twist", "std_msgs/String"]}
    r.delete(b, 1.0)
    r.delete(ep("sub", "/c", "/cmd", "std_msgs/String", "3"), 1.0)
    r.expire(1.0)
    assert r.type_conflicts() == {}
    assert len(r.put(b, 2.0)) == 1
