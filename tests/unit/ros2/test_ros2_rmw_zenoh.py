"""rmw_zenoh's key, token, QoS and attachment layout against the examples of rmw_zenoh's
docs/design.md (tag upstream/0.6.7 of ros2-gbp/rmw_zenoh-release) and Zenoh's own serializer."""

from __future__ import annotations

import pytest
import zenoh
import zenoh.ext
from zenros.ros2.rmw_zenoh import (
    DEFAULT_QOS,
    Attachment,
    Durability,
    Entity,
    EntityKind,
    Qos,
    Reliability,
    RmwZenohError,
    action_endpoints,
    data_key,
    keyexpr_to_qos,
    qos_to_keyexpr,
)

STRING_HASH = "RIHS01_df668c740482bbd48fb39d76a70dfd4bd59db1288021743503259e948f6b1a18"
ADD_TWO_INTS_HASH = "RIHS01_e118de6bf5eeb66a2491b5bda11202e7b68f198d6f67922cf30364858239c81a"


def test_data_keys_of_design_md() -> None:
    assert data_key(0, "/chatter", "std_msgs/msg/String") == (
        f"0/chatter/std_msgs::msg::dds_::String_/{STRING_HASH}")
    assert data_key(0, "/robot1/chatter", "std_msgs/msg/String") == (
        f"0/robot1/chatter/std_msgs::msg::dds_::String_/{STRING_HASH}")
    # example_interfaces has no wheel here: design.md's hash is the check of its definition
    assert data_key(2, "/add_two_ints", "example_interfaces/srv/AddTwoInts") == (
        f"2/add_two_ints/example_interfaces::srv::dds_::AddTwoInts_/{ADD_TWO_INTS_HASH}")


def _entity(kind: EntityKind, zid: str, node: str, eid: int, depth: int = 10,
            topic: str = "/chatter", tp: str = "std_msgs::msg::dds_::String_",
            h: str = STRING_HASH) -> Entity:
    return Entity(domain_id=0, zid=zid, node_id=0, entity_id=eid, kind=kind, namespace="/",
                  node=node, topic=topic, dds_type=tp, type_hash=h, qos=Qos(depth=depth))


DESIGN_TOKENS = [
    (Entity(0, "aac3178e146ba6f1fc6e6a4085e77f21", 0, 0, EntityKind.NODE, "/", "listener"),
     "@ros2_lv/0/aac3178e146ba6f1fc6e6a4085e77f21/0/0/NN/%/%/listener"),
    (_entity(EntityKind.SUBSCRIPTION, "aac3178e146ba6f1fc6e6a4085e77f21", "listener", 10),
     "@ros2_lv/0/aac3178e146ba6f1fc6e6a4085e77f21/0/10/MS/%/%/listener/%chatter/"
     f"std_msgs::msg::dds_::String_/{STRING_HASH}/::,10:,:,:,,"),
    (_entity(EntityKind.PUBLISHER, "8b20917502ee955ac4476e0266340d5c", "talker", 10, depth=7),
     "@ros2_lv/0/8b20917502ee955ac4476e0266340d5c/0/10/MP/%/%/talker/%chatter/"
     f"std_msgs::msg::dds_::String_/{STRING_HASH}/::,7:,:,:,,"),
    (_entity(EntityKind.SERVICE, "f9980ee0495eaafb3e38f0d19e2eae12", "add_two_ints_server", 10,
             topic="/add_two_ints", tp="example_interfaces::srv::dds_::AddTwoInts_",
             h=ADD_TWO_INTS_HASH),
     "@ros2_lv/0/f9980ee0495eaafb3e38f0d19e2eae12/0/10/SS/%/%/add_two_ints_server/"
     f"%add_two_ints/example_interfaces::srv::dds_::AddTwoInts_/{ADD_TWO_INTS_HASH}/::,10:,:,:,,"),
    (_entity(EntityKind.CLIENT, "e1dc8d1b45ae8717fce78689cc655685", "add_two_ints_client", 10,
             topic="/add_two_ints", tp="example_interfaces::srv::dds_::AddTwoInts_",
             h=ADD_TWO_INTS_HASH),
     "@ros2_lv/0/e1dc8d1b45ae8717fce78689cc655685/0/10/SC/%/%/add_two_ints_client/"
     f"%add_two_ints/example_interfaces::srv::dds_::AddTwoInts_/{ADD_TWO_INTS_HASH}/::,10:,:,:,,"),
]


@pytest.mark.parametrize(("entity", "token"), DESIGN_TOKENS, ids=[t[-20:] for _, t in DESIGN_TOKENS])
def test_tokens_of_design_md(entity: Entity, token: str) -> None:
    assert entity.token() == token
    assert Entity.parse(token) == entity


