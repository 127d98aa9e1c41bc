"""codec: every registered type round-trips (JSON, or MessagePack for bulk types), JSON is
readable and ROS-shaped, numpy fields decode as views, and errors name path and type."""

from __future__ import annotations

import importlib
import itertools
import json
import math
from typing import Any

import msgspec
import msgspec.inspect as mi
import numpy as np
import pytest
from zenros.codec import (
    JSON,
    MSGPACK,
    codec_for,
    decode_any,
    encoding_of,
    from_builtins,
    split_encoding,
    to_builtins,
)
from zenros.errors import CodecError, DecodeError, EncodeError, TypeMismatchError, UnknownTypeError
from zenros.message import Float32Array, Float64Array, Int8Array, Message
from zenros.msgs.geometry_msgs import (
    Point,
    PoseStamped,
    PoseWithCovarianceStamped,
    Twist,
    Vector3,
)
from zenros.msgs.nav_msgs import MapMetaData, OccupancyGrid, Odometry
from zenros.msgs.sensor_msgs import BatteryState, JointState, LaserScan
from zenros.msgs.std_msgs import Float64, Header, String
from zenros.msgs.tf2_msgs import TFMessage
from zenros.registry import registered_types

BULK = {
    "nav_msgs/OccupancyGrid", "sensor_msgs/LaserScan",
    "zenros_msgs/SetParamRequest", "zenros_msgs/GetParamResponse", "zenros_msgs/ParamRows",
    "zenros_msgs/SyncResponse",
    # byte sequences (images, point clouds, compressed data: base64 in JSON)
    "sensor_msgs/Image", "sensor_msgs/CompressedImage", "sensor_msgs/PointCloud2",
    "std_msgs/ByteMultiArray", "std_msgs/UInt8MultiArray", "visualization_msgs/MeshFile",
    "test_msgs/BoundedPlainSequences", "test_msgs/BoundedSequences",
    "test_msgs/UnboundedSequences", "example_interfaces/ByteMultiArray",
    "example_interfaces/UInt8MultiArray", "audio_common_msgs/AudioData",
    "audio_common_msgs/AudioDataStamped",
}


# ------------------------------------------------------------------ sample messages


def _sample_value(t: mi.Type, n: itertools.count[int], depth: int) -> Any:
    k = next(n)
    if isinstance(t, mi.StructType):
        return _sample(t, n, depth + 1, every_field=True)
    if isinstance(t, mi.BoolType):
        return k % 2 == 0
    if isinstance(t, mi.IntType):
        lo = t.ge if t.ge is not None else (t.gt + 1 if t.gt is not None else None)
        hi = t.le if t.le is not None else (t.lt - 1 if t.lt is not None else None)
        if lo is not None and hi is not None:
            return lo + k % (hi - lo + 1)
        return k if lo is None else max(k, lo)
    if isinstance(t, mi.FloatType):
        return k + 0.5  # exact in float32 too
    if isinstance(t, (mi.StrType, mi.AnyType)):
        return f"s{k}"
    if isinstance(t, mi.BytesType):
        return bytes([k % 256, 0, 255])
    if isinstance(t, mi.NoneType):
        return None
    if isinstance(t, mi.LiteralType):
        return t.values[k % len(t.values)]
    if isinstance(t, mi.EnumType):
        return list(t.cls)[k % len(t.cls)]
    if isinstance(t, mi.UnionType):
        options = [u for u in t.types if not isinstance(u, mi.NoneType)]
        return _sample_value(options[0], n, depth) if options else None
    if isinstance(t, mi.ListType):
        size = 2 if depth < 3 else 0  # recursive types (trees) stay finite
        if t.min_length is not None:  # constrained lists (UUID: exactly 16 bytes)
            size = max(size, t.min_length)
        if t.max_length is not None:  # bounded sequences (ParameterDescriptor's ranges)
            size = min(size, t.max_length)
        return [_sample_value(t.item_type, n, depth) for _ in range(size)]
    if isinstance(t, mi.DictType):
        return {str(_sample_value(t.key_type, n, depth)): _sample_value(t.value_type, n, depth)}
    if isinstance(t, mi.CustomType):
        array_cls: Any = t.cls
        dtype = array_cls.dtype_
        values = ([-1, 0, 100] if dtype == np.int8 else [k % 256, 0, 255] if dtype == np.uint8
                  else [k + 0.5, k + 1.5, -(k + 0.25)])
        return np.array(values, dtype=dtype).view(array_cls)
    raise AssertionError(f"no sample for {t!r}")


