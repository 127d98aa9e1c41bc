"""names: ROS name validation (with a caret under the bad character), resolution, remapping,
and the key expressions / liveliness tokens built from names."""

from __future__ import annotations

import pytest
import zenoh
from zenros.errors import InvalidNameError
from zenros.names import (
    DEFAULT_PREFIX,
    KeySpace,
    Remapper,
    Token,
    basename,
    chunk,
    join,
    namespace_of,
    parse_token,
    resolve,
    unchunk,
    validate_name,
    validate_namespace,
    validate_node_name,
)


def caret_column(exc: pytest.ExceptionInfo[InvalidNameError], name: str) -> int:
    """The index in ``name`` that the error's caret line points at."""
    lines = str(exc.value).splitlines()
    name_line, caret_line = lines[-2], lines[-1]
    assert name_line.strip() == name, lines
    offset = name_line.index(name)
    assert caret_line.strip() == "^", lines
    return caret_line.index("^") - offset


# ------------------------------------------------------------------ valid names


@pytest.mark.parametrize(
    "name",
    ["chatter", "cmd_vel", "_hidden", "a1", "robot1/odom", "/tf", "/robot1/cmd_vel", "~/status",
     "~", "/", "x/y/z", "Upper_Case"],
)
def test_valid_names_are_returned_unchanged(name: str) -> None:
    assert validate_name(name) == name


# ------------------------------------------------------------------ invalid names, with caret


@pytest.mark.parametrize(
    ("name", "bad_index", "why"),
    [
        ("a*b", 1, "'*'"),
        ("odom$", 4, "'$'"),
        ("?x", 0, "'?'"),
        ("a/#", 2, "'#'"),
        ("cmd vel", 3, "' '"),
        ("a-b", 1, "'-'"),
        ("a.b", 1, "'.'"),
        ("a%b", 1, "'%'"),
        ("caf\u00e9", 3, "not allowed"),
        ("a//b", 2, "empty segment"),
        ("//a", 1, "empty segment"),
        ("a/", 1, "end with '/'"),
        ("/robot1/", 7, "end with '/'"),
        ("1abc", 0, "digit"),
        ("robot/2d_map", 6, "digit"),
        ("/ns/9", 4, "digit"),
        ("a__b", 1, "'__'"),
        ("ns/x__", 4, "'__'"),
        ("__ns", 0, "'__'"),
        ("a~", 1, "'~'"),
        ("/ns/~x", 4, "'~'"),
    ],
)
def test_invalid_names_point_at_the_offending_character(
    name: str, bad_index: int, why: str
) -> None:
    with pytest.raises(InvalidNameError) as exc:
        validate_name(name)
    assert why in str(exc.value)
    assert repr(name) in str(exc.value)
    assert caret_column(exc, name) == bad_index


def test_invalid_name_error_is_also_a_value_error() -> None:
    with pytest.raises(ValueError, match="invalid topic name"):
        validate_name("a*")


def test_error_names_the_kind_of_name() -> None:
    with pytest.raises(InvalidNameError, match="invalid service name 'get map'"):
        validate_name("get map", "service")


def test_empty_name_is_rejected() -> None:
    with pytest.raises(InvalidNameError, match="may not be empty"):
        validate_name("")


# ------------------------------------------------------------------ resolution


@pytest.mark.parametrize(
    ("name", "namespace", "expected"),
    [
        ("chatter", "/", "/chatter"),
        ("chatter", "/robot1", "/robot1/chatter"),
        ("sensors/scan", "/robot1", "/robot1/sensors/scan"),
        ("/tf", "/robot1", "/tf"),
        ("/robot2/odom", "/robot1", "/robot2/odom"),
        ("/", "/robot1", "/"),
    ],
)
def test_resolve_relative_and_global(name: str, namespace: str, expected: str) -> None:
    assert resolve(name, namespace, "/robot1/node") == expected


@pytest.mark.parametrize(
    ("name", "expected"),
    [("~/status", "/robot1/chassis/status"), ("~/a/b", "/robot1/chassis/a/b"),
     ("~", "/robot1/chassis"), ("~/", "/robot1/chassis")],
)
def test_resolve_private_names_under_the_node(name: str, expected: str) -> None:
    assert resolve(name, "/robot1", "/robot1/chassis") == expected