def test_namespaced_node_token_round_trips() -> None:
    e = Entity(3, "1f", 2, 7, EntityKind.PUBLISHER, "/robot1/arm", "driver", topic="/robot1/arm/js",
               dds_type="sensor_msgs::msg::dds_::JointState_", type_hash=STRING_HASH,
               qos=Qos(reliability=Reliability.BEST_EFFORT, durability=Durability.TRANSIENT_LOCAL,
                       depth=1))
    tok = e.token()
    assert "/%robot1%arm/driver/%robot1%arm%js/" in tok
    assert tok.endswith("/2:1:,1:,:,:,,")
    assert Entity.parse(tok) == e
    assert len(e.gid) == 16 and e.gid != Entity.parse(DESIGN_TOKENS[1][1]).gid


def test_qos_string() -> None:
    assert qos_to_keyexpr(DEFAULT_QOS) == "::,:,:,:,,"
    # a profile with rmw's "system default" zeros reads as rmw_zenoh's defaults
    assert qos_to_keyexpr(Qos(reliability=Reliability.SYSTEM_DEFAULT, depth=0, deadline=(0, 0))) == (
        "::,:,:,:,,")
    q = Qos(reliability=Reliability.BEST_EFFORT, depth=5, deadline=(1, 500), lifespan=(0, 7))
    assert qos_to_keyexpr(q) == "2::,5:1,500:0,7:,,"
    assert keyexpr_to_qos(qos_to_keyexpr(q)) == q
    assert keyexpr_to_qos("::,10:,:,:,,") == Qos(depth=10)


@pytest.mark.parametrize("bad", ["", "::,10", "::10:,:,:,,", "x::,10:,:,:,,", "::,-1:,:,:,,",
                                 "9::,10:,:,:,,", "::,10:,:,:,"])
def test_bad_qos_strings_are_refused(bad: str) -> None:
    with pytest.raises(RmwZenohError):
        keyexpr_to_qos(bad)


@pytest.mark.parametrize("bad", ["@ros2_lv/0/z/0/0/XX/%/%/n", "@ros2_lv/0/z/0/0/NN/%/%",
                                 "@other/0/z/0/0/NN/%/%/n", "@ros2_lv/0/z/0/1/MP/%/%/n",
                                 "@ros2_lv/x/z/0/0/NN/%/%/n", "@ros2_lv/0/z/0/0/NN/%//n"])
def test_bad_tokens_are_refused(bad: str) -> None:
    with pytest.raises(RmwZenohError):
        Entity.parse(bad)


def test_attachment_is_zenohs_serialization() -> None:
    gid = bytes(range(16))
    a = Attachment(sequence_number=42, source_timestamp=1_700_000_000_123_456_789, gid=gid)
    ref = zenoh.ext.z_serialize((zenoh.ext.Int64(42), zenoh.ext.Int64(1_700_000_000_123_456_789),
                                 gid)).to_bytes()
    assert a.encode() == ref
    assert len(ref) == 33
    assert Attachment.decode(ref) == a
    seq, ts, g = zenoh.ext.z_deserialize(tuple[zenoh.ext.Int64, zenoh.ext.Int64, bytes],
                                         zenoh.ZBytes(a.encode()))
    assert (int(seq), int(ts), bytes(g)) == (42, 1_700_000_000_123_456_789, gid)


@pytest.mark.parametrize("bad", [b"", bytes(32), bytes(34), bytes(16) + b"\x0f" + bytes(16)])
def test_bad_attachments_are_refused(bad: bytes) -> None:
    with pytest.raises(RmwZenohError):
        Attachment.decode(bad)


def test_action_endpoints() -> None:
    ep = action_endpoints("/fibonacci", "example_interfaces/action/Fibonacci")
    assert ep["send_goal"] == ("/fibonacci/_action/send_goal",
                               "example_interfaces/action/Fibonacci_SendGoal")
    assert ep["status"] == ("/fibonacci/_action/status", "action_msgs/msg/GoalStatusArray")
    key = data_key(0, ep["feedback"][0], ep["feedback"][1])
    assert key.startswith("0/fibonacci/_action/feedback/"
                          "example_interfaces::action::dds_::Fibonacci_FeedbackMessage_/RIHS01_")


def test_type_names() -> None:
    from zenros.errors import UnknownTypeError
    from zenros.ros2.typenames import dds_to_ros, ros_to_dds, ros_to_zenros, zenros_to_ros

    assert zenros_to_ros("geometry_msgs/Twist") == "geometry_msgs/msg/Twist"
    assert zenros_to_ros("std_srvs/SetBool", "srv") == "std_srvs/srv/SetBool"
    assert ros_to_dds("geometry_msgs/msg/Twist") == "geometry_msgs::msg::dds_::Twist_"
    assert ros_to_dds("std_srvs/srv/SetBool_Request") == "std_srvs::srv::dds_::SetBool_Request_"
    assert dds_to_ros("test_msgs::action::dds_::Fibonacci_SendGoal_") == (
        "test_msgs/action/Fibonacci_SendGoal")
    assert ros_to_zenros("nav_msgs/msg/Odometry") == "nav_msgs/Odometry"
    for bad in ("Twist", "geometry_msgs/Twist", "a/b/c/d"):
        with pytest.raises(UnknownTypeError):
            ros_to_dds(bad)
    with pytest.raises(UnknownTypeError):
        dds_to_ros("geometry_msgs::msg::Twist")
