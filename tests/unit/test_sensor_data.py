"""`zenros.images` and `zenros.point_cloud2`: sensor_msgs/Image and PointCloud2 as numpy views,
with the layouts ROS defines (row padding, byte order, field offsets and counts, organised
clouds) and sensor_msgs_py.point_cloud2's documented behaviour (NaN skipping, field choice,
(u, v) picking)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from zenros.codec import codec_for
from zenros.errors import DecodeError, EncodeError
from zenros.images import encoding_layout, image_to_numpy, numpy_to_image
from zenros.msgs.sensor_msgs import Image, PointCloud2, PointField
from zenros.msgs.std_msgs import Header
from zenros.point_cloud2 import (
    create_cloud,
    create_cloud_xyz32,
    dtype_from_fields,
    read_points,
    read_points_numpy,
)

# ---------------------------------------------------------------- images


@pytest.mark.parametrize(("encoding", "dtype", "channels"), [
    ("rgb8", np.uint8, 3), ("bgra8", np.uint8, 4), ("mono16", np.uint16, 1),
    ("32FC1", np.float32, 1), ("16SC3", np.int16, 3), ("64FC2", np.float64, 2),
    ("bayer_rggb8", np.uint8, 1), ("yuv422", np.uint8, 2),
])
def test_an_image_round_trips_through_its_encoding(encoding: str, dtype: type,
                                                    channels: int) -> None:
    shape = (4, 5) if channels == 1 else (4, 5, channels)
    arr = (np.arange(np.prod(shape)) % 200).astype(dtype).reshape(shape)
    msg = numpy_to_image(arr, encoding, Header(frame_id="camera"))
    assert (msg.height, msg.width, msg.encoding) == (4, 5, encoding)
    assert msg.step == 5 * channels * np.dtype(dtype).itemsize
    back = image_to_numpy(msg)
    assert back.dtype == np.dtype(dtype) and np.array_equal(back, arr)
    wire = codec_for(Image)
    again = image_to_numpy(wire.decode(wire.encode(msg)))  # MessagePack, bytes kept
    assert np.array_equal(again, arr)


def test_row_padding_and_big_endian_data_are_read_as_ros_lays_them_out() -> None:
    rows = [bytes([1, 2, 3, 0xEE]), bytes([4, 5, 6, 0xEE])]  # mono8, width 3, step 4
    padded = Image(height=2, width=3, encoding="mono8", step=4, data=b"".join(rows))
    assert image_to_numpy(padded).tolist() == [[1, 2, 3], [4, 5, 6]]
    big = Image(height=1, width=2, encoding="mono16", is_bigendian=1, step=4,
                data=bytes([0x01, 0x02, 0x03, 0x04]))
    assert image_to_numpy(big).tolist() == [[0x0102, 0x0304]]
    view = image_to_numpy(numpy_to_image(np.zeros((2, 2), np.uint8), "mono8"))
    assert not view.flags.writeable  # a view of the message's bytes


@pytest.mark.parametrize(("msg", "error"), [
    (Image(height=1, width=1, encoding="nv12", data=b"x"), "unknown image encoding"),
    (Image(height=2, width=2, encoding="rgb8", step=6, data=bytes(11)), "need 12"),
    (Image(height=1, width=4, encoding="mono8", step=3, data=bytes(4)), "less than a row"),
])
def test_a_bad_image_is_refused_with_the_reason(msg: Image, error: str) -> None:
    with pytest.raises(DecodeError, match=error):
        image_to_numpy(msg)


def test_an_array_that_does_not_fit_the_encoding_is_refused() -> None:
    with pytest.raises(EncodeError, match="takes"):
        numpy_to_image(np.zeros((2, 2), np.uint8), "rgb8")
    with pytest.raises(EncodeError, match="holds uint8"):
        numpy_to_image(np.zeros((2, 2), np.float32), "mono8")
    with pytest.raises(ValueError, match="floats are 32 or 64"):
        encoding_layout("16FC1")


# ---------------------------------------------------------------- point clouds


def test_xyz_points_round_trip_and_read_as_views() -> None:
    pts = np.array([[1, 2, 3], [4, 5, 6], [7, 8, 9]], np.float32)
    cloud = create_cloud_xyz32(Header(frame_id="lidar"), pts)
    assert (cloud.point_step, cloud.row_step, cloud.width, cloud.height) == (12, 36, 3, 1)
    assert [(f.name, f.offset, f.datatype) for f in cloud.fields] == [
        ("x", 0, PointField.FLOAT32), ("y", 4, PointField.FLOAT32), ("z", 8, PointField.FLOAT32)]
    assert np.array_equal(read_points_numpy(cloud), pts)
    points = read_points(cloud)
    assert points.dtype.names == ("x", "y", "z") and not points.flags.writeable
    assert read_points(cloud, field_names=["z"])["z"].tolist() == [3, 6, 9]
    wire = codec_for(PointCloud2)
    assert np.array_equal(read_points_numpy(wire.decode(wire.encode(cloud))), pts)


def test_offsets_padding_counts_and_mixed_types_follow_the_fields() -> None:
    fields = [PointField(name="x", offset=0, datatype=PointField.FLOAT32, count=1),
              PointField(name="intensity", offset=8, datatype=PointField.UINT16, count=1),
              PointField(name="rgb", offset=12, datatype=PointField.UINT8, count=3)]
    dtype = dtype_from_fields(fields, 16)
    assert dtype.itemsize == 16 and dtype["rgb"].shape == (3,)
    cloud = create_cloud(Header(), None, np.array([(1.5, 7, (1, 2, 3))], dtype))
    assert cloud.point_step == 16 and len(cloud.data) == 16
    (p,) = read_points(cloud)
    assert (p["x"], p["intensity"], p["rgb"].tolist()) == (1.5, 7, [1, 2, 3])
    with pytest.raises(DecodeError, match="one element type"):
        read_points_numpy(cloud)
    rows = create_cloud(Header(), fields[:2], [(0.5, 1), (2.5, 65535)])
    assert read_points(rows)["intensity"].tolist() == [1, 65535]


def test_nans_are_skipped_on_request_and_organised_clouds_keep_their_shape() -> None:
    pts = np.array([[0, 0, 0], [math.nan, 1, 1], [2, 2, 2], [3, math.nan, 3]], np.float32)
    cloud = create_cloud_xyz32(Header(), pts)
    assert len(read_points(cloud)) == 4
    assert read_points_numpy(cloud, skip_nans=True).tolist() == [[0, 0, 0], [2, 2, 2]]
    organised = create_cloud(Header(), None, read_points(cloud).copy().reshape(2, 2))
    assert (organised.height, organised.width, organised.row_step) == (2, 2, 24)
    assert read_points(organised, reshape_organized_cloud=True).shape == (2, 2)
    picked = read_points(organised, uvs=[(1, 1), (0, 1)])  # (u, v): column, row
    assert picked["x"].tolist()[1] == 2 and math.isnan(picked["y"][0])


def test_padded_rows_and_short_or_malformed_clouds() -> None:
    fields = [PointField(name="v", offset=0, datatype=PointField.UINT8, count=1)]
    padded = PointCloud2(height=2, width=2, fields=fields, point_step=1, row_step=3,
                         data=bytes([1, 2, 0xEE, 3, 4]))
    assert read_points(padded, reshape_organized_cloud=True)["v"].tolist() == [[1, 2], [3, 4]]
    short = PointCloud2(height=1, width=4, fields=fields, point_step=1, data=bytes(3))
    with pytest.raises(DecodeError, match="need 4"):
        read_points(short)
    with pytest.raises(DecodeError, match="no field 'w'"):
        read_points(padded, field_names=["w"])
    bad = PointCloud2(height=1, width=1, point_step=1, data=b"x",
                      fields=[PointField(name="q", offset=0, datatype=99, count=1)])
    with pytest.raises(DecodeError, match="unknown datatype 99"):
        read_points(bad)
    with pytest.raises(EncodeError, match="needs 2 values"):
        create_cloud(Header(), [*fields, PointField(name="w", offset=1, datatype=2, count=1)],
                     [(1,)])
