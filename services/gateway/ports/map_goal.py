"""`check_goal_free`: a goal the map already says is inside an obstacle is refused at once.

Nav would take such a goal and fail it at planning (206 GOAL_OCCUPIED), after the REST call
had answered 200 with a started task. The gateway holds the current map (``map``, latched),
so it refuses the goal itself with a 400 saying so, in nav's words. Only the map's own
occupied cells count (nav's static layer: occupancy >= 100 is lethal); a goal near a wall,
behind a virtual wall or in an obstacle the laser sees is nav's to judge.
"""

from __future__ import annotations

from zenros.errors import MapError
from zenros.maps import GridMap
from zenros.msgs.nav_msgs import OccupancyGrid

from ..errors import Refused

__all__ = ["LETHAL", "check_goal_free"]

LETHAL = 100  # occupancy at and above which nav's static layer marks a cell lethal


def check_goal_free(grid: OccupancyGrid | None, x: float, y: float, what: str = "goal") -> None:
    """Raise `Refused` when map point (``x``, ``y``) is inside an obstacle of ``grid``
    (the current map; None, unreadable, or a point outside it: nothing to say here)."""
    if grid is None:
        return
    try:
        m = GridMap.from_msg(grid)
    except MapError:
        return
    row, col = m.world_to_cell(x, y)
    if m.in_bounds(row, col) and int(m.grid[row, col]) >= LETHAL:
        raise Refused(f"{what} ({x:.2f}, {y:.2f}) is inside an obstacle")
