"""The parameter store: operations, subtree semantics, search, durability, replica merge, YAML."""

from __future__ import annotations

import copy
import logging
import random
import signal
import subprocess
import sys
import textwrap
from pathlib import Path
from typing import Any

import msgspec
import pytest
from zenros.errors import (
    InvalidNameError,
    InvalidParameterValueError,
    ParameterError,
    ParameterNotFoundError,
)
from zenros.services.master.param_store import ParamStore
from zenros.services.master.param_tree import (
    Change,
    Entry,
    ParamTree,
    Stamp,
    decode_entries,
    encode_entries,
)
from zenros.services.master.param_value import resolve_param_name


@pytest.fixture
def store(tmp_path: Path) -> Any:
    with ParamStore(tmp_path / "params.db", source="a") as s:
        yield s


RICH = {
    "flag": True,
    "off": False,
    "count": 3,
    "zero": 0,
    "big": 2**63 + 5,
    "neg": -(2**63),
    "ratio": 0.5,
    "whole": 2.0,
    "name": "base_link",
    "numeric_str": "1",
    "blob": b"\x00\xff\x10",
    "mixed": [1, 2.5, "x", True, b"\x01", [1, [2]], {"k": [True]}],
    "empty_list": [],
    "empty_ns": {},
    "nested": {"a": {"b": {"c": 1}}, "d": [0.1, 0.2]},
}


def typed(value: Any) -> bytes:
    """An encoding that tells bool from int and list from tuple, with sorted dict keys."""
    return msgspec.msgpack.Encoder(order="deterministic").encode(value)


# ------------------------------------------------------------------ basic operations


def test_leaf_values_keep_their_types(store: ParamStore, tmp_path: Path) -> None:
    for key, value in RICH.items():
        store.set(f"/t/{key}", value)
    for key, value in RICH.items():
        got = store.get(f"/t/{key}")
        assert typed(got) == typed(value), key
    assert store.get("/t/flag") is True and store.get("/t/count") == 3
    assert type(store.get("/t/count")) is int and type(store.get("/t/whole")) is float
    assert type(store.get("/t/blob")) is bytes
    store.close()
    with ParamStore(tmp_path / "params.db") as again:
        assert typed(again.get("/t")) == typed(RICH)
        assert again.source == "a"


def test_get_namespace_returns_the_subtree(store: ParamStore) -> None:
    store.set("/nav/max_speed", 1.5)
    store.set("/nav/costmap/inflation", 0.3)
    store.set("/chassis/wheel_base", 0.3)
    assert store.get("/nav") == {"max_speed": 1.5, "costmap": {"inflation": 0.3}}
    assert store.get("/nav/costmap") == {"inflation": 0.3}
    assert store.get("/") == {
        "chassis": {"wheel_base": 0.3},
        "nav": {"costmap": {"inflation": 0.3}, "max_speed": 1.5},
    }


def test_returned_values_are_copies(store: ParamStore) -> None:
    store.set("/a", {"l": [1, 2]})
    got = store.get("/a")
    got["l"].append(3)
    assert store.get("/a/l") == [1, 2]


def test_set_dict_replaces_the_subtree(store: ParamStore) -> None:
    store.set("/nav", {"a": 1, "b": {"c": 2}})
    store.set("/nav", {"x": 1})
    assert store.get("/nav") == {"x": 1}
    assert not store.has("/nav/a") and not store.has("/nav/b/c")


def test_setting_a_leaf_on_a_namespace_replaces_it(store: ParamStore) -> None:
    store.set("/nav/a", 1)
    store.set("/nav/b/c", 2)
    store.set("/nav", 5)
    assert store.get("/nav") == 5
    assert store.names() == ["/nav"]


def test_setting_below_a_leaf_turns_it_into_a_namespace(store: ParamStore) -> None:
    store.set("/nav", 5)
    store.set("/nav/speed", 1.0)
    assert store.get("/nav") == {"speed": 1.0}
    assert store.names() == ["/nav/speed"]


def test_empty_dict_is_an_empty_namespace(store: ParamStore) -> None:
    store.set("/ns", {})
    assert store.has("/ns") and store.get("/ns") == {}
    store.set("/ns/x", 1)
    assert store.get("/ns") == {"x": 1}
    store.set("/", {"only": {}})
    assert store.get("/") == {"only": {}}