def _sample(info: mi.StructType, n: itertools.count[int], depth: int, every_field: bool) -> Any:
    return info.cls(**{
        f.name: _sample_value(f.type, n, depth) for f in info.fields if every_field or f.required
    })


def sample(cls: type[Message]) -> Message:
    """An instance of ``cls`` with every field set to a non-default value."""
    info = mi.type_info(cls)
    assert isinstance(info, mi.StructType)
    msg: Message = _sample(info, itertools.count(1), 0, every_field=True)
    return msg


def minimal(cls: type[Message]) -> Message:
    """An instance of ``cls`` with defaults, and samples for required fields (if any)."""
    info = mi.type_info(cls)
    assert isinstance(info, mi.StructType)
    msg: Message = _sample(info, itertools.count(1), 0, every_field=False)
    return msg


def array_fields(msg: Any, path: str = "$") -> list[tuple[str, np.ndarray]]:
    out = []
    for name in msg.__struct_fields__:
        value = getattr(msg, name)
        if isinstance(value, np.ndarray):
            out.append((f"{path}.{name}", value))
        elif isinstance(value, msgspec.Struct):
            out.extend(array_fields(value, f"{path}.{name}"))
    return out


# Import every module that registers wire types, so the parametrization is the same whatever
# else pytest collected first.
for _mod in ("zenros.action", "zenros.smach.introspection", "zenros.param_protocol",
             "zenros.services.master.messages", "zenros.msgs.tf_srvs", "zenros.shutdown"):
    importlib.import_module(_mod)
ALL_TYPES = sorted(
    (name, cls) for name, cls in registered_types().items()
    if not name.startswith("zenros_test")  # types other test modules define for themselves
)


# ------------------------------------------------------------------ round trips


@pytest.mark.parametrize(("name", "cls"), ALL_TYPES, ids=[n for n, _ in ALL_TYPES])
@pytest.mark.parametrize("make", [minimal, sample], ids=["default", "sample"])
def test_every_registered_type_round_trips(name: str, cls: type[Message], make: Any) -> None:
    msg = make(cls)
    codec = codec_for(cls)
    data = codec.encode(msg)
    assert isinstance(data, bytes)
    back = codec.decode(data)
    assert type(back) is cls
    assert to_builtins(back) == to_builtins(msg)
    for (path, before), (_, after) in zip(array_fields(msg), array_fields(back), strict=True):
        assert type(after) is type(before), path
        assert after.dtype == before.dtype, path
        np.testing.assert_array_equal(after, before)


@pytest.mark.parametrize(("name", "cls"), ALL_TYPES, ids=[n for n, _ in ALL_TYPES])
def test_encoding_is_json_unless_bulk(name: str, cls: type[Message]) -> None:
    codec = codec_for(cls)
    assert codec.type_name == name
    if name in BULK:
        assert codec.bulk and codec.mime == MSGPACK
    else:
        assert not codec.bulk and codec.mime == JSON
    assert codec.encoding == f"{codec.mime};{name}" == encoding_of(cls)


@pytest.mark.parametrize(
    ("name", "cls"),
    [(n, c) for n, c in ALL_TYPES if n not in BULK],
    ids=[n for n, _ in ALL_TYPES if n not in BULK],
)
def test_json_is_readable_with_ros_field_names(name: str, cls: type[Message]) -> None:
    msg = sample(cls)
    obj = json.loads(codec_for(cls).encode(msg))
    assert isinstance(obj, dict)
    assert list(obj) == list(cls.__struct_fields__)
    assert obj == to_builtins(msg)


def test_codec_is_cached() -> None:
    assert codec_for(Twist) is codec_for(Twist)


def test_twist_json_layout() -> None:
    data = codec_for(Twist).encode(Twist(linear=Vector3(x=0.5), angular=Vector3(z=-1.0)))
    assert json.loads(data) == {
        "linear": {"x": 0.5, "y": 0.0, "z": 0.0},
        "angular": {"x": 0.0, "y": 0.0, "z": -1.0},
    }


def test_numpy_fields_are_lists_in_json() -> None:
    odom = Odometry()
    odom.pose.covariance[0] = 0.25
    obj = json.loads(codec_for(Odometry).encode(odom))
    cov = obj["pose"]["covariance"]
    assert isinstance(cov, list) and len(cov) == 36 and cov[0] == 0.25


