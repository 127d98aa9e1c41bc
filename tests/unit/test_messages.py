"""message and msgs/*: the registry, user-defined types, services and actions, numpy array
fields, and the Time/Duration value types."""

from __future__ import annotations

import math
from typing import Any

import msgspec
import numpy as np
import pytest
from zenros.codec import codec_for
from zenros.errors import UnknownTypeError
from zenros.message import (
    ActionType,
    Float32Array,
    Float64Array,
    Int8Array,
    Message,
    ServiceType,
    UInt8Array,
    array_field,
    define_action,
    define_service,
    normalize_type_name,
    to_array,
)
from zenros.msgs import example_interfaces, std_srvs
from zenros.msgs.builtin_interfaces import Duration, Time
from zenros.msgs.geometry_msgs import (
    Point,
    Pose,
    PoseWithCovariance,
    Quaternion,
    Twist,
    TwistWithCovariance,
)
from zenros.msgs.nav_msgs import MapMetaData, OccupancyGrid, Odometry
from zenros.msgs.rcl_interfaces import Log
from zenros.msgs.sensor_msgs import Imu, LaserScan
from zenros.msgs.std_msgs import Header, String
from zenros.registry import lookup_action, lookup_service, lookup_type, registered_types

# ------------------------------------------------------------------ registry


EXPECTED_TYPES = [
    "builtin_interfaces/Time", "builtin_interfaces/Duration", "std_msgs/Header",
    "std_msgs/String", "std_msgs/Empty", "geometry_msgs/Twist", "geometry_msgs/Pose",
    "geometry_msgs/TransformStamped", "nav_msgs/Odometry", "nav_msgs/OccupancyGrid",
    "nav_msgs/Path", "sensor_msgs/LaserScan", "sensor_msgs/Imu", "sensor_msgs/JointState",
    "sensor_msgs/BatteryState", "tf2_msgs/TFMessage", "rosgraph_msgs/Clock", "rcl_interfaces/Log",
]


@pytest.mark.parametrize("name", EXPECTED_TYPES)
def test_standard_types_are_registered_under_ros_names(name: str) -> None:
    cls = lookup_type(name)
    assert cls.__msgtype__ == name
    assert registered_types()[name] is cls


@pytest.mark.parametrize(
    "name", ["geometry_msgs/Twist", "geometry_msgs/msg/Twist", "/geometry_msgs/Twist",
             "geometry_msgs/msg/Twist/"],
)
def test_lookup_type_accepts_ros1_and_ros2_spellings(name: str) -> None:
    assert lookup_type(name) is Twist


def test_normalize_type_name() -> None:
    assert normalize_type_name("pkg/msg/Name") == "pkg/Name"
    assert normalize_type_name("pkg/srv/Name") == "pkg/Name"
    assert normalize_type_name("pkg/action/Name") == "pkg/Name"
    assert normalize_type_name("pkg/Name") == "pkg/Name"
    assert normalize_type_name("pkg/other/Name") == "pkg/other/Name"


def test_unknown_type_suggests_the_closest_few() -> None:
    with pytest.raises(UnknownTypeError) as exc:
        lookup_type("geometry_msgs/Twits")
    text = str(exc.value)
    assert text == "unknown message type 'geometry_msgs/Twits'; did you mean geometry_msgs/Twist?"
    with pytest.raises(UnknownTypeError, match=r"did you mean nav_msgs/Odometry\?$"):
        lookup_type("Odometri")
    with pytest.raises(UnknownTypeError, match=r"no close match among \d+ registered"):
        lookup_type("zz/Qqqqqq")


def test_an_unambiguous_short_name_is_accepted() -> None:
    assert lookup_type("Twist") is Twist
    assert lookup_service("AddTwoInts").name == "example_interfaces/AddTwoInts"
    # (not Fibonacci: the ROS 2 tests define test_msgs/Fibonacci too, which makes it ambiguous)
    assert lookup_action("NavigateToPose").name == "nav2_msgs/NavigateToPose"

    class ThingA(Message):
        __msgtype__ = "zenros_test_a/Thing"

    class ThingB(Message):
        __msgtype__ = "zenros_test_b/Thing"

    with pytest.raises(UnknownTypeError, match=r"'Thing' is ambiguous: zenros_test_a/Thing or "
                       r"zenros_test_b/Thing"):
        lookup_type("Thing")