def test_root_can_only_be_set_to_a_dict(store: ParamStore) -> None:
    with pytest.raises(InvalidParameterValueError, match="root namespace"):
        store.set("/", 1)
    store.set("/a", 1)
    store.set("/", {"b": 2})
    assert store.get("/") == {"b": 2}


def test_delete_leaf_and_subtree(store: ParamStore) -> None:
    store.set("/nav", {"a": 1, "b": {"c": 2, "d": 3}})
    store.delete("/nav/a")
    assert store.get("/nav") == {"b": {"c": 2, "d": 3}}
    store.delete("/nav/b")
    assert not store.has("/nav")
    with pytest.raises(ParameterNotFoundError):
        store.get("/nav")
    with pytest.raises(ParameterNotFoundError):
        store.delete("/nav")


def test_missing_parameter_error_is_helpful(store: ParamStore) -> None:
    store.set("/nav/max_speed", 1.0)
    store.set("/nav/min_speed", 0.1)
    with pytest.raises(ParameterNotFoundError) as info:
        store.get("/nav/max_sped")
    assert isinstance(info.value, LookupError) and isinstance(info.value, ParameterError)
    assert "/nav/max_sped is not set" in str(info.value)
    assert "max_speed, min_speed" in str(info.value)
    assert store.get("/") == {"nav": {"max_speed": 1.0, "min_speed": 0.1}}


def test_has_and_names(store: ParamStore) -> None:
    store.set("/a/b/c", 1)
    store.set("/a/bb", 2)
    store.set("/ab", 3)
    assert store.has("/a") and store.has("/a/b") and store.has("/a/b/c")
    assert not store.has("/a/b/c/d") and not store.has("/b") and not store.has("/a/c")
    assert store.names() == ["/a/b/c", "/a/bb", "/ab"]
    assert store.names("/a") == ["/a/b/c", "/a/bb"]
    assert store.names("/a/b") == ["/a/b/c"]
    assert store.names("/a/b/c") == ["/a/b/c"]
    assert store.names("/zz") == []


def test_names_and_values_are_validated(store: ParamStore) -> None:
    with pytest.raises(InvalidNameError):
        store.set("relative", 1)
    with pytest.raises(InvalidNameError, match="'__' is reserved"):
        store.set("/a__b", 1)
    with pytest.raises(InvalidNameError, match="segment 'bad key'"):
        store.set("/a", {"bad key": 1})
    with pytest.raises(InvalidParameterValueError, match="null"):
        store.set("/a", None)
    with pytest.raises(InvalidParameterValueError, match="unsupported value set"):
        store.set("/a", {1, 2})
    with pytest.raises(InvalidParameterValueError, match="64 bits"):
        store.set("/a", 2**64)
    with pytest.raises(InvalidParameterValueError, match="dict keys must be str"):
        store.set("/a", [{1: 2}])
    assert store.names() == []


# ------------------------------------------------------------------ names and search


def test_resolve_param_name() -> None:
    assert resolve_param_name("~x", node="/robot1/nav") == "/robot1/nav/x"
    assert resolve_param_name("~/x/y", node="/robot1/nav") == "/robot1/nav/x/y"
    assert resolve_param_name("x", node="/robot1/nav") == "/robot1/x"
    assert resolve_param_name("x", node="/robot1/nav", namespace="/other") == "/other/x"
    assert resolve_param_name("/g", node="/robot1/nav") == "/g"
    assert resolve_param_name("x") == "/x"
    with pytest.raises(InvalidNameError, match="needs a node"):
        resolve_param_name("~x")


def test_search_follows_ros_search_param(store: ParamStore) -> None:
    # The example of the ROS 1 parameter server API documentation.
    store.set("/robot_description", "top")
    store.set("/robot_description/arm", "a")
    store.set("/robot_description/base", "b")
    store.set("/pr2/robot_description", "pr2")
    store.set("/pr2/robot_description/base", "b")
    assert store.search("/pr2/foo", "robot_description") == "/pr2/robot_description"
    assert store.search("/pr2/foo", "robot_description/arm") == "/pr2/robot_description/arm"
    assert store.search("/other/foo", "robot_description/arm") == "/robot_description/arm"
    assert store.search("/", "robot_description") == "/robot_description"
    assert store.search("/pr2/foo", "missing") is None


def test_search_checks_the_callers_private_namespace_first(store: ParamStore) -> None:
    store.set("/speed", 1)
    store.set("/ns/speed", 2)
    store.set("/ns/node/speed", 3)
    assert store.search("/ns/node", "speed") == "/ns/node/speed"
    assert store.search("/ns/other", "speed") == "/ns/speed"
    assert store.search("/x/y/z", "speed") == "/speed"