def test_bulk_payload_is_not_json() -> None:
    data = codec_for(LaserScan).encode(LaserScan())
    with pytest.raises(ValueError):  # JSONDecodeError or UnicodeDecodeError
        json.loads(data)
    assert isinstance(msgspec.msgpack.decode(data), dict)


# ------------------------------------------------------------------ ROS-shaped JSON


def test_rosbridge_style_twist_with_ints_decodes() -> None:
    msg = codec_for(Twist).decode(b'{"linear": {"x": 1, "y": 0, "z": 0}, "angular": {"z": 2}}')
    assert msg == Twist(linear=Vector3(x=1.0), angular=Vector3(z=2.0))
    assert isinstance(msg.linear.x, float)


def test_ros1_header_with_seq_and_unknown_fields_decodes() -> None:
    payload = json.dumps({
        "header": {"seq": 42, "stamp": {"sec": 5, "nanosec": 6}, "frame_id": "map"},
        "pose": {"position": {"x": 1.5, "y": 2.5, "z": 0}, "orientation": {"w": 1}},
        "extra_field": {"anything": [1, 2, 3]},
    }).encode()
    msg = codec_for(PoseStamped).decode(payload)
    assert msg.header.frame_id == "map"
    assert (msg.header.stamp.sec, msg.header.stamp.nanosec) == (5, 6)
    assert (msg.pose.position.x, msg.pose.position.y) == (1.5, 2.5)
    assert msg.pose.orientation.w == 1.0


def test_missing_fields_take_defaults() -> None:
    msg = codec_for(PoseStamped).decode(b"{}")
    assert msg == PoseStamped()
    assert msg.pose.orientation.w == 1.0


def test_json_lists_decode_into_numpy_fields() -> None:
    cov = [float(i) for i in range(36)]
    data = json.dumps({"pose": {"covariance": cov}}).encode()
    msg = codec_for(PoseWithCovarianceStamped).decode(data)
    arr = msg.pose.covariance
    assert isinstance(arr, Float64Array) and arr.dtype == np.float64
    assert arr.tolist() == cov


def test_json_nested_lists_for_arrays_are_flattened() -> None:
    data = json.dumps({"pose": {"covariance": [[1.0, 2.0], [3.0, 4.0]]}}).encode()
    arr = codec_for(Odometry).decode(data).pose.covariance
    assert arr.shape == (4,)


def test_json_nan_in_a_float_field_survives_the_round_trip() -> None:
    """ROS uses NaN for "unknown" (BatteryState.temperature, .charge, ...): a sample carrying
    one must still decode, and come back as NaN."""
    msg = BatteryState(voltage=12.5, temperature=math.nan, cell_voltage=[3.7, math.nan])
    back = codec_for(BatteryState).decode(codec_for(BatteryState).encode(msg))
    assert back.voltage == 12.5
    assert math.isnan(back.temperature)
    assert back.cell_voltage[0] == 3.7 and math.isnan(back.cell_voltage[1])


@pytest.mark.parametrize("value", [math.inf, -math.inf])
def test_json_infinite_float_does_not_make_the_sample_undecodable(value: float) -> None:
    back = codec_for(Float64).decode(codec_for(Float64).encode(Float64(data=value)))
    assert back.data == value or math.isnan(back.data)


# ------------------------------------------------------------------ MessagePack views


def _payload_view(buf: bytearray) -> np.ndarray:
    return np.frombuffer(buf, dtype=np.uint8)


def test_msgpack_arrays_are_zero_copy_views_of_the_payload() -> None:
    scan = LaserScan(angle_min=-1.0, range_max=10.0)
    scan.ranges = np.linspace(0.5, 5.0, 100, dtype=np.float32).view(Float32Array)
    scan.intensities = np.ones(100, dtype=np.float32).view(Float32Array)
    payload = bytearray(codec_for(LaserScan).encode(scan))
    back = codec_for(LaserScan).decode(payload)
    for arr in (back.ranges, back.intensities):
        assert isinstance(arr, Float32Array) and arr.dtype == np.float32
        assert not arr.flags.owndata
        assert np.shares_memory(arr, _payload_view(payload))
    assert not np.shares_memory(back.ranges, back.intensities)
    np.testing.assert_array_equal(back.ranges, scan.ranges)
    np.testing.assert_array_equal(back.intensities, scan.intensities)


