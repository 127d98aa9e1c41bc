"""GridMap: an occupancy grid in numpy with its resolution and origin; load, save, convert.

``load_map("office.yaml")`` reads a map_server map; ``GridMap.to_msg()`` and
``GridMap.from_msg()`` convert to and from ``nav_msgs/OccupancyGrid``; ``save_map`` writes
YAML + image as map_saver does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import MapError
from ..message import Int8Array
from ..msgs.builtin_interfaces import Time
from ..msgs.geometry_msgs import Point, Pose
from ..msgs.nav_msgs import MapMetaData, OccupancyGrid
from ..msgs.std_msgs import Header
from ..tf.convert import yaw_from_msg, yaw_to_msg
from .convert import grid_to_pixels, pixels_to_grid
from .image import encode_image, read_image, write_image
from .meta import MapMeta, Mode, read_meta, write_meta

__all__ = ["GridMap", "load_map", "save_map"]


@dataclass(eq=False)
class GridMap:
    """Occupancy values -1 (unknown), 0 (free) .. 100 (occupied), row 0 at the bottom.

    Attributes:
        grid: int8 array of shape (height, width); ``grid[row, col]``, row 0 = bottom.
        resolution: metres per cell.
        origin: (x, y, yaw) of the lower-left corner of cell (0, 0) in ``map``.
        source: the YAML file the map was loaded from, if any.
    """

    grid: np.ndarray
    resolution: float
    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    source: Path | None = field(default=None, compare=False)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, GridMap):
            return NotImplemented
        return (self.resolution == other.resolution and self.origin == other.origin
                and np.array_equal(self.grid, other.grid))

    @property
    def width(self) -> int:
        return int(self.grid.shape[1])

    @property
    def height(self) -> int:
        return int(self.grid.shape[0])

    def world_to_cell(self, x: float, y: float) -> tuple[int, int]:
        """The (row, col) of the cell holding map point (x, y); may be outside the grid."""
        ox, oy, yaw = self.origin
        dx, dy = x - ox, y - oy
        if yaw:
            c, s = math.cos(yaw), math.sin(yaw)
            dx, dy = c * dx + s * dy, -s * dx + c * dy
        return math.floor(dy / self.resolution), math.floor(dx / self.resolution)

    def cell_to_world(self, row: int, col: int) -> tuple[float, float]:
        """The map point at the centre of cell (row, col)."""
        ox, oy, yaw = self.origin
        dx, dy = (col + 0.5) * self.resolution, (row + 0.5) * self.resolution
        if yaw:
            c, s = math.cos(yaw), math.sin(yaw)
            dx, dy = c * dx - s * dy, s * dx + c * dy
        return ox + dx, oy + dy

    def in_bounds(self, row: int, col: int) -> bool:
        return 0 <= row < self.height and 0 <= col < self.width

    def to_msg(self, frame_id: str = "map", stamp: Time | None = None) -> OccupancyGrid:
        """This map as a ``nav_msgs/OccupancyGrid`` (the cells are copied)."""
        ox, oy, yaw = self.origin
        pose = Pose(position=Point(x=ox, y=oy),
                    orientation=yaw_to_msg(yaw))
        t = stamp if stamp is not None else Time()
        return OccupancyGrid(
            header=Header(stamp=t, frame_id=frame_id),
            info=MapMetaData(map_load_time=t, resolution=self.resolution,
                             width=self.width, height=self.height, origin=pose),
            data=np.ascontiguousarray(self.grid, dtype=np.int8).reshape(-1).copy()
            .view(Int8Array),
        )

    @classmethod
    def from_msg(cls, msg: OccupancyGrid) -> GridMap:
        """A map from a ``nav_msgs/OccupancyGrid`` (checks size against the data length)."""
        w, h = msg.info.width, msg.info.height
        data = np.asarray(msg.data, dtype=np.int8)
        if w * h != data.size:
            raise MapError(f"OccupancyGrid: {w}x{h} cells but {data.size} values")
        if not (math.isfinite(msg.info.resolution) and msg.info.resolution > 0):
            raise MapError(f"OccupancyGrid: resolution must be positive, got {msg.info.resolution}")
        q = msg.info.origin.orientation
        yaw = yaw_from_msg(q)
        p = msg.info.origin.position
        return cls(data.reshape(h, w).copy(), float(msg.info.resolution), (p.x, p.y, yaw))

    def image(self, fmt: str = "png", mode: Mode = "trinary") -> bytes:
        """The map encoded as an image file (``png`` or ``pgm``), as map_saver draws it."""
        return encode_image(grid_to_pixels(self.grid, mode=mode), fmt)


def load_map(path: str | Path) -> GridMap:
    """Load a map_server map (YAML + image).

    Raises:
        MapError: the YAML or the image is missing or malformed; the message names the file
            and the key.
    """
    meta = read_meta(path)
    if not meta.image.is_file():
        raise MapError(f"{path}: 'image' names {str(meta.image)!r}, which does not exist")
    pixels = read_image(meta.image)
    grid = pixels_to_grid(pixels, mode=meta.mode, negate=meta.negate,
                          occupied_thresh=meta.occupied_thresh, free_thresh=meta.free_thresh)
    return GridMap(grid, meta.resolution, meta.origin, Path(path))


def save_map(grid_map: GridMap, path: str | Path, *, mode: Mode = "trinary",
             image_format: str = "pgm") -> Path:
    """Write ``path`` (YAML) and its image beside it, as map_saver does; return the image path.

    Trinary writes 254/0/205 with thresholds 0.65/0.196 (exact on reload for -1/0/100).
    Scale needs ``image_format="png"`` (unknown is transparent) and records thresholds
    1.0/0.0, so values come back within 1 (map_saver records 0.65/0.196, which rescales them).
    """
    path = Path(path)
    if mode == "scale" and image_format != "png":
        raise MapError(f"{path}: scale mode stores unknown as transparency; use image_format='png'")
    image = path.with_suffix("." + image_format)
    occ, free = (1.0, 0.0) if mode == "scale" else (0.65, 0.196)
    meta = MapMeta(image=image, resolution=grid_map.resolution, origin=grid_map.origin,
                   negate=False, occupied_thresh=occ, free_thresh=free, mode=mode)
    write_image(grid_to_pixels(grid_map.grid, mode=mode), image)
    write_meta(meta, path)
    return image
