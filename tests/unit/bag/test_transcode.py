"""Bulk payloads as JSON (--bulk-json) and back, losslessly."""

from __future__ import annotations

import json
import math

import numpy as np
from zenros.bag.transcode import from_json, to_json
from zenros.codec import codec_for
from zenros.msgs.nav_msgs import MapMetaData, OccupancyGrid
from zenros.msgs.sensor_msgs import LaserScan


def test_round_trip() -> None:
    grid = OccupancyGrid(info=MapMetaData(width=3, height=1, resolution=0.5),
                         data=np.array([-1, 0, 100], np.int8))
    wire = codec_for(OccupancyGrid).encode(grid)
    to, back = to_json("nav_msgs/OccupancyGrid"), from_json("nav_msgs/OccupancyGrid")
    assert to is not None
    text = to(wire)
    assert text is not None and json.loads(text)["data"] == [-1, 0, 100]
    again = back(text)
    assert again is not None and codec_for(OccupancyGrid).decode(again) == grid


def test_nan_survives() -> None:
    scan = LaserScan(ranges=np.array([1.0, math.nan], np.float32), range_max=math.nan)
    to, back = to_json("sensor_msgs/LaserScan"), from_json("sensor_msgs/LaserScan")
    assert to is not None
    text = to(codec_for(LaserScan).encode(scan))
    assert text is not None
    out = back(text)
    assert out is not None
    got = codec_for(LaserScan).decode(out)
    assert math.isnan(got.range_max) and math.isnan(float(got.ranges[1]))


def test_only_bulk_types_and_bad_payloads() -> None:
    assert to_json("geometry_msgs/Twist") is None
    assert to_json("no_pkg/Unknown") is None
    to = to_json("sensor_msgs/LaserScan")
    assert to is not None and to(b"\xc1 not msgpack") is None
    assert from_json("sensor_msgs/LaserScan")(b"{not json") is None