def test_msgpack_arrays_decoded_from_bytes_are_read_only_views() -> None:
    ranges = np.array([1.0, 2.0], dtype=np.float32).view(Float32Array)
    back = codec_for(LaserScan).decode(codec_for(LaserScan).encode(LaserScan(ranges=ranges)))
    assert not back.ranges.flags.owndata
    with pytest.raises(ValueError):  # received messages are shared: read-only
        back.ranges[0] = 5.0


def test_msgpack_occupancy_grid_round_trip_and_grid_view() -> None:
    width, height = 7, 5
    cells = np.tile(np.array([-1, 0, 50, 100, 0, 0, -1], dtype=np.int8), height)
    grid = OccupancyGrid(info=MapMetaData(width=width, height=height, resolution=0.05))
    grid.data = cells.view(Int8Array)
    payload = bytearray(codec_for(OccupancyGrid).encode(grid))
    back = codec_for(OccupancyGrid).decode(payload)
    assert isinstance(back.data, Int8Array)
    assert np.shares_memory(back.data, _payload_view(payload))
    assert (back.info.width, back.info.height, back.info.resolution) == (width, height, 0.05)
    view = back.grid()
    assert view.shape == (height, width) and view.dtype == np.int8
    assert np.shares_memory(view, back.data)
    np.testing.assert_array_equal(view, cells.reshape(height, width))


def test_msgpack_payload_carries_raw_bytes() -> None:
    ranges = np.array([1.0, 2.0, 3.0], dtype=np.float32)
    scan = LaserScan(ranges=ranges.view(Float32Array))
    raw = msgspec.msgpack.decode(codec_for(LaserScan).encode(scan))
    assert raw["ranges"] == ranges.tobytes()


def test_msgpack_decodes_from_bytearray_and_memoryview() -> None:
    data = codec_for(LaserScan).encode(
        LaserScan(ranges=np.array([1.5, 2.5], dtype=np.float32).view(Float32Array))
    )
    for buf in (bytearray(data), memoryview(data)):
        assert codec_for(LaserScan).decode(buf).ranges.tolist() == [1.5, 2.5]


def test_msgpack_non_contiguous_arrays_encode() -> None:
    ranges = np.arange(10, dtype=np.float32)[::2]
    back = codec_for(LaserScan).decode(codec_for(LaserScan).encode(LaserScan(ranges=ranges)))
    assert back.ranges.tolist() == [0.0, 2.0, 4.0, 6.0, 8.0]


def test_msgpack_accepts_plain_lists_in_array_fields() -> None:
    scan = LaserScan(ranges=[1.0, 2.0])  # type: ignore[arg-type, unused-ignore]
    back = codec_for(LaserScan).decode(codec_for(LaserScan).encode(scan))
    assert isinstance(back.ranges, Float32Array) and back.ranges.tolist() == [1.0, 2.0]


@pytest.mark.parametrize(
    ("field", "cls", "values"),
    [("ranges", LaserScan, np.array([1.0, 2.0, 3.0])),          # float64 into float32 field
     ("data", OccupancyGrid, np.array([100, -1, 0]))],           # int64 into int8 field
)
def test_msgpack_arrays_of_another_dtype_keep_their_values(
    field: str, cls: type[Message], values: np.ndarray
) -> None:
    """A plain ``np.array([...])`` (float64/int64) in a narrower field must not be garbled."""
    msg = cls(**{field: values})
    codec = codec_for(cls)
    try:
        back = codec.decode(codec.encode(msg))
    except EncodeError:
        return  # refusing clearly is acceptable; silently corrupting is not
    assert getattr(back, field).tolist() == values.tolist()


# ------------------------------------------------------------------ decode errors


def test_decode_error_names_the_path_and_expected_type() -> None:
    data = b'{"pose": {"pose": {"position": {"x": "one"}}}}'
    with pytest.raises(DecodeError) as exc:
        codec_for(PoseWithCovarianceStamped).decode(data)
    text = str(exc.value)
    assert "$.pose.pose.position.x" in text
    assert "geometry_msgs/PoseWithCovarianceStamped" in text
    assert "float" in text and "str" in text


def test_decode_error_for_a_list_element() -> None:
    data = b'{"transforms": [{}, {"transform": {"rotation": {"w": "x"}}}]}'
    with pytest.raises(DecodeError, match=r"\$\.transforms\[1\]\.transform\.rotation\.w"):
        codec_for(TFMessage).decode(data)