@pytest.mark.parametrize("key", ["", "/abs", "~priv"])
def test_search_rejects_global_and_private_keys(store: ParamStore, key: str) -> None:
    with pytest.raises(InvalidNameError, match="relative name"):
        store.search("/ns", key)


# ------------------------------------------------------------------ listeners


def test_listeners_see_leaf_changes_after_commit(store: ParamStore) -> None:
    seen: list[Change] = []
    committed: list[list[Entry]] = []
    remove = store.add_listener(seen.append)
    store.add_entry_listener(lambda rows: committed.append(list(rows)))
    store.set("/a", {"x": 1, "y": 2})
    assert [(c.name, c.value, c.deleted) for c in seen] == [("/a/x", 1, False), ("/a/y", 2, False)]
    seen.clear()
    stamp = store.set("/a", 5)
    # deletions come first, so a mirror never holds a leaf and a namespace at once
    assert [(c.name, c.deleted) for c in seen] == [("/a/x", True), ("/a/y", True), ("/a", False)]
    assert all(c.stamp == stamp for c in seen)
    assert [e.name for e in committed[-1]] == ["/a"]
    seen.clear()
    store.set("/a", 5, stamp)  # the same write again changes nothing
    assert seen == []
    remove()
    store.set("/b", 1)
    assert seen == []
    assert [e.name for e in committed[-1]] == ["/b"]


def test_failing_listener_does_not_undo_the_write(
    store: ParamStore, caplog: pytest.LogCaptureFixture
) -> None:
    def boom(change: Change) -> None:
        raise RuntimeError("listener bug")

    store.add_listener(boom)
    with caplog.at_level(logging.ERROR):
        store.set("/a", 1)
    assert store.get("/a") == 1
    assert "listener" in caplog.text and "listener bug" in caplog.text


def test_listener_may_read_the_store(store: ParamStore) -> None:
    reads: list[Any] = []
    store.add_listener(lambda c: reads.append(store.get("/")))
    store.set("/a", 1)
    assert reads == [{"a": 1}]


# ------------------------------------------------------------------ tombstones and stamps


def test_delete_keeps_a_tombstone(store: ParamStore) -> None:
    store.set("/a/b", 1)
    stamp = store.delete("/a")
    rows = {e.name: e for e in store.entries()}
    assert rows["/a"].deleted and rows["/a"].stamp == stamp and rows["/a"].value is None
    assert not rows["/a/b"].deleted  # hidden by the newer tombstone above it


def test_local_stamps_increase_and_follow_merged_ones(store: ParamStore) -> None:
    s1 = store.set("/a", 1)
    s2 = store.set("/a", 2)
    assert s2 > s1 and s1.source == "a"
    future = Stamp(s2.time + 10**15, "z")
    store.merge([Entry("/b", future.time, future.source, False, 1)])
    s3 = store.set("/b", 2)
    assert s3 > future and store.get("/b") == 2


def test_an_older_write_loses(store: ParamStore) -> None:
    new = store.set("/a", "new")
    store.set("/a", "old", Stamp(new.time - 1, "a"))
    assert store.get("/a") == "new"


def test_changes_since(store: ParamStore) -> None:
    s1 = store.set("/a", 1)
    store.set("/b", 2)
    store.delete("/a")
    assert [(e.name, e.deleted) for e in store.changes_since(s1)] == [("/b", False), ("/a", True)]
    assert len(store.changes_since(Stamp(0, ""))) == 2


def test_entries_round_trip_on_the_wire(store: ParamStore) -> None:
    store.set("/t", RICH)
    store.delete("/t/flag")
    rows = store.entries()
    assert decode_entries(encode_entries(rows)) == rows


def test_merge_rejects_malformed_rows(store: ParamStore) -> None:
    with pytest.raises(InvalidNameError):
        store.merge([Entry("relative", 1, "x", False, 1)])
    with pytest.raises(ParameterError, match="NTP64"):
        store.merge([Entry("/a", 2**64, "x", False, 1)])
    with pytest.raises(InvalidParameterValueError):
        store.merge([Entry("/a", 1, "x", False, None)])
    assert store.entries() == []


# ------------------------------------------------------------------ replicas