def test_unknown_type_error_is_a_lookup_error() -> None:
    with pytest.raises(LookupError):
        lookup_type("nope/Nope")


def test_registered_types_is_a_copy() -> None:
    types = registered_types()
    types.pop("geometry_msgs/Twist")
    assert "geometry_msgs/Twist" in registered_types()


def test_every_registered_type_is_a_message_named_as_registered() -> None:
    for name, cls in registered_types().items():
        assert issubclass(cls, Message)
        assert normalize_type_name(cls.__msgtype__) == name


# ------------------------------------------------------------------ user-defined types


class BatteryAlarm(Message):  # type: ignore[misc, unused-ignore]
    __msgtype__ = "zenros_test_pkg/BatteryAlarm"
    level: float = 0.0
    cells: list[float] = msgspec.field(default_factory=list)
    reason: str = ""


class Blob(Message):  # type: ignore[misc, unused-ignore]
    __msgtype__ = "zenros_test_pkg/msg/Blob"
    __bulk__ = True
    data: UInt8Array = array_field(UInt8Array)


class Unnamed(Message):  # type: ignore[misc, unused-ignore]
    value: int = 0


def test_user_defined_type_registers_and_round_trips() -> None:
    assert lookup_type("zenros_test_pkg/BatteryAlarm") is BatteryAlarm
    assert lookup_type("zenros_test_pkg/msg/BatteryAlarm") is BatteryAlarm
    codec = codec_for(BatteryAlarm)
    msg = BatteryAlarm(level=0.15, cells=[3.7, 3.6], reason="low")
    assert codec.decode(codec.encode(msg)) == msg
    assert codec.encoding == "application/json;zenros_test_pkg/BatteryAlarm"


def test_user_defined_type_written_pkg_msg_name_registers_normalized() -> None:
    assert "zenros_test_pkg/Blob" in registered_types()
    assert lookup_type("zenros_test_pkg/Blob") is Blob


def test_user_defined_bulk_type_uses_msgpack() -> None:
    codec = codec_for(Blob)
    assert codec.bulk
    assert codec.encoding.startswith("application/msgpack;")
    back = codec.decode(codec.encode(Blob(data=to_array(UInt8Array, [1, 2, 255]))))
    assert back.data.tolist() == [1, 2, 255]
    assert back.data.dtype == np.uint8


def test_message_without_msgtype_is_not_registered() -> None:
    assert Unnamed not in registered_types().values()
    assert codec_for(Unnamed).type_name == "Unnamed"


def test_messages_are_mutable() -> None:
    p = Point(x=1.0)
    p.y = 2.0
    assert (p.x, p.y, p.z) == (1.0, 2.0, 0.0)


def test_ros_defaults() -> None:
    assert Quaternion() == Quaternion(x=0.0, y=0.0, z=0.0, w=1.0)
    assert Pose().orientation.w == 1.0
    assert Header().frame_id == "" and Header().stamp == Time()
    assert Log().level == Log.INFO == 20
    assert (Log.DEBUG, Log.WARN, Log.ERROR, Log.FATAL) == (10, 30, 40, 50)


def test_default_factories_are_not_shared() -> None:
    a, b = Twist(), Twist()
    a.linear.x = 1.0
    assert b.linear.x == 0.0
    o1, o2 = Odometry(), Odometry()
    o1.pose.covariance[0] = 5.0
    assert o2.pose.covariance[0] == 0.0


# ------------------------------------------------------------------ services and actions


def test_standard_services_and_actions() -> None:
    trigger = lookup_service("std_srvs/Trigger")
    assert trigger is std_srvs.Trigger
    assert trigger.Request is std_srvs.TriggerRequest
    assert trigger.Response is std_srvs.TriggerResponse
    assert lookup_service("std_srvs/srv/SetBool") is std_srvs.SetBool
    assert lookup_service("example_interfaces/srv/AddTwoInts") is example_interfaces.AddTwoInts
    fib = lookup_action("example_interfaces/action/Fibonacci")
    assert fib is example_interfaces.Fibonacci
    assert (fib.Goal, fib.Result, fib.Feedback) == (
        example_interfaces.FibonacciGoal, example_interfaces.FibonacciResult,
        example_interfaces.FibonacciFeedback,
    )


class ChargeRequest(Message):  # type: ignore[misc, unused-ignore]
    __msgtype__ = "zenros_test_pkg/ChargeRequest"
    dock: str = ""


