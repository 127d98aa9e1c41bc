"""The tf service's node in one process, over two sessions: services, authorities, statics."""

from __future__ import annotations

import threading
from typing import Any

import pytest
from zenros.errors import (
    ConnectivityException,
    ExtrapolationException,
    InvalidArgumentException,
    InvalidParameterValueError,
    LookupException,
)
from zenros.msgs.builtin_interfaces import Duration, Time
from zenros.msgs.geometry_msgs import TransformStamped
from zenros.msgs.tf_srvs import (
    CanTransform,
    CanTransformRequest,
    Frames,
    FramesRequest,
    LookupTransform,
    LookupTransformRequest,
    TF2Error,
)
from zenros.services.tf.node import TfNode
from zenros.testing import wait_for
from zenros.tf import LATEST, BufferClient, TransformBroadcaster, transform_stamped

STATICS = ["0.1 0 0.2 0 0 0 base_link laser", {"parent": "base_link", "child": "imu", "z": 0.3}]


def link(parent: str, child: str, x: float, sec: int) -> TransformStamped:
    return transform_stamped(parent, child, (x, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0), Time(sec=sec))


@pytest.fixture
def system(make_node: Any) -> tuple[TfNode, Any, BufferClient]:
    """The tf node in session 0 with two statics; a chassis broadcasting odom → base_link at
    t = 10..12 s, and a client, in session 1."""
    tf: TfNode = make_node("tf", 0, cls=TfNode,
                           parameter_overrides={"static_transforms": STATICS})
    chassis = make_node("chassis", 1)
    br = TransformBroadcaster(chassis)
    client = BufferClient(make_node("user", 1))
    assert client.wait_for_server(10)
    for i in range(200):  # until Zenoh routes /tf between the sessions
        br.send_transform(link("odom", "base_link", 1.0, 10))
        if tf.buffer.can_transform("odom", "base_link", Time(sec=10), timeout=0.05):
            break
    for sec, x in ((11, 2.0), (12, 3.0)):
        br.send_transform(link("odom", "base_link", x, sec))
    assert tf.buffer.can_transform("odom", "base_link", Time(sec=12), timeout=5)
    return tf, chassis, client


def test_lookup_and_can_transform_through_the_service(system: Any) -> None:
    _, _, client = system
    t = client.lookup_transform("odom", "laser", LATEST)
    assert t.header.stamp == Time(sec=12) and t.header.frame_id == "odom"
    assert t.transform.translation.x == pytest.approx(3.1)
    t = client.lookup_transform("odom", "imu", Time(sec=10, nanosec=500_000_000))
    assert t.transform.translation.x == pytest.approx(1.5)
    assert t.transform.translation.z == pytest.approx(0.3)
    assert client.can_transform("laser", "odom", Time(sec=11))
    assert not client.can_transform("laser", "odom", Time(sec=13))
    # Time travel: base_link at 10 s seen from base_link at 12 s, through odom.
    t = client.lookup_transform_full("base_link", Time(sec=12), "base_link", Time(sec=10), "odom")
    assert t.transform.translation.x == pytest.approx(-2.0)


@pytest.mark.parametrize(("target", "source", "sec", "exc", "code", "text"), [
    ("odom", "nowhere", 12, LookupException, TF2Error.LOOKUP_ERROR, '"nowhere" passed to'),
    ("odom", "laser", 30, ExtrapolationException, TF2Error.EXTRAPOLATION_ERROR,
     "extrapolation into the future"),
    ("/odom", "laser", 12, InvalidArgumentException, TF2Error.INVALID_ARGUMENT_ERROR,
     "cannot start with a '/'"),
])  # fmt: skip
def test_a_failed_lookup_comes_back_as_a_tf2_error(
    system: Any, make_node: Any, target: str, source: str, sec: int, exc: type, code: int,
    text: str,
) -> None:
    _, _, client = system
    with pytest.raises(exc, match=text.replace("(", r"\(")):
        client.lookup_transform(target, source, Time(sec=sec))
    raw = make_node("raw", 1).create_client(LookupTransform, "/tf/lookup_transform")
    res = raw.call(LookupTransformRequest(target_frame=target, source_frame=source,
                                          source_time=Time(sec=sec)))
    assert res.error.error == code and text in res.error.error_string


def test_connectivity_error_and_explained_can_transform(system: Any, make_node: Any) -> None:
    tf, chassis, client = system
    TransformBroadcaster(chassis).send_transform(link("world", "dock", 1.0, 12))
    assert tf.buffer.can_transform("world", "dock", LATEST, timeout=5)
    with pytest.raises(ConnectivityException):
        client.lookup_transform("odom", "dock", LATEST)
    raw = make_node("raw", 1).create_client(CanTransform, "/tf/can_transform")
    res = raw.call(CanTransformRequest(target_frame="odom", source_frame="dock"))
    assert not res.can_transform and "not part of the same tree" in res.error_string


def test_a_lookup_with_a_timeout_waits_for_the_data(system: Any) -> None:
    _, chassis, client = system
    got: list[Any] = []
    t = threading.Thread(target=lambda: got.append(
        client.lookup_transform("odom", "arm", LATEST, timeout=10.0)))
    t.start()
    br = TransformBroadcaster(chassis)
    # Keep sending until the waiting lookup returns (it must not have failed meanwhile).
    assert wait_for(lambda: br.send_transform(link("base_link", "arm", 0.5, 12)) or not
                    t.is_alive(), timeout=10)  # fmt: skip
    t.join(5)
    assert got and got[0].transform.translation.x == pytest.approx(3.5)
    # With a short timeout and no data: the underlying error, not a timeout (tf2's rule).
    with pytest.raises(LookupException):
        client.lookup_transform("odom", "never", LATEST, timeout=Duration(nanosec=200_000_000))


def test_frames_report_authorities_rates_and_statics(system: Any, make_node: Any) -> None:
    _, _, _ = system
    frames_client = make_node("viewer", 1).create_client(Frames, "/tf/frames")
    res = frames_client.call(FramesRequest())
    by_id = {f.frame_id: f for f in res.frames}
    assert sorted(by_id) == ["base_link", "imu", "laser"]
    base = by_id["base_link"]
    assert base.parent == "odom" and base.authority == "/chassis" and not base.static
    assert base.most_recent == Time(sec=12) and base.count >= 3 and base.rate > 0
    assert base.delay > 0  # wall clock now minus a stamp at 12 s
    for child in ("imu", "laser"):
        assert by_id[child].static and by_id[child].parent == "base_link"
        assert by_id[child].authority == "/tf"
    assert "'base_link':" in res.yaml and "broadcaster: '/chassis'" in res.yaml


def test_static_transforms_can_be_added_at_run_time(system: Any) -> None:
    tf, _, client = system
    tf.set_parameter("static_transforms", ["0 0 0.5 0 0 0 base_link mast"])
    assert client.can_transform("base_link", "mast", LATEST, timeout=5.0)
    assert client.can_transform("base_link", "laser", LATEST)  # the earlier ones stay
    with pytest.raises(InvalidParameterValueError, match="static_transforms"):
        tf.set_parameter("static_transforms", ["0 0 base_link"])


def test_bad_static_transforms_fail_at_startup(make_node: Any) -> None:
    with pytest.raises(InvalidParameterValueError, match=r"static_transforms'\[1\]"):
        make_node("tf", 0, cls=TfNode, parameter_overrides={
            "static_transforms": ["0 0 0 0 0 0 a b", {"parent": "a", "child": "c", "yaw": "x"}]
        })