def test_two_replicas_converge_after_a_partition(tmp_path: Path) -> None:
    with ParamStore(tmp_path / "a.db", source="a") as a, ParamStore(
        tmp_path / "b.db", source="b"
    ) as b:
        disconnect = a.add_entry_listener(b.merge)  # connected: a's commits reach b
        a.set("/nav", {"speed": 1.0, "accel": 0.5})
        assert b.get("/nav") == {"speed": 1.0, "accel": 0.5}
        disconnect()  # partition
        t_b = b.set("/nav/speed", 2.0)
        a.set("/nav/speed", 3.0, Stamp(t_b.time + 1000, "a"))  # a's write is the later one
        b.delete("/nav/accel")
        a.set("/chassis/wheel_base", 0.3)
        # heal: exchange everything, in both directions
        b.merge(a.entries())
        a.merge(b.entries())
        assert a.digest() == b.digest()
        assert a.get("/") == b.get("/") == {
            "chassis": {"wheel_base": 0.3},
            "nav": {"speed": 3.0},
        }


def test_merge_is_commutative_and_idempotent(tmp_path: Path) -> None:
    a, b = ParamTree(), ParamTree()
    rows_a = a.plan_set("/x", {"p": 1, "q": {"r": 2}}, Stamp(10, "a"))
    rows_b = b.plan_set("/x/q", 9, Stamp(11, "b")) + b.plan_set("/x/p", 3, Stamp(9, "b"))
    one = ParamStore(tmp_path / "1.db")
    two = ParamStore(tmp_path / "2.db")
    one.merge(rows_a)
    one.merge(rows_b)
    two.merge(rows_b)
    two.merge(rows_a)
    assert one.digest() == two.digest()
    assert one.get("/") == two.get("/") == {"x": {"p": 1, "q": 9}}
    assert one.merge(rows_a + rows_b) == []
    one.close()
    two.close()


@pytest.mark.parametrize(("b_time", "expected"), [(20, {"x": 1, "y": 2}), (5, {"x": 1})])
def test_subtree_replacement_against_a_concurrent_write(b_time: int, expected: Any) -> None:
    a, b = ParamTree(), ParamTree()
    rows_a = a.plan_set("/cfg", {"x": 1}, Stamp(10, "a"))
    rows_b = b.plan_set("/cfg/y", 2, Stamp(b_time, "b"))
    for first, second in ((rows_a, rows_b), (rows_b, rows_a)):
        tree = ParamTree()
        tree.apply(tree.winners(first))
        tree.apply(tree.winners(second))
        assert tree.get("/cfg") == expected


def test_equal_stamps_break_ties_by_content() -> None:
    rows = [Entry("/a", 5, "s", False, "x"), Entry("/a", 5, "s", False, "y")]
    t1, t2 = ParamTree(rows), ParamTree(rows[::-1])
    assert t1.get("/a") == t2.get("/a") == "y"
    assert t1.entries() == t2.entries()


def test_random_writes_match_ros_semantics(tmp_path: Path) -> None:
    rng = random.Random(7)
    model: dict[str, Any] = {}
    with ParamStore(tmp_path / "p.db") as store:
        for step in range(400):
            name = random_name(rng)
            if rng.random() < 0.2:
                if store.has(name):
                    store.delete(name)
                    model_delete(model, name)
                else:
                    with pytest.raises(ParameterNotFoundError):
                        store.delete(name)
            else:
                value = random_value(rng)
                store.set(name, value)
                model_set(model, name, value)
            assert typed(pruned(store.get("/"))) == typed(pruned(model)), step
            assert_no_leaf_above_a_leaf(store.names())
        view = store.get("/")
    with ParamStore(tmp_path / "p.db") as again:
        assert typed(again.get("/")) == typed(view)