class ChargeResponse(Message):  # type: ignore[misc, unused-ignore]
    __msgtype__ = "zenros_test_pkg/ChargeResponse"
    ok: bool = False


class DockGoal(Message):  # type: ignore[misc, unused-ignore]
    __msgtype__ = "zenros_test_pkg/DockGoal"
    dock: str = ""


class DockResult(Message):  # type: ignore[misc, unused-ignore]
    __msgtype__ = "zenros_test_pkg/DockResult"
    docked: bool = False


class DockFeedback(Message):  # type: ignore[misc, unused-ignore]
    __msgtype__ = "zenros_test_pkg/DockFeedback"
    distance: float = 0.0


def test_define_service() -> None:
    srv = define_service("zenros_test_pkg/srv/Charge", ChargeRequest, ChargeResponse)
    assert isinstance(srv, ServiceType)
    assert srv.name == "zenros_test_pkg/Charge"
    assert lookup_service("zenros_test_pkg/Charge") is srv
    assert lookup_service("zenros_test_pkg/srv/Charge") is srv


def test_define_action() -> None:
    act = define_action("zenros_test_pkg/action/Dock", DockGoal, DockResult, DockFeedback)
    assert isinstance(act, ActionType)
    assert act.name == "zenros_test_pkg/Dock"
    assert lookup_action("zenros_test_pkg/Dock") is act
    assert (act.Goal, act.Result, act.Feedback) == (DockGoal, DockResult, DockFeedback)


def test_unknown_service_and_action_suggest_close_ones() -> None:
    with pytest.raises(UnknownTypeError, match=r"unknown service type 'std_srvs/Trigr'; did you "
                       r"mean std_srvs/Trigger\?"):
        lookup_service("std_srvs/Trigr")
    with pytest.raises(UnknownTypeError, match=r"unknown action type 'nav2_msgs/DockRobt'; did "
                       r"you mean nav2_msgs/DockRobot or nav2_msgs/UndockRobot\?"):
        lookup_action("nav2_msgs/DockRobt")


def test_a_message_type_is_not_a_service_type() -> None:
    with pytest.raises(UnknownTypeError):
        lookup_service("geometry_msgs/Twist")


# ------------------------------------------------------------------ numpy array fields


@pytest.mark.parametrize(
    ("cls", "dtype"),
    [(Float32Array, np.float32), (Float64Array, np.float64), (Int8Array, np.int8),
     (UInt8Array, np.uint8)],
)
def test_to_array_from_list_bytes_and_array(cls: Any, dtype: type) -> None:
    from_list = to_array(cls, [1, 2, 3])
    assert isinstance(from_list, cls) and from_list.dtype == dtype
    assert from_list.tolist() == [1, 2, 3]
    raw = np.array([4, 5], dtype=dtype).tobytes()
    from_bytes = to_array(cls, raw)
    assert isinstance(from_bytes, cls) and from_bytes.tolist() == [4, 5]
    assert not from_bytes.flags.owndata  # a view on the bytes, no copy
    from_2d = to_array(cls, np.ones((2, 3), dtype=dtype))
    assert from_2d.shape == (6,)


def test_to_array_from_bytearray_is_a_view() -> None:
    buf = bytearray(np.array([1.5, 2.5], dtype=np.float32).tobytes())
    arr = to_array(Float32Array, buf)
    assert np.shares_memory(arr, np.frombuffer(buf, dtype=np.uint8))
    buf[0:4] = np.array([9.0], dtype=np.float32).tobytes()
    assert arr[0] == 9.0


def test_array_field_defaults() -> None:
    assert isinstance(LaserScan().ranges, Float32Array)
    assert LaserScan().ranges.size == 0
    cov = PoseWithCovariance().covariance
    assert isinstance(cov, Float64Array) and cov.shape == (36,) and not cov.any()
    assert TwistWithCovariance().covariance.shape == (36,)
    assert Imu().orientation_covariance.shape == (9,)
    assert isinstance(OccupancyGrid().data, Int8Array)


def test_occupancy_grid_view() -> None:
    grid = OccupancyGrid(info=MapMetaData(width=4, height=3, resolution=0.05))
    grid.data = to_array(Int8Array, [-1] * 4 + [0] * 4 + [100] * 4)
    view = grid.grid()
    assert view.shape == (3, 4)
    assert view.dtype == np.int8
    assert view[0].tolist() == [-1] * 4 and view[2].tolist() == [100] * 4
    assert np.shares_memory(view, grid.data)