def test_resolve_private_name_without_slash() -> None:
    """ROS 1 writes private names ``~x``; it must mean the same as ``~/x``."""
    assert resolve("~status", "/robot1", "/robot1/chassis") == "/robot1/chassis/status"
    assert resolve("~a/b", "/", "/chassis") == "/chassis/a/b"


def test_private_name_needs_a_node() -> None:
    with pytest.raises(InvalidNameError, match="needs a node"):
        resolve("~/status", "/robot1", None)


def test_resolve_validates_first() -> None:
    with pytest.raises(InvalidNameError, match="invalid service name"):
        resolve("get*map", "/", kind="service")


def test_join_namespace_of_basename() -> None:
    assert join("/", "x") == "/x"
    assert join("/a/b", "x") == "/a/b/x"
    assert namespace_of("/a/b/node") == "/a/b"
    assert namespace_of("/node") == "/"
    assert basename("/a/b/node") == "node"
    assert basename("/node") == "node"


# ------------------------------------------------------------------ namespaces and node names


@pytest.mark.parametrize(
    ("ns", "expected"),
    [("", "/"), ("/", "/"), ("robot1", "/robot1"), ("/robot1", "/robot1"),
     ("/robot1/", "/robot1"), ("a/b", "/a/b"), ("/a/b/", "/a/b")],
)
def test_namespace_normalization(ns: str, expected: str) -> None:
    assert validate_namespace(ns) == expected


@pytest.mark.parametrize("ns", ["/a//b", "/1robot", "/a*", "/a b", "~", "/~x", "/a__b"])
def test_invalid_namespaces(ns: str) -> None:
    with pytest.raises(InvalidNameError, match="invalid namespace name"):
        validate_namespace(ns)


def test_namespace_of_only_slashes_is_root_or_rejected() -> None:
    """A namespace is '/' or '/a/b', never the empty string."""
    try:
        ns = validate_namespace("//")
    except InvalidNameError:
        return
    assert ns == "/"


@pytest.mark.parametrize("name", ["talker", "_private", "node2", "Chassis_Node"])
def test_valid_node_names(name: str) -> None:
    assert validate_node_name(name) == name


@pytest.mark.parametrize(
    ("name", "bad_index"),
    [("2talker", 0), ("tal-ker", 3), ("a/b", 1), ("my node", 2), ("node$", 4), ("~x", 0)],
)
def test_invalid_node_names_point_at_the_character(name: str, bad_index: int) -> None:
    with pytest.raises(InvalidNameError, match="invalid node name") as exc:
        validate_node_name(name)
    assert caret_column(exc, name) == bad_index


def test_empty_node_name() -> None:
    with pytest.raises(InvalidNameError, match="may not be empty"):
        validate_node_name("")


# ------------------------------------------------------------------ remapping


def test_remapper_parses_rules_and_special_keys() -> None:
    r = Remapper.parse(["chatter:=/talk", "__ns:=robot1", "__node:=renamed"])
    assert r.rules == {"chatter": "/talk"}
    assert r.namespace == "/robot1"
    assert r.node_name == "renamed"


def test_remapper_long_forms_of_special_keys() -> None:
    r = Remapper.parse(["__namespace:=/fleet/r1", "__name:=chassis"])
    assert r.namespace == "/fleet/r1"
    assert r.node_name == "chassis"


def test_remap_rules_are_resolved_in_the_node_context() -> None:
    r = Remapper.parse(["chatter:=/talk", "~/state:=status", "/scan:=base_scan"])
    ns, node = "/robot1", "/robot1/talker"
    assert r.apply("/robot1/chatter", ns, node) == "/talk"
    assert r.apply("/robot1/talker/state", ns, node) == "/robot1/status"
    assert r.apply("/scan", ns, node) == "/robot1/base_scan"
    assert r.apply("/robot1/other", ns, node) == "/robot1/other"
    # "chatter" is relative: in another namespace it names another topic
    assert r.apply("/robot1/chatter", "/robot2", "/robot2/talker") == "/robot1/chatter"