def test_random_replicas_converge(tmp_path: Path) -> None:
    rng = random.Random(11)
    stores = [ParamStore(tmp_path / f"{i}.db", source=f"r{i}") for i in range(3)]
    try:
        for _ in range(300):
            s = rng.choice(stores)
            name = random_name(rng)
            if rng.random() < 0.2:
                if s.has(name):
                    s.delete(name)
            else:
                s.set(name, random_value(rng))
            if rng.random() < 0.1:  # an occasional partial sync
                src, dst = rng.sample(stores, 2)
                rows = src.entries()
                dst.merge(rng.sample(rows, len(rows) // 2))
        for dst in stores:
            for src in stores:
                if src is not dst:
                    rows = src.entries()
                    rng.shuffle(rows)
                    dst.merge(rows)
        assert len({s.digest() for s in stores}) == 1
        views = [typed(s.get("/")) for s in stores]
        assert views[0] == views[1] == views[2]
        assert all(s.merge(stores[0].entries()) == [] for s in stores)
        assert_no_leaf_above_a_leaf(stores[0].names())
    finally:
        for s in stores:
            s.close()


def random_name(rng: random.Random) -> str:
    return "/" + "/".join(rng.choice("abc") for _ in range(rng.randint(1, 3)))


def random_value(rng: random.Random) -> Any:
    roll = rng.random()
    if roll < 0.5:
        return rng.randint(0, 9)
    if roll < 0.6:
        return {}
    return {rng.choice("abc"): random_value(rng) for _ in range(rng.randint(1, 2))}


def model_set(tree: dict[str, Any], name: str, value: Any) -> None:
    """The ROS 1 parameter server's set: implicit namespaces replace leaves on the path."""
    *path, last = name.strip("/").split("/")
    for part in path:
        if not isinstance(tree.get(part), dict):
            tree[part] = {}
        tree = tree[part]
    tree[last] = copy.deepcopy(value)


def model_delete(tree: dict[str, Any], name: str) -> None:
    *path, last = name.strip("/").split("/")
    for part in path:
        tree = tree[part]
    del tree[last]


def pruned(value: Any) -> Any:
    """Drop empty namespaces (the store forgets them once their last leaf is gone)."""
    if not isinstance(value, dict):
        return value
    out = {k: pruned(v) for k, v in value.items()}
    return {k: v for k, v in out.items() if v != {}}


def assert_no_leaf_above_a_leaf(names: list[str]) -> None:
    for name in names:
        assert not any(other.startswith(name + "/") for other in names), name


# ------------------------------------------------------------------ YAML


def test_yaml_round_trip(store: ParamStore, tmp_path: Path) -> None:
    store.set("/nav", RICH)
    store.set("/top_flag", True)
    store.set("/robot1/chassis/wheel_base", 0.3)
    text = store.dump_yaml()
    assert "ros__parameters" in text
    with ParamStore(tmp_path / "other.db") as other:
        other.load_yaml(text)
        assert typed(other.get("/")) == typed(store.get("/"))


def test_yaml_dump_of_a_namespace_and_a_leaf(store: ParamStore) -> None:
    store.set("/nav", {"max_speed": 1.0, "costmap": {"inflation": 0.3}})
    assert store.dump_yaml("/nav") == textwrap.dedent(
        """\
        /nav:
          ros__parameters:
            costmap:
              inflation: 0.3
            max_speed: 1.0
        """
    )
    assert store.dump_yaml("/nav/max_speed") == "/nav:\n  ros__parameters:\n    max_speed: 1.0\n"
    with pytest.raises(ParameterNotFoundError):
        store.dump_yaml("/missing")


def test_load_ros2_layouts(store: ParamStore) -> None:
    text = textwrap.dedent(
        """\
        /nav:
          ros__parameters:
            max_speed: 0.5
            costmap.inflation: 0.3
            planner: {tolerance: 0.1}
        chassis:
          ros__parameters:
            wheel_base: 0.3
        robot1:
          tf:
            ros__parameters:
              buffer: 10.0
        /**:
          ros__parameters:
            use_sim_time: true
        """
    )
    names = store.load_yaml(text, source="sim.yaml")
    assert store.get("/") == {
        "nav": {"max_speed": 0.5, "costmap": {"inflation": 0.3}, "planner": {"tolerance": 0.1}},
        "chassis": {"wheel_base": 0.3},
        "robot1": {"tf": {"buffer": 10.0}},
        "use_sim_time": True,
    }
    assert "/nav/costmap/inflation" in names


def test_load_under_a_namespace_and_plain_layout(store: ParamStore) -> None:
    store.load_yaml("nav: {ros__parameters: {speed: 1}}\n/**: {ros__parameters: {g: 2}}", "/r1")
    store.load_yaml("a: 1\nb: {c: [1, 2]}\n", "/plain")
    assert store.get("/r1") == {"nav": {"speed": 1}, "g": 2}
    assert store.get("/plain") == {"a": 1, "b": {"c": [1, 2]}}


def test_load_merges_instead_of_replacing(store: ParamStore) -> None:
    store.set("/nav", {"keep": 1, "speed": 1, "ns": {"x": 1}})
    store.load_yaml("/nav: {ros__parameters: {speed: 2, ns: {}, new: 3}}")
    assert store.get("/nav") == {"keep": 1, "speed": 2, "ns": {"x": 1}, "new": 3}


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("a: [unclosed", "sim.yaml: not valid YAML"),
        ("- 1\n- 2\n", "sim.yaml: expected a mapping"),
        ("nav: {ros__parameters: {speed: null}}", r"sim.yaml: parameter /nav/speed: .*null"),
        ("/*/nav: {ros__parameters: {a: 1}}", "sim.yaml: node pattern"),
        ("nav: {ros__parameters: {a: 1}}\nchassis: {speed: 1}", "has no ros__parameters"),
        ("nav: {ros__parameters: {a: 1, a.b: 2}}", r"/nav/a is given both a value"),
        ("nav: {ros__parameters: {1bad: 2}}", "segment '1bad'"),
        ("nav: {ros__parameters: {when: 2024-01-01}}", "unsupported value date"),
    ],
)
def test_load_errors_name_the_file(store: ParamStore, text: str, match: str) -> None:
    with pytest.raises(ParameterError, match=match):
        store.load_yaml(text, source="sim.yaml")
    assert store.names() == []