def test_decode_error_for_array_fields() -> None:
    with pytest.raises(DecodeError, match=r"expected an array, got str .*\$\.pose\.covariance"):
        codec_for(Odometry).decode(b'{"pose": {"covariance": "zeros"}}')
    # 3 bytes are not a whole float32: the error must say which field
    with pytest.raises(DecodeError, match=r"\$\.ranges"):
        codec_for(LaserScan).decode(msgspec.msgpack.encode({"ranges": b"\x00\x00\x00"}))


@pytest.mark.parametrize(
    ("cls", "data"),
    [(Twist, b"not json"), (Twist, b"[1, 2]"), (Twist, b""), (String, b'{"data": 5}'),
     (JointState, b'{"name": "a"}'), (LaserScan, b"\xc1"), (LaserScan, b"{}")],
)
def test_malformed_payloads_raise_decode_error(cls: type[Message], data: bytes) -> None:
    with pytest.raises(DecodeError, match=f"expected {cls.__msgtype__}"):
        codec_for(cls).decode(data)


def test_decode_error_is_a_codec_and_value_error() -> None:
    with pytest.raises(CodecError):
        codec_for(Twist).decode(b"x")
    with pytest.raises(ValueError):
        codec_for(Twist).decode(b"x")


# ------------------------------------------------------------------ encode errors


def test_publishing_another_type_raises_encode_error() -> None:
    with pytest.raises(EncodeError, match="expected geometry_msgs/Twist, got String"):
        codec_for(Twist).encode(String(data="x"))  # type: ignore[arg-type, unused-ignore]


def test_publishing_a_dict_raises_encode_error() -> None:
    with pytest.raises(EncodeError, match="expected geometry_msgs/Twist, got dict"):
        codec_for(Twist).encode({"linear": {}})  # type: ignore[arg-type, unused-ignore]


def test_subclass_instances_are_not_the_declared_type() -> None:
    class MyTwist(Twist):  # type: ignore[misc, unused-ignore]
        pass

    with pytest.raises(EncodeError):
        codec_for(Twist).encode(MyTwist())


def test_unencodable_field_value_raises_encode_error() -> None:
    msg = String(data=object())  # type: ignore[arg-type, unused-ignore]
    with pytest.raises(EncodeError, match="cannot encode std_msgs/String"):
        codec_for(String).encode(msg)


def test_numpy_scalars_encode_as_numbers() -> None:
    x, y, z = np.float32(1.5), np.float64(2.0), np.int64(3)
    msg = Point(x=x, y=y, z=z)  # type: ignore[arg-type, unused-ignore]
    assert json.loads(codec_for(Point).encode(msg)) == {"x": 1.5, "y": 2.0, "z": 3}


# ------------------------------------------------------------------ encodings


def test_check_encoding_accepts_own_and_schemaless_encodings() -> None:
    codec = codec_for(Twist)
    codec.check_encoding("application/json;geometry_msgs/Twist")
    codec.check_encoding("application/json")
    codec.check_encoding("")
    codec.check_encoding("application/msgpack;geometry_msgs/Twist")


def test_check_encoding_rejects_another_schema() -> None:
    expected = "expected geometry_msgs/Twist, got std_msgs/String"
    with pytest.raises(TypeMismatchError, match=expected):
        codec_for(Twist).check_encoding("application/json;std_msgs/String")


def test_check_encoding_rejects_another_mime() -> None:
    with pytest.raises(TypeMismatchError, match="text/plain"):
        codec_for(Twist).check_encoding("text/plain")


def test_type_mismatch_is_a_decode_error() -> None:
    with pytest.raises(DecodeError):
        codec_for(Twist).check_encoding("application/json;nav_msgs/Odometry")


def test_check_encoding_accepts_the_ros2_spelling_of_its_own_type() -> None:
    """``pkg/msg/Name`` is the same type as ``pkg/Name`` (lookup_type agrees)."""
    codec_for(Twist).check_encoding("application/json;geometry_msgs/msg/Twist")


def test_split_encoding() -> None:
    assert split_encoding("application/json;geometry_msgs/Twist") == (
        "application/json", "geometry_msgs/Twist",
    )
    assert split_encoding("application/json") == ("application/json", "")


def test_decode_any_uses_the_schema() -> None:
    odom = Odometry(child_frame_id="base_link")
    msg = decode_any(codec_for(Odometry).encode(odom), encoding_of(Odometry))
    assert isinstance(msg, Odometry) and msg.child_frame_id == "base_link"
    scan = decode_any(codec_for(LaserScan).encode(LaserScan(range_max=5.0)), encoding_of(LaserScan))
    assert isinstance(scan, LaserScan) and scan.range_max == 5.0


