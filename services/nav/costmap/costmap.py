"""Costmap2D: Nav2's layered costmap (static, obstacle, inflation, then keep-out) on numpy.

The master grid is rebuilt in the window each change touches, in Nav2's order: the static
layer's costs, the obstacle layer combined by maximum (its unknown cells leave the master
as it is; a known cell replaces an unknown master cell), inflation around lethal cells,
and last the keep-out cells written as 254 (a costmap filter: lethal, not inflated).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from zenros.message import Int8Array
from zenros.msgs.builtin_interfaces import Time
from zenros.msgs.geometry_msgs import Point, Pose, Quaternion
from zenros.msgs.nav_msgs import MapMetaData, OccupancyGrid
from zenros.msgs.std_msgs import Header

from .geometry import EMPTY, Bounds, GridGeometry
from .inflation import Inflation
from .keepout import rasterise
from .obstacle import ObstacleParams, Scan, update_layer
from .values import (
    FREE_SPACE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
    cost_to_occupancy,
    occupancy_to_cost,
)

__all__ = ["Costmap2D", "CostmapParams"]


@dataclass(frozen=True, slots=True)
class CostmapParams:
    """Costmap parameters; the defaults are the nav service's (nav2_params.yaml's
    inflation_radius 0.7 and cost_scaling_factor 3.0; the plugin's own are 0.55 and 10.0)."""

    robot_radius: float = 0.22
    """The inscribed radius of a circular robot (Nav2's ``robot_radius``)."""
    inflation_radius: float = 0.7
    cost_scaling_factor: float = 3.0
    inflate_unknown: bool = False
    inflate_around_unknown: bool = False
    track_unknown_space: bool = False
    lethal_cost_threshold: int = 100
    trinary_costmap: bool = True
    obstacle: ObstacleParams = field(default_factory=ObstacleParams)

    def with_(self, **changes: Any) -> CostmapParams:
        """A copy with some fields changed."""
        return replace(self, **changes)