# ------------------------------------------------------------------ durability


def test_a_second_process_cannot_open_the_same_database(tmp_path: Path) -> None:
    with ParamStore(tmp_path / "p.db"), pytest.raises(ParameterError, match="in use by another"):
        ParamStore(tmp_path / "p.db")
    with ParamStore(tmp_path / "p.db"):
        pass


WRITER = """
import sys
from zenros.services.master.param_store import ParamStore

store = ParamStore(sys.argv[1])
i = 0
while True:
    if i % 10 == 0:
        store.set(f"/t/n{i}", {"i": i, "l": [i, b"x"], "d": {"e": True}})
    else:
        store.set(f"/w/k{i % 7}/v{i}", i)
    if i % 13 == 0 and i % 10:
        store.delete(f"/w/k{i % 7}")
    print(i, flush=True)
    i += 1
"""


def replay(ops: list[int]) -> ParamTree:
    """The writer's operations 0..n, on the pure tree."""
    tree = ParamTree()
    for i in ops:
        if i % 10 == 0:
            value = {"i": i, "l": [i, b"x"], "d": {"e": True}}
            rows = tree.plan_set(f"/t/n{i}", value, Stamp(2 * i + 1, "x"))
        else:
            rows = tree.plan_set(f"/w/k{i % 7}/v{i}", i, Stamp(2 * i + 1, "x"))
        tree.apply(tree.winners(rows))
        if i % 13 == 0 and i % 10:
            tree.apply(tree.winners(tree.plan_delete(f"/w/k{i % 7}", Stamp(2 * i + 2, "x"))))
    return tree


def test_acknowledged_writes_survive_kill_9(tmp_path: Path) -> None:
    db = tmp_path / "params.db"
    argv = [sys.executable, "-c", WRITER, str(db)]
    with subprocess.Popen(argv, stdout=subprocess.PIPE, text=True) as proc:
        try:
            assert proc.stdout is not None
            first = [proc.stdout.readline() for _ in range(200)]
            proc.send_signal(signal.SIGKILL)  # mid-stream: the writer is still writing
            rest = proc.stdout.read()  # lines printed before death were acknowledged too
        finally:
            proc.kill()
            proc.wait(timeout=10)
    assert proc.returncode == -signal.SIGKILL
    acked = [int(line) for line in [*first, *rest.splitlines()] if line.strip()]
    assert acked == list(range(len(acked))) and len(acked) >= 200
    with ParamStore(db) as reopened:
        got = typed(reopened.get("/"))
    # every acknowledged write is there; at most the one in flight was committed as well
    candidates = [replay(acked), replay([*acked, len(acked)])]
    assert got in [typed(t.get("/")) for t in candidates]


def test_a_write_given_an_older_clock_reading_is_still_the_newest(store: ParamStore) -> None:
    """The master passes its session's HLC time as ``now``; a replica's row stamped later
    (a clock ahead) must not make the next local write lose."""
    future = store.set("/x", 1, Stamp(2**62, "other"))
    stamp = store.set("/x", 2, now=1000)
    assert stamp > future and store.get("/x") == 2
    assert store.delete("/x", now=1000) > stamp
    assert store.load_yaml("x: 3", now=1000) == ["/x"] and store.get("/x") == 3
