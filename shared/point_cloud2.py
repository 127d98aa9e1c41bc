"""`sensor_msgs/PointCloud2` as numpy, with the functions of ROS 2's ``sensor_msgs_py.
point_cloud2`` (`read_points`, `read_points_numpy`, `create_cloud`, `create_cloud_xyz32`) and
their rules: fields by name, offsets and counts as the message lays them out, NaN points
skipped on request, organised clouds kept (height x width) on request. Reading is a
zero-copy view of the message's bytes wherever the layout allows."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

from .errors import DecodeError, EncodeError
from .message import UInt8Array, to_array
from .msgs.sensor_msgs import PointCloud2, PointField
from .msgs.std_msgs import Header

__all__ = ["DATATYPES", "create_cloud", "create_cloud_xyz32", "dtype_from_fields",
           "fields_from_dtype", "read_points", "read_points_numpy"]

# PointField datatype -> numpy element type (little-endian)
DATATYPES: dict[int, np.dtype[Any]] = {
    PointField.INT8: np.dtype("i1"), PointField.UINT8: np.dtype("u1"),
    PointField.INT16: np.dtype("<i2"), PointField.UINT16: np.dtype("<u2"),
    PointField.INT32: np.dtype("<i4"), PointField.UINT32: np.dtype("<u4"),
    PointField.FLOAT32: np.dtype("<f4"), PointField.FLOAT64: np.dtype("<f8"),
}
_BY_DTYPE = {(dt.kind, dt.itemsize): code for code, dt in DATATYPES.items()}


def dtype_from_fields(fields: Iterable[PointField], point_step: int | None = None,
                      bigendian: bool = False) -> np.dtype[Any]:
    """The structured numpy type of a point: each field at its offset (a field with count
    n > 1 is an array of n), the whole ``point_step`` bytes long."""
    names, formats, offsets = [], [], []
    for f in fields:
        if f.datatype not in DATATYPES:
            raise DecodeError(f"point field {f.name!r}: unknown datatype {f.datatype}")
        base = DATATYPES[f.datatype]
        if bigendian:
            base = base.newbyteorder(">")
        names.append(f.name)
        formats.append(base if f.count == 1 else np.dtype((base, (f.count,))))
        offsets.append(f.offset)
    spec: dict[str, Any] = {"names": names, "formats": formats, "offsets": offsets}
    if point_step is not None:
        spec["itemsize"] = point_step
    try:
        made: np.dtype[Any] = np.dtype(spec)  # type: ignore[call-overload]
        return made
    except ValueError as exc:
        raise DecodeError(f"point fields do not fit a point of {point_step} bytes: {exc}") \
            from None


def fields_from_dtype(dtype: np.dtype[Any]) -> list[PointField]:
    """The PointFields of a structured numpy type (the inverse of `dtype_from_fields`)."""
    if dtype.names is None:
        raise EncodeError(f"points need a structured dtype (named fields), got {dtype}")
    out = []
    for name in dtype.names:
        sub, offset = dtype.fields[name][:2]  # type: ignore[index]
        base, count = (sub.base, int(np.prod(sub.shape))) if sub.shape else (sub, 1)
        code = _BY_DTYPE.get((base.kind, base.itemsize))
        if code is None:
            raise EncodeError(f"point field {name!r}: {base} has no PointField datatype")
        out.append(PointField(name=name, offset=offset, datatype=code, count=count))
    return out


def read_points(cloud: PointCloud2, field_names: Sequence[str] | None = None,
                skip_nans: bool = False, uvs: Iterable[Any] | None = None,
                reshape_organized_cloud: bool = False) -> np.ndarray[Any, Any]:
    """The points as a structured array (a view of the message's bytes unless NaNs are
    skipped or points picked by ``uvs``, (u, v) pairs of an organised cloud).

    Raises:
        DecodeError: a field name the cloud does not have, or too few bytes.
    """
    dtype = dtype_from_fields(cloud.fields, cloud.point_step, bool(cloud.is_bigendian))
    count = cloud.width * cloud.height
    row = cloud.width * cloud.point_step
    if cloud.height > 1 and cloud.row_step < row:
        raise DecodeError(f"row_step {cloud.row_step} is shorter than a row of points ({row})")
    need = cloud.row_step * (cloud.height - 1) + row if cloud.height > 1 else count * cloud.point_step
    if len(cloud.data) < need:
        raise DecodeError(f"cloud data has {len(cloud.data)} bytes; {cloud.height} x "
                          f"{cloud.width} points of {cloud.point_step} bytes need {need}")
    if cloud.height > 1 and cloud.row_step != row:  # padded rows: one copy, without the pads
        rows = np.ndarray((cloud.height, row), np.uint8, buffer=cloud.data,
                          strides=(cloud.row_step, 1))
        points = np.ascontiguousarray(rows).view(dtype).reshape(-1)
    else:
        points = np.frombuffer(cloud.data, dtype, count)
    if field_names is not None:
        missing = [n for n in field_names if n not in (dtype.names or ())]
        if missing:
            raise DecodeError(f"the cloud has no field {missing[0]!r} (it has "
                              f"{', '.join(dtype.names or ())})")
        points = points[list(field_names)]
    if uvs is not None:
        index = [v * cloud.width + u for u, v in uvs]
        points = points[index]
    if skip_nans:
        floats = [n for n in (points.dtype.names or ()) if points.dtype[n].kind == "f"]
        if floats:
            keep = np.ones(len(points), bool)
            for n in floats:
                column = points[n]
                keep &= ~np.isnan(column.reshape(len(points), -1)).any(axis=1)
            points = points[keep]
    if reshape_organized_cloud and cloud.height > 1 and not skip_nans and uvs is None:
        return points.reshape(cloud.height, cloud.width)
    return points


def read_points_numpy(cloud: PointCloud2, field_names: Sequence[str] | None = None,
                      skip_nans: bool = False, uvs: Iterable[Any] | None = None,
                      reshape_organized_cloud: bool = False) -> np.ndarray[Any, Any]:
    """The points as a plain (n, fields) array; the fields must share one element type."""
    points = read_points(cloud, field_names, skip_nans, uvs, reshape_organized_cloud)
    names = points.dtype.names or ()
    kinds = {points.dtype[n].base for n in names}
    if len(kinds) != 1 or any(points.dtype[n].shape for n in names):
        raise DecodeError("read_points_numpy needs fields of one element type and count 1 "
                          f"(got {', '.join(f'{n}: {points.dtype[n]}' for n in names)})")
    (base,) = kinds
    flat = np.stack([points[n] for n in names], axis=-1)
    return flat.astype(base.newbyteorder("="), copy=False)


def create_cloud(header: Header, fields: Sequence[PointField] | None,
                 points: Any) -> PointCloud2:
    """A PointCloud2 of ``points``: a structured array (``fields`` None: its dtype says the
    layout), or rows of values laid out by ``fields`` (a list of tuples, an (n, k) array).
    A 2-D structured array makes an organised cloud."""
    if isinstance(points, np.ndarray) and points.dtype.names is not None and fields is None:
        array = points
        fields = fields_from_dtype(points.dtype)
        dtype = dtype_from_fields(fields, points.dtype.itemsize)
        array = np.ascontiguousarray(points).astype(dtype, copy=False)
    else:
        if fields is None:
            raise EncodeError("create_cloud: give fields, or points as a structured array")
        dtype = dtype_from_fields(fields)
        plain = points if isinstance(points, np.ndarray) else list(points)
        array = np.zeros(len(plain), dtype)
        if len(plain):
            rows = np.asarray(plain, dtype=object if not isinstance(plain, np.ndarray)
                              else None).reshape(len(plain), -1)
            names = dtype.names or ()
            if rows.shape[1] != len(names):
                raise EncodeError(f"each point needs {len(names)} values ({', '.join(names)}), "
                                  f"got {rows.shape[1]}")
            for k, name in enumerate(names):
                array[name] = rows[:, k].astype(dtype[name])
    height, width = (array.shape if array.ndim == 2 else (1, len(array)))
    return PointCloud2(header=header, height=height, width=width, fields=list(fields),
                       is_bigendian=False, point_step=dtype.itemsize,
                       row_step=dtype.itemsize * width, is_dense=False,
                       data=to_array(UInt8Array, array.tobytes()))


def create_cloud_xyz32(header: Header, points: Any) -> PointCloud2:
    """A cloud of x, y, z float32 points from an (n, 3) array or a list of triples."""
    fields = [PointField(name=n, offset=4 * i, datatype=PointField.FLOAT32, count=1)
              for i, n in enumerate("xyz")]
    return create_cloud(header, fields, np.asarray(points, np.float32).reshape(-1, 3))
