"""nav2_msgs: zenros's definitions (zenros.ros2.nav2_definitions) against Nav2's own.

NAV2_HASHES are what ROS 2's own generator computes from Nav2's files: the .action/.srv/.msg
of ros-navigation/navigation2's nav2_msgs, branch kilted (71a1d84f4, nav2_msgs 1.4.2;
NavigateThroughPoses: branch jazzy, f4108e5b1, nav2_msgs 1.3.13), converted with
rosidl_adapter and hashed with rosidl_generator_type_description 4.9.5 (both from the ROS 2
Kilted wheels), the dependencies' descriptions from the interface wheels. (No nav2_msgs wheel
or published hash exists here; how they were computed: docs/ros2.md, "nav2_msgs".)
A top-level hash covers every part (goal, result, feedback, the send-goal and get-result
services, the feedback message), their fields' names, types and order.
"""

from __future__ import annotations

import msgspec
import pytest
from zenros.msgs import nav2_msgs
from zenros.registry import lookup_action, lookup_service
from zenros.ros2 import type_hash
from zenros.ros2.cdr import cdr_codec
from zenros.ros2.registry import definition, ros_name_of

NAV2_HASHES = {
    "nav2_msgs/msg/WaypointStatus": "RIHS01_4ac489f0a5a77648dcecf79b070c1ce5b126cd8fe4ed6ff0d316f87089b8f028",
    "nav2_msgs/srv/LoadMap": "RIHS01_eb875de5ea9bb394573effc3f239015b19869dd7a8988136768372c6ef907ec1",
    "nav2_msgs/srv/SaveMap": "RIHS01_fd31bfe2c69b4e15bf86155148940d27d762296b058bda8d450a7f38b6c557e7",
    "nav2_msgs/srv/ClearEntireCostmap": "RIHS01_553f54f9cadab44553fdf5627433fcb6701f71c1fc2eb55a7b4a004fdeeab952",
    # ManageLifecycleNodes.srv of navigation2 3f650828c (unchanged since Humble), same tools
    "nav2_msgs/srv/ManageLifecycleNodes": "RIHS01_1850f4f677251bb8f7744e3c0a87ef4f66c205e2f8740a8330251af7d1804460",
    "nav2_msgs/action/NavigateToPose": "RIHS01_a56dba8a3234a1215e610180dc703ae25bbf406dded8b54887891c9732857eab",
    "nav2_msgs/action/NavigateThroughPoses": "RIHS01_4e680a34fd27772095da6ffdb32ae348adbc3d948248d38cf8d5ca3fc7a3a6c4",  # Jazzy
    "nav2_msgs/action/ComputePathToPose": "RIHS01_b11d50c914791956069419b8f4ad441e3c66fcfbd9461f8e87110b77dc6febe9",
    "nav2_msgs/action/FollowPath": "RIHS01_9d95513552fb578cfb933d7e0160273911269cbdf4b348f1acb87d8a903b13cf",
    "nav2_msgs/action/FollowWaypoints": "RIHS01_667c9e9d426ede27da21dd3cdd3a34e4fc5cc6405b35bc9d5c0b084479920f54",
    "nav2_msgs/action/Spin": "RIHS01_8463b23d8454c92f735dbc77a62138d4e8570570939e39eab993dd63d8442925",
    "nav2_msgs/action/BackUp": "RIHS01_cc8889ed926f2e6956d1a3d0459e8e610289ed689efdcf8bcff3e4a349cea741",
    "nav2_msgs/action/DriveOnHeading": "RIHS01_14e7a7c5a558249d00ffe1e1ad64c06f4ac85f3527f04811dba9cf0cb0cc38a8",
    "nav2_msgs/action/DockRobot": "RIHS01_d4398769495d327a0cba210e3cf1055ac742ec8a3eccc683f88b1c730b1d6405",
    "nav2_msgs/action/UndockRobot": "RIHS01_fe446bf5f84bbdc08b5a1123365e3c9b1e522e50a412d64c36995f808df915a2",
}


@pytest.mark.parametrize("ros_name", sorted(NAV2_HASHES))
def test_nav2_hash_is_nav2s(ros_name: str) -> None:
    assert type_hash(ros_name) == NAV2_HASHES[ros_name]


def _nav2_classes() -> list[type]:
    out: list[type] = []
    for name in nav2_msgs.__all__:
        obj = getattr(nav2_msgs, name)
        if isinstance(obj, type) and issubclass(obj, msgspec.Struct):
            out.append(obj)
    return out


@pytest.mark.parametrize("cls", _nav2_classes(), ids=lambda c: c.__name__)
def test_every_nav2_class_has_nav2s_definition(cls: type) -> None:
    """Each zenros nav2_msgs class is carried under Nav2's definition (not a derived one) and
    its CDR codec round-trips it: fields Nav2 lacks stay on the zenros side."""
    ros = ros_name_of(cls)
    head, _, short = ros.rpartition("/")
    base = ros if "/msg/" in ros else f"{head}/{short.split('_', 1)[0]}"
    assert base in NAV2_HASHES  # a part of a type whose hash is Nav2's
    assert definition(ros).name == ros
    codec = cdr_codec(cls)
    msg = cls()
    assert codec.decode(codec.encode(msg)) == msg


def test_fields_beyond_nav2_stay_in_zenros() -> None:
    act = lookup_action("nav2_msgs/NavigateToPose")
    fb = act.Feedback(distance_remaining=2.5, position_tracking_error=0.3)
    back = cdr_codec(act.Feedback).decode(cdr_codec(act.Feedback).encode(fb))
    assert back.distance_remaining == 2.5  # float32 on the wire: 2.5 is exact
    assert back.position_tracking_error == 0.0  # not in Nav2 Kilted's feedback
    srv = lookup_service("nav2_msgs/ClearEntireCostmap")
    # Nav2's request holds one std_msgs/Empty (one byte in CDR); zenros's class has no field
    assert cdr_codec(srv.Request).encode(srv.Request()) == b"\x00\x01\x00\x00\x00"