def test_decode_any_without_schema_or_with_unknown_type() -> None:
    with pytest.raises(DecodeError, match="names no message type"):
        decode_any(b"{}", "application/json")
    with pytest.raises(UnknownTypeError, match="no_pkg/Nope"):
        decode_any(b"{}", "application/json;no_pkg/Nope")


# ------------------------------------------------------------------ builtins


def test_to_builtins_gives_plain_data() -> None:
    odom = Odometry(header=Header(frame_id="odom"))
    obj = to_builtins(odom)
    assert obj["header"] == {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": "odom"}
    assert obj["pose"]["covariance"] == [0.0] * 36
    json.dumps(obj)  # nothing numpy left


def test_from_builtins_builds_typed_messages() -> None:
    msg = from_builtins({"linear": {"x": 1}, "angular": {"z": 0.5}}, Twist)
    assert msg == Twist(linear=Vector3(x=1.0), angular=Vector3(z=0.5))
    scan = from_builtins({"ranges": [1.0, 2.5]}, LaserScan)
    assert isinstance(scan.ranges, Float32Array) and scan.ranges.tolist() == [1.0, 2.5]


@pytest.mark.parametrize(("name", "cls"), ALL_TYPES, ids=[n for n, _ in ALL_TYPES])
def test_builtins_round_trip(name: str, cls: type[Message]) -> None:
    msg = sample(cls)
    assert to_builtins(from_builtins(to_builtins(msg), cls)) == to_builtins(msg)


def test_from_builtins_errors_name_path_and_type() -> None:
    with pytest.raises(DecodeError, match=r"expected geometry_msgs/Twist: .*\$\.linear\.x"):
        from_builtins({"linear": {"x": [1]}}, Twist)
    with pytest.raises(DecodeError, match="expected geometry_msgs/Twist"):
        from_builtins([1, 2], Twist)
    with pytest.raises(DecodeError, match=r"\$\.ranges"):
        from_builtins({"ranges": "abc"}, LaserScan)


def test_from_builtins_refuses_unknown_fields_with_their_path() -> None:
    with pytest.raises(DecodeError, match=r"unknown field 'linar' at \$ \(geometry_msgs/Twist has: linear, angular\)"):
        from_builtins({"linar": {"x": 1}}, Twist)
    with pytest.raises(DecodeError, match=r"unknown field 'X' at \$\.linear \(geometry_msgs/Vector3 has: x, y, z\)"):
        from_builtins({"linear": {"X": 1}}, Twist)
    with pytest.raises(DecodeError, match=r"unknown field 'stmp' at \$\.header"):
        from_builtins({"header": {"stmp": {"sec": 1}}}, LaserScan)
    with pytest.raises(DecodeError, match=r"unknown field 'child' at \$\.transforms\[1\]"):
        from_builtins({"transforms": [{"child_frame_id": "a"}, {"child": "b"}]}, TFMessage)
    # the wire stays lenient: a newer sender's extra field is skipped there
    assert codec_for(Twist).decode(b'{"linear": {"x": 1.0}, "extra": 1}').linear.x == 1.0


def test_from_builtins_takes_ros1_time_names_and_header_seq() -> None:
    """ROS 1 clients (roslibpy's Time/Header) write secs/nsecs and Header.seq; the JSON
    doors take them as the reference rosbridge does (sec/nanosec, seq dropped)."""
    from zenros.codec import from_builtins
    from zenros.msgs.builtin_interfaces import Duration, Time
    from zenros.registry import lookup_type

    stamped = lookup_type("geometry_msgs/PointStamped")
    msg = from_builtins({"header": {"seq": 7, "stamp": {"secs": 3, "nsecs": 5},
                                    "frame_id": "base"}, "point": {"y": 1.0}}, stamped)
    assert msg.header.stamp == Time(sec=3, nanosec=5)
    assert msg.header.frame_id == "base"
    path = from_builtins({"poses": [{"header": {"stamp": {"secs": 1}}}]},
                         lookup_type("nav_msgs/Path"))
    assert path.poses[0].header.stamp == Time(sec=1, nanosec=0)
    assert from_builtins({"secs": 2, "nsecs": 9}, Duration) == Duration(sec=2, nanosec=9)
    assert from_builtins({"sec": 2, "nanosec": 9}, Time) == Time(sec=2, nanosec=9)