class Costmap2D:
    """A layered costmap over a width × height grid in the map frame.

    Args:
        occupancy: the static map as int8 occupancy (−1, 0..100), shape (height, width),
            row 0 at the origin (``OccupancyGrid.grid()``), or None for a map with no
            static layer (all free, or all unknown with ``track_unknown_space``).
        resolution: metres per cell.
        origin: the map-frame position of the corner of cell (0, 0).
        params: layer parameters.
        shape: (height, width) when ``occupancy`` is None.
    """

    def __init__(
        self,
        occupancy: np.ndarray | None,
        resolution: float,
        origin: tuple[float, float] = (0.0, 0.0),
        params: CostmapParams = CostmapParams(),
        *,
        shape: tuple[int, int] | None = None,
    ) -> None:
        if occupancy is None:
            if shape is None:
                raise ValueError("a costmap without a static map needs shape=(height, width)")
            h, w = shape
        else:
            occupancy = np.asarray(occupancy)
            if occupancy.ndim != 2:
                raise ValueError(f"occupancy must be 2-D (height, width), got {occupancy.shape}")
            h, w = occupancy.shape
        self.geometry = GridGeometry(
            int(w), int(h), float(resolution), float(origin[0]), float(origin[1])
        )
        self.params = params
        self.inflation = Inflation(
            self.geometry.resolution, params.robot_radius, params.inflation_radius,
            params.cost_scaling_factor, params.inflate_unknown, params.inflate_around_unknown,
        )
        unknown = NO_INFORMATION if params.track_unknown_space else FREE_SPACE
        self._static = np.full((h, w), unknown, dtype=np.uint8)
        self._obstacle = np.full((h, w), unknown, dtype=np.uint8)
        self._keepout = np.zeros((h, w), dtype=bool)
        self._master = np.empty((h, w), dtype=np.uint8)
        if occupancy is not None:
            self._static[:] = self._static_costs(occupancy)
        self._rebuild(self.geometry.full)

    # --- construction ------------------------------------------------------------------

    @classmethod
    def from_occupancy_grid(
        cls, grid: OccupancyGrid, params: CostmapParams = CostmapParams()
    ) -> Costmap2D:
        """A costmap whose static layer is a nav_msgs/OccupancyGrid (origin yaw ignored)."""
        info = grid.info
        if len(grid.data) != info.width * info.height:
            raise ValueError(
                f"OccupancyGrid has {len(grid.data)} cells for {info.width} x {info.height}"
            )
        origin = (info.origin.position.x, info.origin.position.y)
        return cls(grid.grid(), info.resolution, origin, params)

    def _static_costs(self, occupancy: np.ndarray) -> np.ndarray:
        p = self.params
        return occupancy_to_cost(
            occupancy, track_unknown_space=p.track_unknown_space,
            lethal_cost_threshold=p.lethal_cost_threshold, trinary_costmap=p.trinary_costmap,
        )

    # --- geometry ----------------------------------------------------------------------

    @property
    def width(self) -> int:
        return self.geometry.width

    @property
    def height(self) -> int:
        return self.geometry.height

    @property
    def resolution(self) -> float:
        return self.geometry.resolution

    @property
    def origin(self) -> tuple[float, float]:
        return (self.geometry.origin_x, self.geometry.origin_y)

    def world_to_map(self, x: float, y: float) -> tuple[int, int] | None:
        """The cell ``(mx, my)`` holding a map-frame point, or None outside the map."""
        return self.geometry.world_to_map(x, y)

    def map_to_world(self, mx: float, my: float) -> tuple[float, float]:
        """The map-frame centre of cell ``(mx, my)``."""
        return self.geometry.map_to_world(mx, my)

    # --- costs -------------------------------------------------------------------------

    @property
    def costs(self) -> np.ndarray:
        """The master grid: uint8 (height, width), ``costs[my, mx]``; read-only view."""
        v = self._master.view()
        v.flags.writeable = False
        return v

    def cost(self, mx: int, my: int) -> int:
        """The cost of one cell (IndexError outside the map)."""
        if not self.geometry.contains(mx, my):
            raise IndexError(f"cell ({mx}, {my}) is outside the {self.width} x {self.height} map")
        return int(self._master[my, mx])

    def cost_at(self, x: float, y: float) -> int:
        """The cost at a map-frame point; 255 (no information) outside the map."""
        cell = self.world_to_map(x, y)
        return NO_INFORMATION if cell is None else int(self._master[cell[1], cell[0]])

    @property
    def keepout_mask(self) -> np.ndarray:
        """The rasterised keep-out areas and walls (bool, read-only view)."""
        v = self._keepout.view()
        v.flags.writeable = False
        return v

    # --- layers ------------------------------------------------------------------------

    def near_static(self, points: np.ndarray, reach: float) -> np.ndarray:
        """Whether each (N, 2) world point lies within ``reach`` m (whole cells) of a
        lethal cell of the static map (a wall the map knows, not one the scan marked)."""
        cells = self.geometry.world_to_cells(points).tolist()
        k = max(0, int(np.ceil(reach / self.resolution)))
        h, w = self._static.shape
        return np.array([bool((self._static[max(0, my - k):min(h, my + k + 1),
                                            max(0, mx - k):min(w, mx + k + 1)]
                               == LETHAL_OBSTACLE).any()) for mx, my in cells], dtype=bool)

    def set_static(self, occupancy: np.ndarray) -> None:
        """Replace the static layer (same shape) and rebuild the whole master grid."""
        occupancy = np.asarray(occupancy)
        if occupancy.shape != self._static.shape:
            raise ValueError(f"static map shape {occupancy.shape} != costmap {self._static.shape}")
        self._static[:] = self._static_costs(occupancy)
        self._rebuild(self.geometry.full)

    def update_from_scan(self, scan: Any, pose: tuple[float, float, float]) -> Bounds:
        """Clear and mark the obstacle layer from a LaserScan (or ``Scan``) taken by a
        sensor at ``pose`` = (x, y, yaw) in the map frame, then rebuild the master grid
        around the cells that changed. Returns that window (empty if nothing changed).

        Raises:
            ValueError: a non-finite pose or scan angle.
        """
        s = Scan(
            float(scan.angle_min), float(scan.angle_increment), float(scan.range_min),
            float(scan.range_max), np.asarray(scan.ranges),
        )
        touched = update_layer(self._obstacle, self.geometry, self.params.obstacle, s, pose)
        return self._rebuild(touched)

    def mark(self, points: Sequence[Sequence[float]] | np.ndarray) -> Bounds:
        """Mark map-frame points as lethal in the obstacle layer (e.g. from another
        sensor); returns the rebuilt window."""
        cells = self.geometry.world_to_cells(np.asarray(points, dtype=np.float64))
        mx, my = cells[:, 0], cells[:, 1]
        inside = (mx >= 0) & (mx < self.width) & (my >= 0) & (my < self.height)
        mx, my = mx[inside], my[inside]
        if mx.size == 0:
            return EMPTY
        self._obstacle[my, mx] = LETHAL_OBSTACLE
        return self._rebuild(Bounds.around(mx, my))

    def clear_obstacles(self) -> None:
        """Forget everything the obstacle layer saw (Nav2's clear_entirely_* services)."""
        self._obstacle[:] = NO_INFORMATION if self.params.track_unknown_space else FREE_SPACE
        self._rebuild(self.geometry.full)

    def set_keepout(
        self,
        polygons: Iterable[Sequence[Sequence[float]]] = (),
        walls: Iterable[Sequence[Sequence[float]]] = (),
    ) -> None:
        """Replace the keep-out areas (polygons) and virtual walls (polylines), each a
        list of map-frame ``(x, y)`` points; their cells become lethal (not inflated).

        Raises:
            ValueError: a shape that is not a list of finite points (a polygon needs 3,
                a wall 2); the previous shapes stay.
        """
        new = rasterise(self.geometry, polygons, walls)
        changed = np.nonzero(new != self._keepout)
        self._keepout = new
        if changed[0].size:
            ys, xs = changed
            self._rebuild(Bounds.around(xs, ys))

    # --- the master grid ---------------------------------------------------------------

    def rebuild(self) -> None:
        """Recompute the whole master grid from the layers (updates do it per window)."""
        self._rebuild(self.geometry.full)

    def _rebuild(self, touched: Bounds) -> Bounds:
        """Recompute the master grid in ``touched`` grown by the inflation radius (every
        cell whose inflated cost a change there can alter); returns that window."""
        if touched.empty:
            return EMPTY
        w, h = self.width, self.height
        r = self.inflation.cells
        window = touched.grow(r, w, h)
        src = window.grow(r, w, h)  # inflation reads sources up to r cells outside
        st, ob = self._static[src.slices], self._obstacle[src.slices]
        combined = np.where(
            ob == NO_INFORMATION, st, np.where(st == NO_INFORMATION, ob, np.maximum(st, ob))
        )
        inner = (
            slice(window.y0 - src.y0, window.y1 - src.y0),
            slice(window.x0 - src.x0, window.x1 - src.x0),
        )
        out = self.inflation.apply(combined, inner)
        out[self._keepout[window.slices]] = LETHAL_OBSTACLE
        self._master[window.slices] = out
        return window

    def to_occupancy_grid(self, frame_id: str = "map", stamp: Time | None = None) -> OccupancyGrid:
        """The master grid in Nav2's published scale (0, 1..98, 99 inscribed, 100 lethal,
        −1 unknown) as a nav_msgs/OccupancyGrid."""
        t = stamp if stamp is not None else Time()
        return OccupancyGrid(
            header=Header(stamp=t, frame_id=frame_id),
            info=MapMetaData(
                map_load_time=t, resolution=self.resolution, width=self.width, height=self.height,
                origin=Pose(
                    position=Point(x=self.origin[0], y=self.origin[1], z=0.0),
                    orientation=Quaternion(w=1.0),
                ),
            ),
            data=cost_to_occupancy(self._master).ravel().view(Int8Array),
        )