def test_remap_private_source_without_slash() -> None:
    r = Remapper.parse(["~state:=status"])
    assert r.apply("/robot1/talker/state", "/robot1", "/robot1/talker") == "/robot1/status"


@pytest.mark.parametrize("arg", ["chatter", "chatter=/talk", ":=/talk", "chatter:=", ":="])
def test_malformed_remaps(arg: str) -> None:
    with pytest.raises(InvalidNameError, match="expected from:=to"):
        Remapper.parse([arg])


@pytest.mark.parametrize(
    ("arg", "match"),
    [("cmd*vel:=x", "invalid remap source name"), ("x:=cmd vel", "invalid remap target name"),
     ("__ns:=/1x", "invalid namespace name"), ("__node:=a/b", "invalid node name"),
     ("__node:=2d", "invalid node name")],
)
def test_remaps_with_invalid_names(arg: str, match: str) -> None:
    with pytest.raises(InvalidNameError, match=match):
        Remapper.parse([arg])


def test_empty_remapper_changes_nothing() -> None:
    assert Remapper().apply("/a/b", "/a", "/a/n") == "/a/b"
    assert Remapper.parse([]).rules == {}


# ------------------------------------------------------------------ key expressions


def test_default_prefix_matches_the_contract_table() -> None:
    keys = KeySpace()
    assert keys.prefix == DEFAULT_PREFIX == "zenros"
    assert keys.topic("/robot1/cmd_vel") == "zenros/topic/robot1/cmd_vel"
    assert keys.service("/nav/get_map") == "zenros/service/nav/get_map"
    assert keys.param("/nav/max_speed") == "zenros/param/nav/max_speed"
    assert keys.action("/nav/navigate_to_pose", "send_goal") == (
        "zenros/action/nav/navigate_to_pose/send_goal"
    )


@pytest.mark.parametrize("part", ["send_goal", "cancel_goal", "get_result", "feedback", "status"])
def test_action_keys_under_a_custom_prefix(part: str) -> None:
    keys = KeySpace("t_1234")
    key = keys.action("/robot1/nav/navigate_to_pose", part)
    assert key == f"t_1234/action/robot1/nav/navigate_to_pose/{part}"
    assert str(zenoh.KeyExpr(key)) == key


def test_custom_prefix_keys() -> None:
    keys = KeySpace("fleet/site_a")
    assert keys.topic("/odom") == "fleet/site_a/topic/odom"
    assert keys.service("/r1/reset") == "fleet/site_a/service/r1/reset"
    assert keys.param("/r1/node/speed") == "fleet/site_a/param/r1/node/speed"
    assert keys.all_topics() == "fleet/site_a/topic/**"
    assert keys.alive_all() == "fleet/site_a/alive/**"


def test_topic_name_inverts_topic() -> None:
    keys = KeySpace("p")
    assert keys.topic_name(keys.topic("/robot1/odom")) == "/robot1/odom"
    assert keys.topic_name("elsewhere/odom") == "elsewhere/odom"


def test_built_keys_are_valid_zenoh_key_expressions() -> None:
    keys = KeySpace("p")
    built = [
        keys.topic("/a/b"), keys.service("/s"), keys.param("/n/p"), keys.all_topics(),
        keys.alive_all(), keys.node_token("/ns/n", "zid1", "host.local", 1, 2),
        keys.entity_token("pub", "/ns/n", "/ns/topic", "std_msgs/String", "rel+tl+1", "zid1", 3),
    ]
    for key in built:
        assert str(zenoh.KeyExpr(key)) == key


def test_chunk_and_unchunk() -> None:
    assert chunk("/robot1/cmd_vel") == "%robot1%cmd_vel"
    assert unchunk("%robot1%cmd_vel") == "/robot1/cmd_vel"
    assert chunk("") == "%"
    assert "/" not in chunk("/a/b/c")


# ------------------------------------------------------------------ liveliness tokens