def test_occupancy_grid_view_with_wrong_size_fails() -> None:
    grid = OccupancyGrid(info=MapMetaData(width=4, height=3))
    grid.data = to_array(Int8Array, [0] * 5)
    with pytest.raises(ValueError):
        grid.grid()


def test_messages_with_array_fields_compare_by_value() -> None:
    """``==`` must work on every message, including those holding numpy arrays."""
    assert Odometry() == Odometry()
    assert LaserScan() == LaserScan()
    a = Odometry(child_frame_id="base_link")
    b = Odometry(child_frame_id="base_link")
    b.pose.covariance[0] = 1.0
    assert a != b


def test_messages_without_arrays_compare_by_value() -> None:
    assert Twist() == Twist()
    assert String(data="a") != String(data="b")
    assert Point(x=1.0) != Pose()


# ------------------------------------------------------------------ Time and Duration

NS = 1_000_000_000


def test_time_from_seconds_and_back() -> None:
    t = Time.from_seconds(1.25)
    assert (t.sec, t.nanosec) == (1, 250_000_000)
    assert t.nanoseconds == 1_250_000_000
    assert t.to_sec() == 1.25
    assert Time.from_nanoseconds(3 * NS + 7) == Time(sec=3, nanosec=7)


def test_time_is_zero() -> None:
    assert Time().is_zero()
    assert not Time(nanosec=1).is_zero()


@pytest.mark.parametrize(
    ("seconds", "sec", "nanosec"),
    [(-0.25, -1, 750_000_000), (-1.5, -2, 500_000_000), (-1.0, -1, 0), (-1e-9, -1, 999_999_999),
     (0.0, 0, 0), (2.000000001, 2, 1)],
)
def test_negative_durations_normalize(seconds: float, sec: int, nanosec: int) -> None:
    d = Duration.from_seconds(seconds)
    assert (d.sec, d.nanosec) == (sec, nanosec)
    assert 0 <= d.nanosec < NS
    assert d.to_sec() == pytest.approx(seconds, abs=1e-9)


def test_duration_from_nanoseconds_normalizes() -> None:
    assert Duration.from_nanoseconds(-1) == Duration(sec=-1, nanosec=NS - 1)
    assert Duration.from_nanoseconds(2 * NS + 5) == Duration(sec=2, nanosec=5)
    assert Duration.from_nanoseconds(-(2 * NS)).nanoseconds == -(2 * NS)


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_seconds_rejected(bad: float) -> None:
    with pytest.raises(ValueError, match="finite"):
        Duration.from_seconds(bad)
    with pytest.raises(ValueError, match="finite"):
        Time.from_seconds(bad)


def test_time_duration_arithmetic() -> None:
    t = Time(sec=10, nanosec=900_000_000)
    d = Duration.from_seconds(0.2)
    assert t + d == Time(sec=11, nanosec=100_000_000)
    assert d + t == Time(sec=11, nanosec=100_000_000)
    assert isinstance(d + t, Time)
    assert t - d == Time(sec=10, nanosec=700_000_000)
    assert t - Time(sec=11) == Duration(sec=-1, nanosec=900_000_000)
    assert (t - Time(sec=11)).nanoseconds == -100_000_000
    assert d + d == Duration.from_seconds(0.4)
    assert d - Duration.from_seconds(0.5) == Duration.from_seconds(-0.3)
    assert -d == Duration.from_seconds(-0.2)
    assert d * 3 == Duration.from_seconds(0.6)
    assert d * 0.5 == Duration.from_seconds(0.1)
    assert d * -1 == -d


def test_time_minus_time_is_a_duration() -> None:
    diff = Time(sec=5) - Time(sec=2, nanosec=500_000_000)
    assert isinstance(diff, Duration)
    assert diff.to_sec() == 2.5


def test_meaningless_arithmetic_raises_type_error() -> None:
    t, d = Time(sec=1), Duration(sec=1)
    with pytest.raises(TypeError):
        t + t
    with pytest.raises(TypeError):
        d - t
    with pytest.raises(TypeError):
        t + 1
    with pytest.raises(TypeError):
        d + 1.0


