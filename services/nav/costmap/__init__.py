"""Costmaps for navigation: Nav2's layers and cost values on numpy grids.

API (all map-frame coordinates in metres; cells ``(mx, my)`` = (column, row), row 0 at
the origin, so ``costs[my, mx]``)::

    from zenros.services.nav.costmap import Costmap2D, CostmapParams

    cm = Costmap2D.from_occupancy_grid(grid, CostmapParams(robot_radius=0.22,
                                       inflation_radius=0.7, cost_scaling_factor=3.0))
    # or Costmap2D(occupancy_int8, resolution, (origin_x, origin_y), params)
    cm.costs                        # uint8 (height, width): 0 free .. 252, 253 inscribed,
                                    # 254 lethal, 255 unknown (read-only view)
    cm.world_to_map(x, y)           # (mx, my) or None outside; cm.map_to_world(mx, my)
    cm.update_from_scan(scan, (x, y, yaw))   # LaserScan taken at that sensor pose in map
    cm.set_keepout(polygons=[[(x, y), ...]], walls=[[(x, y), ...]])
    cm.to_occupancy_grid("map", stamp)       # Nav2's published scale (0..100, -1)

Modules: ``values`` (cost constants and the two translation tables), ``geometry``
(world ↔ cell), ``inflation`` (Nav2's decay), ``obstacle`` (scan marking and clearing),
``keepout`` (polygons and walls rasterised), ``costmap`` (the layered Costmap2D),
``snapshot`` (`CostSnapshot`, a copy the planner plans on), ``live`` (`Costmaps`: nav's global
costmap of the current map and the local window). Imports maps (keep-out shapes).
"""

from .costmap import Costmap2D, CostmapParams
from .geometry import Bounds, GridGeometry
from .inflation import Inflation, inflation_cost
from .obstacle import ObstacleParams, Scan
from .values import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    MAX_NON_OBSTACLE,
    NO_INFORMATION,
    cost_to_occupancy,
    occupancy_to_cost,
)

__all__ = [
    "FREE_SPACE",
    "INSCRIBED_INFLATED_OBSTACLE",
    "LETHAL_OBSTACLE",
    "MAX_NON_OBSTACLE",
    "NO_INFORMATION",
    "Bounds",
    "Costmap2D",
    "CostmapParams",
    "GridGeometry",
    "Inflation",
    "ObstacleParams",
    "Scan",
    "cost_to_occupancy",
    "inflation_cost",
    "occupancy_to_cost",
]