@pytest.mark.parametrize("node", ["/talker", "/robot1/chassis", "/fleet/site_a/robot1/nav"])
def test_node_token_round_trip(node: str) -> None:
    keys = KeySpace("t_tok")
    key = keys.node_token(node, "a1b2c3", "robot-1.local", 4242, 1_700_000_000_123_456_789)
    assert key.startswith("t_tok/alive/node/")
    # the node is one chunk, whatever its depth
    assert len(key.split("/")) == 8  # prefix, alive, node, node, zid, host, pid, start
    tok = keys.parse_token(key)
    assert tok == Token(
        "node", node, zid="a1b2c3", host="robot-1.local", pid=4242,
        start_ns=1_700_000_000_123_456_789,
    )


def test_node_token_host_is_made_key_safe() -> None:
    keys = KeySpace()
    key = keys.node_token("/n", "z", "my host/with*stars", 1, 2)
    tok = keys.parse_token(key)
    assert tok is not None
    assert tok.host == "my_host_with_stars"
    assert str(zenoh.KeyExpr(key)) == key


@pytest.mark.parametrize("kind", ["pub", "sub", "srv", "cli", "act", "actc"])
@pytest.mark.parametrize(
    ("node", "name"),
    [("/talker", "/chatter"), ("/robot1/chassis", "/robot1/odom"),
     ("/a/b/c", "/a/b/c/private_topic"), ("/n", "/")],
)
def test_entity_token_round_trip(kind: str, node: str, name: str) -> None:
    keys = KeySpace("t_ent")
    key = keys.entity_token(kind, node, name, "nav_msgs/Odometry", "be+5", "zid9", 17)
    assert len(key.split("/")) == 9  # prefix, alive, kind, node, name, type, qos, zid, eid
    tok = parse_token(keys, key)
    assert tok is not None
    assert (tok.kind, tok.node, tok.name, tok.type, tok.qos, tok.zid, tok.eid) == (
        kind, node, name, "nav_msgs/Odometry", "be+5", "zid9", "17",
    )


def test_entity_token_with_empty_qos() -> None:
    keys = KeySpace()
    key = keys.entity_token("srv", "/n", "/n/reset", "std_srvs/Trigger", "", "z", 1)
    assert "/_/" in key
    tok = keys.parse_token(key)
    assert tok is not None and tok.qos == ""


def test_entity_token_with_nested_prefix() -> None:
    keys = KeySpace("fleet/r1")
    key = keys.entity_token("pub", "/a/n", "/a/t", "std_msgs/String", "rel+10", "z", 2)
    tok = keys.parse_token(key)
    assert tok is not None and (tok.node, tok.name) == ("/a/n", "/a/t")


@pytest.mark.parametrize(
    "key",
    [
        "other/alive/node/%n/z/h/1/2",        # another prefix
        "p/topic/x",                          # not a liveliness key
        "p/alive/node/%n/z/h/1",              # too short
        "p/alive/node/%n/z/h/notapid/2",      # pid not an int
        "p/alive/node/%n/z/h/1/2/extra",      # too long
        "p/alive/bogus/%n/%t/ty/q/z/1",       # unknown kind
        "p/alive/pub/%n/%t/ty/q/z",           # entity too short
        "p/alive/",                           # nothing
    ],
)
def test_parse_token_rejects_foreign_or_malformed_keys(key: str) -> None:
    assert KeySpace("p").parse_token(key) is None


# ------------------------------------------------------------------ prefixes


def test_prefix_from_env(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("ZENROS_PREFIX", raising=False)
    assert KeySpace.from_env().prefix == "zenros"
    monkeypatch.setenv("ZENROS_PREFIX", "from_env")
    assert KeySpace.from_env().prefix == "from_env"
    assert KeySpace.from_env("explicit").prefix == "explicit"


def test_prefix_slashes_are_stripped(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("ZENROS_PREFIX", raising=False)
    assert KeySpace.from_env("/fleet/r1/").prefix == "fleet/r1"


@pytest.mark.parametrize("prefix", ["a*", "a/**", "$x", "a?b", "a#", "a//b", "/", "//"])
def test_invalid_prefixes(prefix: str, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("ZENROS_PREFIX", raising=False)
    with pytest.raises(InvalidNameError, match="invalid key prefix"):
        KeySpace.from_env(prefix)


def test_invalid_prefix_from_env(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("ZENROS_PREFIX", "bad*prefix")
    with pytest.raises(InvalidNameError, match="bad\\*prefix"):
        KeySpace.from_env()