def test_comparisons() -> None:
    assert Time(sec=1) < Time(sec=1, nanosec=1) <= Time(sec=1, nanosec=1)
    assert Time(sec=2) > Time(sec=1, nanosec=999_999_999) >= Time(sec=1, nanosec=999_999_999)
    assert Duration.from_seconds(-0.5) < Duration() < Duration.from_seconds(0.5)
    assert Duration(sec=1) >= Duration(sec=1) and Duration(sec=1) <= Duration(sec=1)
    assert sorted([Time(sec=2), Time(sec=1, nanosec=5), Time(sec=1)]) == [
        Time(sec=1), Time(sec=1, nanosec=5), Time(sec=2),
    ]
    assert Time(sec=1) == Time(sec=1, nanosec=0)
    assert Time(sec=1) != Duration(sec=1)


@pytest.mark.parametrize(
    ("a", "b"),
    [(Time(sec=1), Duration(sec=2)), (Duration(sec=1), Time(sec=2)), (Time(sec=1), 2),
     (Duration(sec=1), 2.0)],
    ids=["time-duration", "duration-time", "time-int", "duration-float"],
)
def test_ordering_against_another_kind_raises_type_error(a: Any, b: Any) -> None:
    """A Time is not earlier or later than a Duration or a number: Python's TypeError."""
    with pytest.raises(TypeError):
        a < b  # noqa: B015
    with pytest.raises(TypeError):
        a >= b  # noqa: B015


def test_time_and_duration_are_frozen_and_hashable() -> None:
    t = Time(sec=1)
    with pytest.raises(AttributeError):
        t.sec = 2  # type: ignore[misc, unused-ignore]
    assert {Time(sec=1): "a"}[Time(sec=1)] == "a"
    assert len({Duration(sec=1), Duration.from_seconds(1.0)}) == 1


_SHIPPED = """
import importlib, json, pkgutil
import zenros.msgs as msgs
for info in pkgutil.walk_packages(msgs.__path__, msgs.__name__ + "."):
    importlib.import_module(info.name)
from zenros.message import TABLES
print(json.dumps({"msg": sorted(TABLES.messages), "srv": sorted(TABLES.services),
                  "action": sorted(TABLES.actions)}))
"""

_LOOKUP = """
import json, sys
from zenros.registry import lookup_action, lookup_service, lookup_type
shipped = json.loads(sys.stdin.read())
find = {"msg": lookup_type, "srv": lookup_service, "action": lookup_action}
failed = []
for kind, names in shipped.items():
    for name in names:
        pkg, _, short = name.partition("/")
        for spelled in (f"{pkg}/{kind}/{short}", name):
            try:
                find[kind](spelled)
            except Exception as exc:
                failed.append(f"{spelled}: {exc}")
print(json.dumps({"failed": failed, "short": lookup_action("Fibonacci").name}))
"""


def test_every_shipped_type_resolves_by_its_ros2_name_in_a_fresh_process() -> None:
    """`zenros.msgs` leaves some packages out (test_msgs, action_tutorials_interfaces: their
    Fibonacci would make the short name ambiguous); a lookup by ``pkg/msg|srv|action/Name`` or
    ``pkg/Name`` imports them on demand, and a short name still means the standard type."""
    import json
    import subprocess
    import sys

    shipped = subprocess.run([sys.executable, "-c", _SHIPPED], capture_output=True, text=True,
                             check=True, timeout=60).stdout
    assert "test_msgs/Fibonacci" in json.loads(shipped)["action"]
    out = subprocess.run([sys.executable, "-c", _LOOKUP], input=shipped, capture_output=True,
                         text=True, check=True, timeout=60).stdout
    result = json.loads(out)
    assert result["failed"] == [], result["failed"]
    assert result["short"] == "example_interfaces/Fibonacci"


_ROS2_CLASS = """
from zenros.ros2.registry import zenros_class_of
cls = zenros_class_of("test_msgs/action/Fibonacci_Goal")
print(cls.__module__ if cls else None)
"""


def test_ros2_structure_name_loads_its_package_on_demand() -> None:
    """What both ROS 2 bridges ask for a topic's DDS or rmw_zenoh type (`zenros_class_of`)."""
    import subprocess
    import sys

    out = subprocess.run([sys.executable, "-c", _ROS2_CLASS], capture_output=True, text=True,
                         check=True, timeout=60).stdout
    assert out.strip() == "zenros.msgs.test_msgs"
